//! Diagnostic: where a free-slip tank's side walls take vertical load. The still tank of
//! `tests/incompressibility.rs` (0.4 × 0.3 × 0.4 m of water, Δx 2 cm, free slip, rapier's
//! 1/60 s) for 1.5 s; over the last 0.5 s, the side walls' carriers' vertical force (the
//! fluid's push on them, `SolidCarriers::f`) summed by height above the floor, and the floor's
//! total, against the water's weight. `PARAMS` overrides parameters.
use staggered_fluid::prelude::*;
use staggered_fluid::scenes;

fn main() {
    let dx = 0.02f32;
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut spec = scenes::hydrostatic_spec(0.4, 0.3, dx, params);
    spec.tanks[0].slip = Slip::FreeSlip;
    let mut sc = spec.build().unwrap();
    let weight = sc.world.fluid_mass() * 9.81;
    let dt = 1.0f32 / 60.0;
    let floor_y = sc
        .world
        .fluid()
        .x
        .iter()
        .map(|x| x.y)
        .fold(f32::MAX, f32::min)
        - 0.5 * dx;
    let mut bins = [0.0f64; 24];
    let (mut floor, mut samples) = (0.0f64, 0);
    for k in 0..90 {
        sc.world.step(sc.gravity, dt).unwrap();
        if k < 60 {
            continue;
        }
        samples += 1;
        let (solids, c) = (sc.world.solids(), sc.world.solid_carriers());
        for s in 0..c.x.len() {
            let name = &solids[c.body[s] as usize].name;
            let fy = c.f[s].y as f64;
            if name.contains("floor") {
                floor += fy;
            } else {
                let b = (((c.x[s].y - floor_y) / dx).floor().max(0.0) as usize).min(23);
                bins[b] += fy;
            }
        }
    }
    let n = samples as f64;
    println!("floor {:.5} W", floor / n / weight);
    let total: f64 = bins.iter().sum::<f64>() / n;
    println!("side walls {:.5} W ({:.3} N)", total / weight, total);
    for (b, f) in bins.iter().enumerate() {
        if f.abs() > 1e-6 {
            println!(
                "  {:.2}-{:.2} m above the floor: {:+.4} N",
                b as f32 * dx,
                (b + 1) as f32 * dx,
                f / n
            );
        }
    }
}
