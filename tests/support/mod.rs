//! Set-up shared by the tests of one body in a tank of water at rapier's 1/60 s, and an open
//! compound box. Each test binary uses only part of it.
#![allow(dead_code)]
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

/// A rapier world and a fluid world holding one dynamic body in a tank of water.
pub struct BodyInTank {
    pub physics: PhysicsWorld,
    pub fluid: FluidWorld,
    pub body: RigidBodyHandle,
}

/// A 0.4 × 0.6 × 0.4 m tank with no-slip walls (also rapier colliders when `rapier_tank`, so
/// rapier bodies rest on its floor), water `depth` deep at spacing `dx` with the default
/// parameters, and one dynamic body with collider `shape` at `at`, coupled under `slip`.
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

/// An open box as one compound of five cuboids: a floor `wall` thick under walls `wall`
/// thick and `height` tall around the interior `[-inner, inner]²` (x, z) from `y = wall` up.
/// The parts meet at internal faces (the walls stand on the floor, the ±z walls between the
/// ±x walls), the case where a compound's sampled normals can point into another part.
pub fn open_box(inner: f32, wall: f32, height: f32) -> rapier3d::parry::shape::SharedShape {
    use rapier3d::parry::shape::SharedShape;
    let part = |c: Vector, h: Vector| {
        (
            Pose::from_translation(c),
            SharedShape::cuboid(h.x, h.y, h.z),
        )
    };
    let o = inner + wall;
    let y = wall + 0.5 * height;
    SharedShape::compound(vec![
        part(
            Vector::new(0.0, 0.5 * wall, 0.0),
            Vector::new(o, 0.5 * wall, o),
        ),
        part(
            Vector::new(inner + 0.5 * wall, y, 0.0),
            Vector::new(0.5 * wall, 0.5 * height, o),
        ),
        part(
            Vector::new(-inner - 0.5 * wall, y, 0.0),
            Vector::new(0.5 * wall, 0.5 * height, o),
        ),
        part(
            Vector::new(0.0, y, inner + 0.5 * wall),
            Vector::new(inner, 0.5 * height, 0.5 * wall),
        ),
        part(
            Vector::new(0.0, y, -inner - 0.5 * wall),
            Vector::new(inner, 0.5 * height, 0.5 * wall),
        ),
    ])
}

/// Index of the tank's floor among `world`'s solids (the built-in tanks name it "… floor").
pub fn floor_index(world: &FluidWorld) -> usize {
    world
        .solids()
        .iter()
        .position(|s| s.name.contains("floor"))
        .expect("a tank with a floor")
}
