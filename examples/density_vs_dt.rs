//! Benchmark: how incompressible the water stays against the step length, He 2012's Algorithm 2
//! as printed (3 iterations from p = 0, no tolerance) beside the default density constraint
//! (pressure memory, iterations and substeps to the 0.1 % / 1 % tolerance). For the still tank
//! (0.4 × 0.3 m, Δx 2 cm) and the five balls (Δx 2 cm), each step length run for `SECS`
//! (default 1.5) simulated seconds; the figures are over the last third: the mean and worst
//! compression of the inner carriers, the density iterations and substeps per step, wall
//! seconds per simulated second, the level error (tank) or the two floating balls' drafts
//! against Archimedes (five balls).
//!
//! `cargo run --release --example density_vs_dt` (`ONLY=tank` or `ONLY=balls` for one scene)
use staggered_fluid::metrics::{sphere_draft, waterline};
use staggered_fluid::{scenes, FluidParams};
use std::time::Instant;

struct Row {
    mean: f64,
    worst: f64,
    iterations: f64,
    substeps: f64,
    wall: f64,
    extra: String,
}

fn paper() -> FluidParams {
    FluidParams {
        density_memory: 0.0,
        max_density_iterations: 3,
        density_mean_tolerance: 0.99,
        density_max_tolerance: 0.99,
        surface_extrapolation: false,
        hydrostatic_walls: false,
        ..Default::default()
    }
}

fn run(name: &str, params: FluidParams, dt: f32, secs: f64) -> Row {
    let mut sc = if name == "tank" {
        scenes::hydrostatic(0.4, 0.3, 0.02, params).unwrap()
    } else {
        scenes::five_balls(0.02, params).unwrap()
    };
    sc.dt = dt;
    if let Some(ph) = sc.physics.as_mut() {
        ph.integration_parameters.dt = dt;
    }
    let dx = sc.world.params().spacing;
    let from = secs * 2.0 / 3.0;
    let (mut mean, mut worst, mut it, mut sub, mut n) = (0.0, 0.0f64, 0.0, 0.0, 0.0);
    let mut drafts = vec![Vec::new(); 2];
    let start = Instant::now();
    sc.run(secs, |s, r| {
        if r.time >= from {
            mean += r.compression_mean;
            worst = worst.max(r.compression_mean);
            it += r.density_iterations as f64;
            sub += r.substeps as f64;
            n += 1.0;
            if let Some(ph) = &s.physics {
                let c: Vec<_> = s
                    .tracked
                    .iter()
                    .map(|(_, h)| ph.bodies[*h].translation())
                    .collect();
                if let Some(level) = waterline(s.world.fluid().x.iter().copied(), &c, 0.12, dx) {
                    let floating = s.tracked.iter().zip(&c).filter_map(|((name, _), c)| {
                        let rho: f64 = name.trim_start_matches("ball ").parse().ok()?;
                        (rho < 1000.0).then_some((rho, c.y))
                    });
                    for (k, (rho, y)) in floating.take(2).enumerate() {
                        let got = (level - (y - 0.06)) as f64;
                        let want = sphere_draft(0.06, rho / 1000.0);
                        drafts[k].push(100.0 * (got - want) / want);
                    }
                }
            }
        }
    })
    .unwrap();
    let wall = start.elapsed().as_secs_f64() / secs;
    let extra = if name == "tank" {
        let level = waterline(sc.world.fluid().x.iter().copied(), &[], 0.0, dx).unwrap();
        let want = sc.world.fluid().len() as f32 * dx.powi(3) / 0.16;
        format!("level {:+.1} mm", 1e3 * (level - want))
    } else {
        let m: Vec<f64> = drafts
            .iter()
            .map(|d| d.iter().sum::<f64>() / d.len().max(1) as f64)
            .collect();
        format!("drafts {:+.1} % / {:+.1} %", m[0], m[1])
    };
    Row {
        mean: 100.0 * mean / n,
        worst: 100.0 * worst,
        iterations: it / n,
        substeps: sub / n,
        wall,
        extra,
    }
}

fn main() {
    let secs: f64 = std::env::var("SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.5);
    let only = std::env::var("ONLY").unwrap_or_default();
    println!("| scene | Δt (s) | constraint | compression mean % | worst step % | iterations/step | substeps/step | wall s / sim s | accuracy |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (name, dts) in [
        (
            "tank",
            vec![
                1.0 / 960.0,
                1.0 / 480.0,
                1.0 / 240.0,
                1.0 / 120.0,
                1.0 / 60.0,
                1.0 / 30.0,
            ],
        ),
        (
            "balls",
            vec![1.0 / 480.0, 1.0 / 240.0, 1.0 / 120.0, 1.0 / 60.0],
        ),
    ] {
        if !only.is_empty() && only != name {
            continue;
        }
        for dt in dts {
            for (label, params) in [("paper", paper()), ("default", FluidParams::default())] {
                let r = run(name, params, dt, secs);
                println!(
                    "| {name} | 1/{:.0} | {label} | {:.3} | {:.3} | {:.1} | {:.2} | {:.2} | {} |",
                    1.0 / dt,
                    r.mean,
                    r.worst,
                    r.iterations,
                    r.substeps,
                    r.wall,
                    r.extra
                );
            }
        }
    }
}
