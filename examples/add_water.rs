//! Minimal coupling: an ordinary rapier world (a fixed floor and two falling boxes) gets a block
//! of water. The fluid pushes the boxes (buoyancy, drag) and they push it back.
//!
//! `cargo run --release --example add_water`
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() -> Result<(), FluidError> {
    // --- an ordinary rapier world
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    physics
        .colliders
        .insert(ColliderBuilder::cuboid(1.0, 0.05, 1.0).translation(Vector::new(0.3, -0.05, 0.15)));
    let light = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.15, 0.45, 0.15)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.05, 0.05).density(400.0),
        light,
        &mut physics.bodies,
    );
    let heavy = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.45, 0.45, 0.15)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::ball(0.05).density(2000.0),
        heavy,
        &mut physics.bodies,
    );

    // --- add water: a tank for the fluid, every collider coupled, a block of water
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: 0.02,
        // rapier's 1/60 s is a long step for the fluid: let the density constraint iterate
        max_density_iterations: 10,
        ..Default::default()
    })?;
    fluid.add_open_tank(Vector::ZERO, Vector::new(0.6, 0.6, 0.3), Slip::NoSlip)?;
    fluid.couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)?;
    fluid.add_block(Vector::ZERO, Vector::new(0.6, 0.2, 0.3), Vector::ZERO)?;

    // --- one call per frame, then rapier's own step (done by step_physics_world)
    for frame in 0..90 {
        let r = fluid.step_physics_world(&mut physics)?;
        if frame % 15 == 0 {
            let (a, b) = (&physics.bodies[light], &physics.bodies[heavy]);
            println!(
                "t {:.2} s  substeps {}  E {:.4}  light box y {:.3} m  heavy ball y {:.3} m",
                r.time,
                r.substeps,
                r.error,
                a.translation().y,
                b.translation().y
            );
        }
    }
    Ok(())
}
