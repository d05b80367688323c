//! Per-stage timings of the five-ball scene (He 2012 Fig. 15) and the share of the time that
//! goes to the solids: the same run with the balls coupled and with them uncoupled (rapier
//! still moves them; the fluid no longer sees them).
//!
//! `cargo run --release --example five_balls_bench [seconds]`
use staggered_fluid::scenes;
use staggered_fluid::StageTimes;

fn run(coupled: bool, seconds: f64) -> (StageTimes, f64, usize, usize, f64) {
    let mut sc = scenes::five_balls(0.02, Default::default()).unwrap();
    if !coupled {
        let handles: Vec<_> = sc
            .world
            .solids()
            .iter()
            .enumerate()
            .filter(|(_, s)| s.collider.is_some())
            .map(|(k, _)| staggered_fluid::SolidHandle(k as u32))
            .collect();
        for h in handles {
            sc.world.uncouple(h).unwrap();
        }
    }
    let mut solid_active = 0usize;
    let r = sc
        .run(seconds, |_, rep| {
            solid_active = solid_active.max(rep.n_solid)
        })
        .unwrap();
    (
        r.stage_seconds,
        r.wall_seconds,
        r.n_fluid,
        solid_active,
        r.us_per_particle_step,
    )
}

fn main() {
    let seconds: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    println!("five balls, {seconds} s simulated at 1/240 s, spacing 0.02 m, 2 threads");
    println!("| run | fluid | solid carriers searched | neighbours | p^d | surface | staggered | assembly | solve | other | wall s | µs/particle-step |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut walls = Vec::new();
    for coupled in [true, false] {
        let (t, wall, nf, ns, us) = run(coupled, seconds);
        println!(
            "| {} | {nf} | {ns} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {wall:.1} | {us:.2} |",
            if coupled { "balls coupled" } else { "balls uncoupled" },
            t.neighbors,
            t.density,
            t.surface,
            t.staggered,
            t.assembly,
            t.solve,
            t.other
        );
        walls.push(wall);
    }
    println!(
        "share of the wall time that goes to the five balls: {:.0} %",
        100.0 * (walls[0] - walls[1]) / walls[0]
    );
}
