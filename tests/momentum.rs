//! Momentum balance between the fluid and the walls: every impulse the fluid receives from a
//! solid is handed to that solid (Eq. 21), so dP/dt = M g + Σ F_wall→fluid to round-off.
use staggered_fluid::prelude::*;

mod support;

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

/// With [`FluidParams::wall_support`] a wall pushes a fluid carrier along the body's normal at
/// that carrier, and the reaction on the body acts on the same line: on a free-slip ball,
/// whose normals all pass through its centre, the water exerts no torque (angular momentum
/// kept pair by pair). Booked at the solid carrier, off that line, the reaction had a torque
/// (3.4e-3 of |F| r here) and a 10 kg/m³ free-slip ball spun up to 9.7 rad/s (3.8 now; 4.0
/// without the option).
/// XSPH is off here: its wall term carries tangential momentum on purpose.
#[test]
fn wall_support_pushes_a_free_slip_ball_through_its_centre() {
    let r = 0.06;
    let params = FluidParams {
        spacing: 0.02,
        wall_support: true,
        xsph: 0.0,
        ..Default::default()
    };
    // a neutrally buoyant ball under water, free to move
    let shape = rapier3d::prelude::ColliderBuilder::ball(r).density(1000.0);
    let at = Vector::new(0.2, 0.15, 0.2);
    let support::BodyInTank {
        mut physics,
        mut fluid,
        ..
    } = support::body_in_tank_with(shape, at, Slip::FreeSlip, 0.25, false, params);
    let (mut worst, mut lift) = (0.0f32, 0.0f32);
    for _ in 0..20 {
        fluid.step_physics_world(&mut physics).unwrap();
        let ball = fluid
            .solids()
            .iter()
            .find(|s| s.rigid.is_some())
            .expect("the ball is coupled");
        lift = ball.force.y;
        worst = worst.max(ball.torque.length() / (ball.force.length() * r));
    }
    let buoyancy = 1000.0 * 9.81 * 4.0 / 3.0 * std::f32::consts::PI * r * r * r;
    println!("largest |torque| / (|force| r) {worst:.2e}; lift {lift:.2} N (ρgV {buoyancy:.2} N)");
    assert!(
        lift > 0.5 * buoyancy,
        "the ball must carry real load: {lift} N"
    );
    // f32 sums of a few hundred pushes
    assert!(worst < 1e-3, "torque {worst} of |F| r");
}
