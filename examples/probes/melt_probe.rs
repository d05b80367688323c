//! Diagnostic: `tests/melting.rs`'s hot case (ice at −2 °C in water at 60 °C, 0.4 m tank,
//! Δx 2 cm) frame by frame at 1/60 s: carriers made by the melt, removed out of the domain,
//! the largest speed and the substeps. `PARAMS='{..}' cargo run --release --example melt_probe`
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::deform::{DeformableParams, Melting};
use staggered_fluid::internals::fill_box;
use staggered_fluid::prelude::*;
use staggered_fluid::{FluidHeat, FluidParams};

fn main() {
    let (dx, half) = (0.02f32, 0.05f32);
    let c = Vector::new(0.2, 0.25 + half - 0.09, 0.2);
    let p = FluidParams {
        spacing: dx,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut w = FluidWorld::new(p).unwrap();
    w.add_open_tank(Vector::ZERO, Vector::splat(0.4), Slip::FreeSlip)
        .unwrap();
    let clear = Vector::splat(half + 0.5 * dx * (1.0 - 1e-3));
    let pts: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.4, 0.25, 0.4), dx)
        .into_iter()
        .filter(|p| ((*p - c).abs() - clear).max_element() >= 0.0)
        .collect();
    w.add_particles(&pts, Vector::ZERO).unwrap();
    w.set_fluid_heat(FluidHeat {
        temperature: 60.0,
        conductivity: 1e-3,
    })
    .unwrap();
    w.add_deformable(
        "ice",
        SharedShape::cuboid(half, half, half),
        Pose::from_translation(c),
        DeformableParams {
            density: 900.0,
            melting: Some(Melting {
                temperature: -2.0,
                melting_point: 0.0,
                conductivity: 2e-3,
                latent_heat: 0.0,
            }),
            ..Default::default()
        },
    )
    .unwrap();
    for k in 0..60 {
        let r = w.step(Vector::new(0.0, -9.81, 0.0), 1.0 / 60.0).unwrap();
        let f = w.fluid();
        let top = f.x.iter().map(|x| x.y).fold(f32::MIN, f32::max);
        let hi = (0..f.len())
            .max_by(|&a, &b| f.p_density[a].total_cmp(&f.p_density[b]))
            .unwrap();
        println!(
            "   highest p^d #{hi} {:.0} Pa at {:.3?} rho {:.1} neighbours {}",
            f.p_density[hi], f.x[hi], f.density[hi], f.neighbors[hi]
        );
        let fast = (0..f.len())
            .max_by(|&a, &b| f.v[a].length().total_cmp(&f.v[b].length()))
            .unwrap();
        println!(
            "   fastest #{fast} of {} at {:.3?} v {:.3?} surface {} neighbours {} rho {:.1} p^d {:.0}",
            f.len(),
            f.x[fast],
            f.v[fast],
            f.surface[fast],
            f.neighbors[fast],
            f.density[fast],
            f.p_density[fast]
        );
        println!(
            "frame {k}: made {} removed {} max speed {:.3} m/s substeps {} top {top:.3} m, density iterations {} drift {} largest compression {:.2} % sealed faces {}",
            r.melt_carriers, r.removed_outside, r.max_speed, r.substeps, r.density_iterations, r.drift_iterations, 100.0 * r.compression_max, r.sealed_faces
        );
    }
}
