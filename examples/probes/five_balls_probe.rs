//! Diagnostic: the five-ball scene at `FACTOR` × its step (CFL and body-force limits scaled
//! too, as `speed_vs_error` does) for `SECS` seconds; prints every ball's height and vertical
//! speed each step, then the waterline. This showed that the balls at ×2 float (the "thrown
//! out of the water" of earlier sweeps was the waterline estimate, see `speed_vs_error`).
//! `WORST=1` adds, where an inner carrier is over 10 % compressed, where it is.
//! `FACTOR=2 SECS=2 cargo run --release --example five_balls_probe`
use staggered_fluid::scenes;

fn main() {
    let f: f32 = std::env::var("FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2.0);
    let secs: f64 = std::env::var("SECS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0);
    let mut p = staggered_fluid::FluidParams::default()
        .with_env_overrides("PARAMS")
        .unwrap();
    p.max_cfl *= f;
    p.body_force_limit *= f;
    let mut sc = scenes::five_balls(0.02, p).unwrap();
    sc.dt *= f;
    if let Some(ph) = sc.physics.as_mut() {
        ph.integration_parameters.dt = sc.dt;
    }
    let handles: Vec<_> = sc.tracked.iter().map(|t| t.1).collect();
    sc.run(secs, |s, rep| {
        let ph = s.physics.as_ref().unwrap();
        let mut line = format!(
            "t {:.4} sub {} it {} E {:.1e} vmax {:.2} removed {}",
            s.world.time(),
            rep.substeps,
            rep.pcg_iterations,
            rep.error,
            rep.max_speed,
            rep.removed_outside
        );
        for h in &handles {
            let b = &ph.bodies[*h];
            line += &format!(" | {:.3} {:+.2}", b.translation().y, b.linvel().y);
        }
        if std::env::var("WORST").is_ok() {
            // the most compressed inner carrier and the ball nearest to it
            let fl = s.world.fluid();
            let worst = (0..fl.len())
                .filter(|&i| !fl.surface[i])
                .max_by(|&a, &b| fl.density[a].total_cmp(&fl.density[b]));
            if let Some(i) = worst {
                let rest = s.world.params().rest_density;
                if fl.density[i] > 1.1 * rest {
                    let (k, d) = handles
                        .iter()
                        .enumerate()
                        .map(|(k, h)| (k, (ph.bodies[*h].translation() - fl.x[i]).length() - 0.06))
                        .min_by(|a, b| a.1.total_cmp(&b.1))
                        .unwrap();
                    line += &format!(
                        " || worst {:.1} % at {:?}, {:.1} mm from ball {k}'s surface",
                        100.0 * (fl.density[i] / rest - 1.0),
                        fl.x[i],
                        1e3 * d
                    );
                }
            }
        }
        println!("{line}");
    })
    .unwrap();
    let ph = sc.physics.as_ref().unwrap();
    let centres: Vec<_> = handles
        .iter()
        .map(|h| ph.bodies[*h].translation())
        .collect();
    let level = staggered_fluid::metrics::waterline(
        sc.world.fluid().x.iter().copied(),
        &centres,
        0.12,
        0.02,
    );
    println!("waterline {level:?}, ball centres {centres:?}");
}
