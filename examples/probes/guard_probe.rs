//! Diagnostic: the failure guards' quantities on the built-in scenes run with their defaults:
//! the largest energy gain of a step over its scale `KE + M|g|Δx`, the largest speed and the
//! fluid lost, so that the guards' defaults sit well above what healthy runs reach.
//! `cargo run --release --example guard_probe [scene ...]` (default: all built-ins, 1 s each;
//! `SECS` the simulated seconds, `FACTOR` a multiple of each scene's step).
use staggered_fluid::{scenes, FluidParams, OnFailure};

fn main() {
    let secs: f64 = std::env::var("SECS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0);
    let factor: f32 = std::env::var("FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0);
    let names: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<String> = if names.is_empty() {
        scenes::NAMES.iter().map(|s| s.to_string()).collect()
    } else {
        names
    };
    for name in names {
        let params = FluidParams {
            on_failure: OnFailure::Warn,
            ..FluidParams::default()
        };
        let mut sc = match scenes::by_name_with(&name, None, params) {
            Ok(s) => s,
            Err(e) => {
                println!("{name}: {e}");
                continue;
            }
        };
        sc.dt *= factor;
        if let Some(ph) = sc.physics.as_mut() {
            ph.integration_parameters.dt = sc.dt;
        }
        let (mut worst, mut at, mut vmax, mut warned) = (f64::NEG_INFINITY, 0.0, 0.0f32, 0);
        let g = sc.gravity;
        let mut scale = 0.0;
        let r = sc.run_with(secs, |s, rep| {
            let w = &s.world;
            let ke: f64 = w
                .fluid()
                .v
                .iter()
                .map(|v| 0.5 * v.length_squared() as f64)
                .sum::<f64>()
                * w.fluid_mass()
                / w.fluid().len().max(1) as f64;
            let ratio = rep.energy_gain / scale;
            if scale > 0.0 && ratio > worst {
                (worst, at) = (ratio, rep.time);
            }
            scale = ke + w.fluid_mass() * g.length() as f64 * w.params().spacing as f64;
            vmax = vmax.max(rep.max_speed);
            warned += rep.warnings.len();
            Ok(())
        });
        println!(
            "{name}: worst gain {worst:.3} × scale at {at:.3} s, max speed {vmax:.2} m/s, \
             {warned} warnings, removed {} ({})",
            sc.world.removed_total(),
            r.map(|_| "ok".to_string())
                .unwrap_or_else(|e| e.to_string())
        );
    }
}
