//! A scripted (kinematic) solid moving through water: it pushes the fluid, no carrier ends up
//! inside it, and every impulse it gives the fluid is reported back (Eq. 21), so the fluid's
//! momentum balances gravity plus all solid forces to round-off.
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::internals::fill_box;
use staggered_fluid::prelude::*;

#[test]
fn moving_cube_pushes_water_and_momentum_balances() {
    let dx = 0.02;
    let mut w = FluidWorld::new(FluidParams {
        spacing: dx,
        ..Default::default()
    })
    .unwrap();
    w.add_open_tank(Vector::ZERO, Vector::new(0.6, 0.4, 0.2), Slip::FreeSlip)
        .unwrap();
    let shape = SharedShape::cuboid(0.04, 0.04, 0.04);
    let start = Pose::from_translation(Vector::new(0.15, 0.1, 0.1));
    let cube = w
        .add_kinematic_solid("cube", shape.clone(), start, Slip::FreeSlip)
        .unwrap();
    let water: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.6, 0.24, 0.2), dx)
        .into_iter()
        .filter(|p| !shape.contains_point(&start, *p))
        .collect();
    w.add_particles(&water, Vector::ZERO).unwrap();
    let speed = 0.5;
    w.set_kinematic(cube, start, Vector::new(speed, 0.0, 0.0), Vector::ZERO)
        .unwrap();

    let g = Vector::new(0.0, -9.81, 0.0);
    let momentum = |w: &FluidWorld| w.fluid_momentum();
    let dt = 0.002;
    let mut prev = momentum(&w);
    let (mut worst, mut drag) = (0.0f64, 0.0f64);
    let steps = 150;
    for _ in 0..steps {
        w.step(g, dt).unwrap();
        let p = momentum(&w);
        let mass = w.fluid_mass();
        for k in 0..3 {
            let solids: f64 = w.solids().iter().map(|s| s.force[k] as f64).sum();
            let got = (p[k] - prev[k]) / dt as f64;
            worst = worst.max((got - (mass * g[k] as f64 - solids)).abs());
        }
        prev = p;
        let s = w.solid(cube).unwrap();
        drag += s.force.x as f64;
        // no fluid carrier inside the moving cube
        let inside = w
            .fluid()
            .x
            .iter()
            .filter(|x| s.shape.contains_point(&s.pose, **x))
            .count();
        assert_eq!(
            inside,
            0,
            "{inside} carriers inside the cube at t = {}",
            w.time()
        );
    }
    // the cube moved with its velocity
    let x = w.solid(cube).unwrap().pose.translation.x;
    assert!(
        (x - (0.15 + speed * dt * steps as f32)).abs() < 1e-4,
        "cube at {x}"
    );
    let weight = w.fluid_mass() * 9.81;
    assert!(
        worst < 5e-3 * weight,
        "momentum imbalance {worst} N (weight {weight} N)"
    );
    // the water resists (mean force on the cube against the motion) and is pushed along
    let drag = drag / steps as f64;
    assert!(drag < 0.0, "mean fluid force on the cube {drag} N");
    assert!(
        momentum(&w)[0] > 0.0,
        "fluid x-momentum {}",
        momentum(&w)[0]
    );
    println!("mean drag {drag} N");
}

/// A submerged cube (side 4Δx) moved up at a steady 0.1 m/s feels its buoyancy and a drag of
/// about ½ρC_dAv² ≈ 0.05 N (C_d ≈ 1.05), 0.5 % of ρ̄gV; the vertical force while it moves
/// must stay within 5 % of ρ̄gV of the force it feels held at rest (ten times the physical drag,
/// for the lattice's frame-to-frame noise). Measured: 1.06 ρ̄gV at rest, 0.81 moving — a
/// motion drag of 2.4 N, 1.2 N already at 0.02 m/s (`examples/probes/drag_probe.rs`;
/// the water under the body is rarefied and over it compressed by the SPH density each
/// substep although the velocity constraint's divergence is zero: docs/experiments.md,
/// "A moving body's motion drag"). It is what holds a light block on the floor (issue 19).
#[test]
#[ignore = "known failure: a submerged body moving at 0.1 m/s loses 25 % of its buoyancy, see the test's doc"]
fn a_body_moving_steadily_through_water_keeps_its_buoyancy() {
    let (dx, half) = (0.025f32, 0.05f32);
    let mut w = FluidWorld::new(FluidParams {
        spacing: dx,
        ..Default::default()
    })
    .unwrap();
    w.add_open_tank(Vector::ZERO, Vector::new(0.4, 0.8, 0.4), Slip::NoSlip)
        .unwrap();
    let c0 = Vector::new(0.2, 0.12, 0.2);
    let shape = SharedShape::cuboid(half, half, half);
    let start = Pose::from_translation(c0);
    let cube = w
        .add_kinematic_solid("cube", shape.clone(), start, Slip::FreeSlip)
        .unwrap();
    let water: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.4, 0.35, 0.4), dx)
        .into_iter()
        .filter(|p| !shape.contains_point(&start, *p))
        .collect();
    w.add_particles(&water, Vector::ZERO).unwrap();
    let g = Vector::new(0.0, -9.81, 0.0);
    let (dt, speed, frames) = (1.0 / 60.0f32, 0.1f32, 30);
    let buoyancy = 1000.0 * 9.81 * (2.0 * half).powi(3) as f64;
    let (mut rest, mut moving) = (0.0f64, 0.0f64);
    for k in 0..2 * frames {
        let t = (k as f32 - frames as f32).max(0.0) * dt;
        let v = if k < frames { 0.0 } else { speed };
        let pose = Pose::from_translation(c0 + Vector::new(0.0, speed * t, 0.0));
        w.set_kinematic(cube, pose, Vector::new(0.0, v, 0.0), Vector::ZERO)
            .unwrap();
        w.step(g, dt).unwrap();
        let f = w.solid(cube).unwrap().force.y as f64 / buoyancy;
        // the second half of each phase, once the start's transient has passed
        if (frames / 2..frames).contains(&k) {
            rest += f / (frames / 2) as f64;
        } else if k >= frames + frames / 2 {
            moving += f / (frames / 2) as f64;
        }
    }
    println!("vertical force at rest {rest:.3} ρ̄gV, moving up at {speed} m/s {moving:.3} ρ̄gV");
    assert!(
        (moving - rest).abs() < 0.05,
        "at rest {rest:.3} ρ̄gV, moving {moving:.3} ρ̄gV"
    );
}
