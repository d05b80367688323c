//! Momentum balance between the fluid and the walls: every impulse the fluid receives from a
//! solid is handed to that solid (Eq. 21), so dP/dt = M g + Σ F_wall→fluid to round-off.
use staggered_fluid::prelude::*;

#[test]
fn fluid_momentum_change_equals_gravity_plus_wall_forces() {
    balance(FluidParams::default());
}

/// The PCISPH solver's boundary forces and Shao's velocity–position correction hand every
/// impulse they give the fluid to the walls.
#[test]
fn pcisph_keeps_the_momentum_balance() {
    balance(FluidParams {
        solver: Solver::Pcisph,
        ..Default::default()
    });
}

/// XSPH smoothing (symmetric pair weights) must not create or destroy momentum.
#[test]
fn xsph_smoothing_keeps_the_momentum_balance() {
    balance(FluidParams {
        xsph: 0.1,
        ..Default::default()
    });
}

fn balance(params: FluidParams) {
    let mut w = FluidWorld::new(FluidParams {
        spacing: 0.02,
        ..params
    })
    .unwrap();
    w.add_open_tank(Vector::ZERO, Vector::new(0.4, 0.4, 0.2), Slip::NoSlip)
        .unwrap();
    w.add_block(
        Vector::ZERO,
        Vector::new(0.16, 0.3, 0.2),
        Vector::new(0.3, 0.0, 0.0),
    )
    .unwrap();
    let g = Vector::new(0.0, -9.81, 0.0);
    let momentum = |w: &FluidWorld| w.fluid_momentum();
    let dt = 0.002;
    let mut prev = momentum(&w);
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for _ in 0..60 {
        w.step(g, dt).unwrap();
        let p = momentum(&w);
        let mass = w.fluid_mass();
        for k in 0..3 {
            let wall: f64 = w.solids().iter().map(|s| s.force[k] as f64).sum();
            let expected = mass * g[k] as f64 - wall;
            let got = (p[k] - prev[k]) / dt as f64;
            worst = worst.max((got - expected).abs());
            scale = scale.max(wall.abs());
        }
        prev = p;
    }
    let weight = w.fluid_mass() * 9.81;
    assert!(
        scale > 0.2 * weight,
        "walls must carry real load ({scale} N)"
    );
    // f32 velocities: allow 0.5 % of the weight
    assert!(
        worst < 5e-3 * weight,
        "momentum imbalance {worst} N (weight {weight} N)"
    );
}
