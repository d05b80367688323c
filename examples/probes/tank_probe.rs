//! Diagnostic: the incompressibility test's still tank (0.4 × 0.3 × 0.4 m, Δx 2 cm) at a given
//! step (`DT`, default 1/60 s): per step the substeps, density iterations, mean / largest
//! compression, kinetic energy, level and the far-field dp/dy. `PARAMS` overrides parameters.
use staggered_fluid::metrics::{hydrostatic_fit, waterline};
use staggered_fluid::prelude::*;
use staggered_fluid::scenes;

fn main() {
    let dx = 0.02f32;
    let dt: f32 = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0 / 60.0);
    let secs: f32 = std::env::var("SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.5);
    let every: usize = std::env::var("EVERY")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(6);
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut sc = scenes::hydrostatic(0.4, 0.3, dx, params).unwrap();
    let m = sc.world.particle_mass() as f64;
    for k in 0..(secs / dt).round() as usize {
        let r = sc.world.step(sc.gravity, dt).unwrap();
        if k % every != 0 {
            continue;
        }
        let f = sc.world.fluid();
        let ke: f64 =
            f.v.iter()
                .map(|v| 0.5 * m * v.length_squared() as f64)
                .sum();
        let level = waterline(f.x.iter().copied(), &[], 0.0, dx).unwrap();
        let fit = hydrostatic_fit((0..f.len()).filter_map(|i| {
            let x = f.x[i];
            let inside =
                x.x > 2.0 * dx && x.x < 0.4 - 2.0 * dx && x.z > 2.0 * dx && x.z < 0.4 - 2.0 * dx;
            (inside && x.y > 2.0 * dx && x.y < level - 3.0 * dx && !f.surface[i])
                .then(|| (x.y as f64, (f.p_density[i] + f.p_velocity[i]) as f64))
        }));
        let slope = fit.map_or(f64::NAN, |f| f.gradient / 9810.0);
        println!(
            "t {:.3} sub {} it {} comp {:.4}% max {:.3}% ke {:.2e} J vmax {:.3} level {:.4} dp/dy {:.3}",
            r.time, r.substeps, r.density_iterations, 100.0 * r.compression_mean, 100.0 * r.compression_max, ke, r.max_speed, level, slope
        );
    }
}
