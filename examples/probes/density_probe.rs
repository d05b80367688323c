//! Diagnostic: how incompressible a built-in scene stays. Runs `SCENE` (default `hydrostatic`)
//! at step `DT` (default the scene's) for `SECS` seconds and prints, every `EVERY` seconds,
//! the compression of the inner carriers (mean and max, SPH density), the density
//! corrections and PCG iterations per step, E, the largest speed, the water level (top
//! carriers + Δx/2, median over columns) and the scene's metric.
//!
//! `SCENE=hydrostatic DT=0.004166 SECS=2 cargo run --release --example density_probe`
//! (`SPACING` sets the spacing, `PARAMS` overrides parameters as JSON); at the end, the
//! largest kinetic energy of the fluid after 0.3 s
use staggered_fluid::metrics::waterline;
use staggered_fluid::{scenes, FluidParams};

fn env<T: std::str::FromStr>(k: &str) -> Option<T> {
    std::env::var(k).ok().and_then(|s| s.parse().ok())
}

fn main() {
    let name = std::env::var("SCENE").unwrap_or_else(|_| "hydrostatic".into());
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut spec = scenes::spec_by_name(&name, env("SPACING"), params).unwrap();
    if std::env::var("FREESLIP").is_ok() {
        for t in spec.tanks.iter_mut() {
            t.slip = staggered_fluid::Slip::FreeSlip;
            t.floor_slip = None;
        }
    }
    let mut sc = spec.build().unwrap();
    if let Some(dt) = env::<f32>("DT") {
        sc.dt = dt;
        if let Some(ph) = sc.physics.as_mut() {
            ph.integration_parameters.dt = dt;
        }
    }
    let secs: f64 = env("SECS").unwrap_or(2.0);
    let every: f64 = env("EVERY").unwrap_or(0.25);
    let dx = sc.world.params().spacing;
    let n0 = sc.world.fluid().len();
    let mut next = every;
    let (mut corr, mut iters, mut steps, mut worst_mean, mut worst_max) =
        (0u64, 0u64, 0u64, 0.0f64, 0.0f64);
    let (mut dens, mut subs) = (0u64, 0u64);
    println!("dt {:.5} s, {} fluid carriers, dx {dx}", sc.dt, n0);
    println!("t | compression mean % | max % | worst mean % | worst max % | steps off tolerance | PCG it/step | E | max speed | level | metric");
    let (mut ke_worst, mut ke_at) = (0.0f64, 0.0f64);
    let r = sc
        .run(secs, |s, rep| {
            if rep.time > 0.3 {
                let f = s.world.fluid();
                let m = s.world.particle_mass() as f64;
                let ke: f64 = f.v.iter().map(|v| 0.5 * m * v.length_squared() as f64).sum();
                if ke > ke_worst {
                    (ke_worst, ke_at) = (ke, rep.time);
                }
            }
            corr += (!rep.density_converged) as u64;
            dens += rep.density_iterations as u64;
            subs += rep.substeps as u64;
            iters += rep.pcg_iterations as u64;
            steps += 1;
            worst_mean = worst_mean.max(rep.compression_mean);
            worst_max = worst_max.max(rep.compression_max);
            if rep.time + 1e-9 >= next {
                next += every;
                let level = waterline(s.world.fluid().x.iter().copied(), &[], 0.0, dx);
                let m = s.sample();
                let fy: f32 = s.world.solids().iter().map(|b| b.force.y).sum();
                let w = (s.world.fluid_mass() * 9.81) as f32;
                let p = &s.world.fluid().p_velocity;
                let pmax = p.iter().cloned().fold(0.0f32, f32::max);
                let pd = &s.world.fluid().p_density;
                let pdmax = pd.iter().cloned().fold(0.0f32, f32::max);
                if let Some(ph) = &s.physics {
                    let centres: Vec<_> = s.tracked.iter().map(|(_, h)| ph.bodies[*h].center_of_mass()).collect();
                    if let Some(level) = waterline(s.world.fluid().x.iter().copied(), &centres, 0.12, dx) {
                        let mut line = String::new();
                        for ((name, h), c) in s.tracked.iter().zip(&centres) {
                            let rho: f32 = name.trim_start_matches("ball ").parse().unwrap_or(0.0);
                            let rb = &ph.bodies[*h];
                            let _ = rb;
                            if rho > 0.0 && rho < 1000.0 {
                                let want = staggered_fluid::metrics::sphere_draft(0.06, rho as f64 / 1000.0);
                                let got = (level - (c.y - 0.06)) as f64;
                                line += &format!(" {name}: draft {:.1} mm vs {:.1} ({:+.1} %);", got * 1e3, want * 1e3, 100.0 * (got - want) / want);
                            } else {
                                line += &format!(" {name}: y {:.3};", c.y);
                            }
                        }
                        eprintln!("   far level {level:.4}:{line}");
                    }
                }
                eprintln!("   density iterations/step {:.1}, substeps {}", dens as f64 / steps.max(1) as f64, rep.substeps);
                for r in s.world.rigids() {
                    eprintln!("     rigid v {:.3?} w {:.3?} active {} sleeping {}", r.linvel, r.angvel, r.active, r.sleeping);
                }
                eprintln!("   all solids F_y/W {:.3}, max p^v {:.0} Pa, max p^d {:.0} Pa (rho g H {:.0})", fy / w, pmax, pdmax, 1000.0 * 9.81 * 0.3);
                println!(
                    "{:.3} | {:.3} | {:.2} | {:.3} | {:.2} | {:.2} | {:.1} | {:.1e} | {:.3} | {:.4} | {:.4}",
                    rep.time,
                    100.0 * rep.compression_mean,
                    100.0 * rep.compression_max,
                    100.0 * worst_mean,
                    100.0 * worst_max,
                    corr as f64 / steps as f64,
                    iters as f64 / steps as f64,
                    rep.error,
                    rep.max_speed,
                    level.unwrap_or(f32::NAN),
                    m.normalized
                );
                corr = 0;
                dens = 0;
                iters = 0;
                steps = 0;
                worst_mean = 0.0;
                worst_max = 0.0;
            }
        })
        .unwrap();
    println!(
        "{} carriers at the end ({} removed), {:.2} wall s per simulated s, {:.2} substeps a \
         step; largest fluid kinetic energy after 0.3 s {ke_worst:.3e} J at {ke_at:.3} s",
        r.n_fluid,
        r.removed_outside,
        r.wall_per_simulated_second,
        subs as f64 / steps.max(1) as f64
    );
}
