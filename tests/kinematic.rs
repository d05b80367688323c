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
