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

/// A 2000 kg/m³ plate coupled on a fixed body, under water: let go (`Dynamic`), the fluid
/// moves it from then on and it sinks (its carriers, kept in world coordinates while it was
/// fixed, get their body-frame copy); a ground (a half-space, rapier's 200 m cuboid), sampled
/// only where the fluid reaches, whose body is let go is refused, naming the solid.
#[test]
fn a_fixed_body_let_go_sinks_and_a_ground_let_go_is_refused() {
    let mut physics = rapier3d::pipeline::PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let plate = physics
        .bodies
        .insert(RigidBodyBuilder::fixed().translation(Vector::new(0.2, 0.15, 0.2)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.08, 0.02, 0.08).density(2000.0),
        plate,
        &mut physics.bodies,
    );
    let mut fluid = fluid_world();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(0.4, 0.4, 0.4), Slip::NoSlip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, 0.3, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    fluid.step_physics_world(&mut physics).unwrap();
    assert!(fluid.rigids().is_empty());
    physics.bodies[plate].set_body_type(RigidBodyType::Dynamic, true);
    for _ in 0..10 {
        fluid.step_physics_world(&mut physics).unwrap();
    }
    assert_eq!(
        fluid.rigids().len(),
        1,
        "the plate is not dynamic in the fluid"
    );
    let y = physics.bodies[plate].translation().y;
    assert!(y < 0.15 - 0.005, "the released plate is at {y} m");
    // its carriers moved with it: none further than a spacing from its faces
    let plate_solid = fluid
        .solid_of(physics.bodies[plate].colliders()[0])
        .unwrap();
    let s = fluid.solid(plate_solid).unwrap();
    let pose = *physics.colliders[physics.bodies[plate].colliders()[0]].position();
    for i in s.range.clone() {
        let local = pose.inverse_transform_point(fluid.solid_carriers().x[i]);
        assert!(
            local.x.abs() < 0.08 + 0.0251 && local.y.abs() < 0.02 + 0.0251,
            "carrier {i} at {local} in the plate's frame"
        );
    }

    // grounds on fixed bodies, let go: a half-space and rapier's guide's 200 m cuboid
    for shape in [
        ColliderBuilder::new(rapier3d::parry::shape::SharedShape::halfspace(Vector::Y)),
        ColliderBuilder::cuboid(100.0, 0.1, 100.0).translation(Vector::new(0.0, -0.1, 0.0)),
    ] {
        ground_let_go_is_refused(shape);
    }
}

/// A ground coupled on a fixed body, whose body is then made dynamic: refused, naming it.
fn ground_let_go_is_refused(shape: ColliderBuilder) {
    let mut physics = rapier3d::pipeline::PhysicsWorld::new();
    let ground = physics.bodies.insert(RigidBodyBuilder::fixed());
    physics
        .colliders
        .insert_with_parent(shape, ground, &mut physics.bodies);
    let mut fluid = fluid_world();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block(
            Vector::new(0.0, 0.0, 0.0),
            Vector::new(0.2, 0.2, 0.2),
            Vector::ZERO,
        )
        .unwrap();
    fluid.step_physics_world(&mut physics).unwrap();
    physics.bodies[ground].set_body_type(RigidBodyType::Dynamic, true);
    let err = fluid.step_physics_world(&mut physics).unwrap_err();
    let text = err.to_string();
    assert!(
        matches!(err, FluidError::Coupling(_)) && text.contains("can only be fixed"),
        "{text}"
    );
}

/// A fluid world at Δx 2.5 cm with the default parameters.
fn fluid_world() -> FluidWorld {
    FluidWorld::new(FluidParams {
        spacing: 0.025,
        ..Default::default()
    })
    .unwrap()
}
