//! Per-stage timings of the five-ball scene (He 2012 Fig. 15) and the share of the time that
//! goes to the solids: the same run with the balls coupled and with them uncoupled (rapier
//! still moves them; the fluid no longer sees them).
//!
//! `cargo run --release --example five_balls_bench [seconds]`
use staggered_fluid::scenes;
use staggered_fluid::StageTimes;

/// Stage times, wall seconds, fluid carriers, most solid carriers searched, µs per
/// particle-step, density iterations per substep, PCG iterations per substep.
type Outcome = (StageTimes, f64, usize, usize, f64, f64, f64);

fn run(coupled: bool, seconds: f64) -> Outcome {
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
    let (mut solid_active, mut substeps, mut density_it, mut pcg_it) = (0usize, 0u64, 0u64, 0u64);
    let r = sc
        .run(seconds, |_, rep| {
            solid_active = solid_active.max(rep.n_solid);
            substeps += rep.substeps as u64;
            density_it += rep.density_iterations as u64;
            pcg_it += rep.pcg_iterations as u64;
        })
        .unwrap();
    let per_substep = |k: u64| k as f64 / substeps.max(1) as f64;
    (
        r.stage_seconds,
        r.wall_seconds,
        r.n_fluid,
        solid_active,
        r.us_per_particle_step,
        per_substep(density_it),
        per_substep(pcg_it),
    )
}

fn main() {
    let seconds: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    println!(
        "five balls, {seconds} s simulated at 1/240 s, spacing 0.02 m, {} threads",
        rayon::current_num_threads()
    );
    println!("| run | fluid | solid carriers searched | neighbours | p^d | surface | staggered | assembly | solve | other | wall s | µs/particle-step | density it/substep | PCG it/substep |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut walls = Vec::new();
    for coupled in [true, false] {
        let (t, wall, nf, ns, us, dit, pit) = run(coupled, seconds);
        println!(
            "| {} | {nf} | {ns} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {wall:.1} | {us:.2} | {dit:.2} | {pit:.1} |",
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
