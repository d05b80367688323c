//! Diagnostic: two slabs of water meeting head-on at ±v (no walls, zero gravity), or one slab
//! hitting a plate (`plate`), with either solver; prints the largest speed per step.
//! `cargo run --release --example pcisph_impact -- [plate|slabs] V CFL` with `PARAMS` overrides.
use staggered_fluid::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let plate = args.get(1).map(|s| s == "plate").unwrap_or(false);
    let v: f32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let cfl: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.4);
    let dx = 0.02f32;
    let p = FluidParams {
        spacing: dx,
        max_cfl: 2.0,
        domain: Some(([-0.5, -0.5, -0.5], [0.8, 0.8, 0.8])),
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut w = FluidWorld::new(p).unwrap();
    if plate {
        w.add_static_box(
            "plate",
            Vector::new(-0.2, -2.0 * dx, -0.2),
            Vector::new(0.5, 0.0, 0.5),
            Slip::FreeSlip,
        )
        .unwrap();
    } else {
        w.add_block(
            Vector::new(0.0, -0.14, 0.0),
            Vector::new(0.3, -0.04, 0.3),
            Vector::new(0.0, v, 0.0),
        )
        .unwrap();
    }
    w.add_block(
        Vector::new(0.0, 0.04, 0.0),
        Vector::new(0.3, 0.14, 0.3),
        Vector::new(0.0, -v, 0.0),
    )
    .unwrap();
    let dt = cfl * dx / v;
    for k in 0..30 {
        let r = w.step(Vector::ZERO, dt).unwrap();
        println!(
            "step {k} substeps {} vmax {:.2} density it {} E {:.4} corrected {}",
            r.substeps, r.max_speed, r.density_iterations, r.error, r.penetrations_corrected
        );
    }
}
