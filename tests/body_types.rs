//! A coupled rapier body whose type changes after coupling: the fluid follows the body's type
//! at each step (a user freezes a body, scripts it, lets it go again), and a change it cannot
//! follow is refused with an error naming the solid.
mod support;

use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

/// A 2000 kg/m³ ball of radius 5 cm held mid-water, then let go. Frozen (rapier's `Fixed`),
/// it is no longer moved by the fluid: the fluid's substeps end at rapier's pose (a dynamic
/// ball would sink 0.7 mm within a 1/60 s frame) and it hands rapier no force; made
/// kinematic, it moves with rapier's velocity; dynamic again, it sinks.
#[test]
fn the_fluid_follows_a_coupled_body_that_is_frozen_scripted_and_let_go() {
    let (r, dx) = (0.05f32, 0.025f32);
    let support::BodyInTank {
        mut physics,
        mut fluid,
        body,
    } = support::body_in_tank(
        ColliderBuilder::ball(r).density(2000.0),
        Vector::new(0.2, 0.15, 0.2),
        Slip::FreeSlip,
        0.3,
        true,
        dx,
    );
    let ch = physics.bodies[body].colliders()[0];
    let solid = fluid.solid_of(ch).unwrap();
    let frame = |fluid: &mut FluidWorld, physics: &mut rapier3d::pipeline::PhysicsWorld| {
        fluid
            .step_with_rapier(
                physics.gravity,
                1.0 / 60.0,
                &mut physics.bodies,
                &physics.colliders,
            )
            .unwrap();
        // where the fluid's substeps left the ball, before rapier's step
        let seen = fluid.solid(solid).unwrap().pose.translation;
        physics.step();
        fluid
            .correct_after_rapier(&mut physics.bodies, &physics.colliders)
            .unwrap();
        seen
    };
    // frozen where it is
    physics.bodies[body].set_body_type(RigidBodyType::Fixed, true);
    let held = physics.bodies[body].translation();
    for _ in 0..10 {
        let seen = frame(&mut fluid, &mut physics);
        assert!(fluid.rigids().is_empty(), "the fluid still moves the ball");
        assert!(
            (seen - held).length() < 1e-6,
            "the fluid moved the frozen ball to {seen} (rapier holds it at {held})"
        );
    }
    // the water still pushes on it: its reported force is about its buoyancy (ρ̄gV ≈ 5.1 N)
    let lift = fluid.solid(solid).unwrap().force.y;
    assert!(
        lift > 3.0 && lift < 7.5,
        "fluid force on the frozen ball {lift} N"
    );
    // scripted: it moves with the velocity rapier gives it, within the fluid's substeps too
    physics.bodies[body].set_body_type(RigidBodyType::KinematicVelocityBased, true);
    physics.bodies[body].set_linvel(Vector::new(0.06, 0.0, 0.0), true);
    let start = physics.bodies[body].translation();
    let seen = frame(&mut fluid, &mut physics);
    assert!(fluid.rigids().is_empty());
    assert!(
        (seen.x - start.x - 0.001).abs() < 1e-5,
        "moved {} m in a frame, 1 mm asked",
        seen.x - start.x
    );
    // let go: heavier than water, it sinks
    physics.bodies[body].set_body_type(RigidBodyType::Dynamic, true);
    let from = physics.bodies[body].translation().y;
    for _ in 0..10 {
        frame(&mut fluid, &mut physics);
    }
    assert_eq!(fluid.rigids().len(), 1, "the ball is dynamic again");
    let sunk = from - physics.bodies[body].translation().y;
    assert!(
        sunk > 0.005,
        "the released ball sank only {sunk} m in 1/6 s"
    );
}

/// A collider coupled on a fixed body keeps no body-frame copy of its carriers: when its body
/// turns dynamic the fluid cannot follow it and says so, naming the solid, instead of leaving
/// the fluid's walls where they were while rapier moves the body.
#[test]
fn a_fixed_body_turned_dynamic_is_refused() {
    let mut physics = rapier3d::pipeline::PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let plate = physics.bodies.insert(RigidBodyBuilder::fixed());
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.1, 0.02, 0.1).translation(Vector::new(0.2, 0.1, 0.2)),
        plate,
        &mut physics.bodies,
    );
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: 0.025,
        ..Default::default()
    })
    .unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(0.4, 0.4, 0.4), Slip::NoSlip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::new(0.0, 0.15, 0.0),
            Vector::new(0.4, 0.3, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    fluid.step_physics_world(&mut physics).unwrap();
    physics.bodies[plate].set_body_type(RigidBodyType::Dynamic, true);
    let err = fluid.step_physics_world(&mut physics).unwrap_err();
    let text = err.to_string();
    assert!(
        matches!(err, FluidError::Coupling(_)) && text.contains("couple the collider again"),
        "{text}"
    );
}
