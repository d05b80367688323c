//! Diagnostic: the largest stable step (issue 18 item 4). Runs built-in scene `SCENE` with its
//! step, CFL limit and body-force limit all multiplied by each of `MULTS` (default 1,2,4,8)
//! for `SECS` seconds and prints the largest rise of the total energy (fluid KE + PE and the
//! rapier bodies' KE + PE) above its value at 0.1 s, the carriers removed, the substeps and
//! the wall time per simulated second.
//!
//! `SCENE=five_balls MULTS=1,4 cargo run --release --example energy_probe`
use staggered_fluid::{scenes, FluidParams};
use std::time::Instant;

fn energy(s: &scenes::Scene) -> f64 {
    let w = &s.world;
    let m = w.particle_mass() as f64;
    let g = -s.gravity.y as f64;
    let mut e: f64 = w
        .fluid()
        .x
        .iter()
        .zip(&w.fluid().v)
        .map(|(x, v)| m * (0.5 * v.length_squared() as f64 + g * x.y as f64))
        .sum();
    if let Some(ph) = &s.physics {
        for (_, b) in ph.bodies.iter() {
            if b.is_dynamic() {
                e += b.kinetic_energy() as f64 + b.mass() as f64 * g * b.center_of_mass().y as f64;
            }
        }
    }
    e
}

fn main() {
    let name = std::env::var("SCENE").unwrap_or_else(|_| "five_balls".into());
    let secs: f64 = std::env::var("SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2.0);
    let mults: Vec<f32> = std::env::var("MULTS")
        .unwrap_or_else(|_| "1,2,4,8".into())
        .split(',')
        .filter_map(|s| s.parse().ok())
        .collect();
    println!("| scene | step × | Δt s | energy rise above 0.1 s (% of |E₀|… of the drop from start) | removed | substeps/step | wall s/sim s |");
    for k in mults {
        let base = FluidParams::default().with_env_overrides("PARAMS").unwrap();
        let params = FluidParams {
            max_cfl: base.max_cfl * k,
            body_force_limit: base.body_force_limit * k,
            ..base
        };
        let mut sc = scenes::spec_by_name(&name, None, params)
            .unwrap()
            .build()
            .unwrap();
        sc.dt *= k;
        if let Some(ph) = sc.physics.as_mut() {
            ph.integration_parameters.dt = sc.dt;
        }
        let e0 = energy(&sc);
        let (mut ref_e, mut rise, mut sub, mut n) = (None::<f64>, 0.0f64, 0u64, 0u64);
        let start = Instant::now();
        let r = sc.run(secs, |s, rep| {
            sub += rep.substeps as u64;
            n += 1;
            let e = energy(s);
            if std::env::var("TRACE").is_ok() && n % ((std::env::var("TRACE").unwrap().parse::<f64>().unwrap_or(0.25) / s.dt as f64).round() as u64).max(1) == 0 {
                let w = &s.world;
                let m = w.particle_mass() as f64;
                let ke: f64 = w.fluid().v.iter().map(|v| 0.5 * m * v.length_squared() as f64).sum();
                let pe: f64 = w.fluid().x.iter().map(|x| m * 9.81 * x.y as f64).sum();
                let level = staggered_fluid::metrics::waterline(w.fluid().x.iter().copied(), &[], 0.0, w.params().spacing).unwrap_or(0.0);
                let mean_rho: f64 = w.fluid().density.iter().map(|&r| r as f64).sum::<f64>() / w.fluid().len() as f64;
                eprintln!("t {:.2} E {e:.3} fluid KE {ke:.3} PE {pe:.3} bodies {:.3} level {level:.4} mean rho {mean_rho:.2} compression {:.3}% max {:.2}% substeps {} vmax {:.2}",
                    rep.time, e - ke - pe, 100.0 * rep.compression_mean, 100.0 * rep.compression_max, rep.substeps, rep.max_speed);
            }
            if rep.time >= 0.1 {
                if let Some(r0) = ref_e {
                    if std::env::var("SPIKES").is_ok() && e > r0 + 0.01 * e0.abs() {
                        let w = &s.world;
                        let m = w.particle_mass() as f64;
                        let ke: f64 = w.fluid().v.iter().map(|v| 0.5 * m * v.length_squared() as f64).sum();
                        eprintln!("  spike t {:.4}: E {e:.2} (+{:.2}), fluid KE {ke:.2}, vmax {:.2}, compression {:.3}% max {:.2}%, substeps {}, density it {}, removed {}",
                            rep.time, e - r0, rep.max_speed, 100.0 * rep.compression_mean, 100.0 * rep.compression_max, rep.substeps, rep.density_iterations, rep.removed_outside);
                    }
                }
                let r0 = *ref_e.get_or_insert(e);
                rise = rise.max(e - r0);
            }
        });
        let wall = start.elapsed().as_secs_f64() / secs;
        match r {
            Ok(r) => println!(
                "| {name} | {k} | {:.4} | {:+.3} J ({:.2} % of the energy released, E0 {e0:.2} J) | {} | {:.2} | {wall:.2} |",
                sc.dt,
                rise,
                100.0 * rise / (e0 - ref_e.unwrap_or(e0)).abs().max(1e-9),
                r.removed_outside,
                sub as f64 / n.max(1) as f64,
            ),
            Err(e) => println!("| {name} | {k} | {:.4} | failed: {e} | | | |", sc.dt),
        }
    }
}
