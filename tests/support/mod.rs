//! Set-up shared by the tests of one body in a tank of water at rapier's 1/60 s.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

/// A rapier world and a fluid world holding one dynamic body in a tank of water.
pub struct BodyInTank {
    pub physics: PhysicsWorld,
    pub fluid: FluidWorld,
    #[allow(dead_code)]
    pub body: RigidBodyHandle,
}

/// A 0.4 × 0.6 × 0.4 m tank with no-slip walls (also rapier colliders when `rapier_tank`, so
/// rapier bodies rest on its floor), water `depth` deep at spacing `dx` with the default
/// parameters, and one dynamic body with collider `shape` at `at`, coupled under `slip`.
#[allow(dead_code)]
pub fn body_in_tank(
    shape: ColliderBuilder,
    at: Vector,
    slip: Slip,
    depth: f32,
    rapier_tank: bool,
    dx: f32,
) -> BodyInTank {
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    };
    body_in_tank_with(shape, at, slip, depth, rapier_tank, params)
}

/// [`body_in_tank`] with the fluid's parameters given (their spacing included).
#[allow(dead_code)]
pub fn body_in_tank_with(
    shape: ColliderBuilder,
    at: Vector,
    slip: Slip,
    depth: f32,
    rapier_tank: bool,
    params: FluidParams,
) -> BodyInTank {
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let body = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(at));
    physics
        .colliders
        .insert_with_parent(shape, body, &mut physics.bodies);
    let mut fluid = FluidWorld::new(params).unwrap();
    let inner = Vector::new(0.4, 0.6, 0.4);
    if rapier_tank {
        fluid
            .add_rapier_tank(&mut physics.colliders, Vector::ZERO, inner, Slip::NoSlip)
            .unwrap();
    } else {
        fluid
            .add_open_tank(Vector::ZERO, inner, Slip::NoSlip)
            .unwrap();
    }
    fluid
        .couple_all(&physics.bodies, &physics.colliders, slip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, depth, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    BodyInTank {
        physics,
        fluid,
        body,
    }
}
