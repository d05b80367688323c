//! A floating box as a rapier rigid body and as lattice shape matching bodies (issue 23):
//! draft against Archimedes and wall seconds per simulated second, each run in turn.
//!
//! `cargo run --release --example lsm_box [seconds]`; `... lsm_box steps` instead runs the
//! soft box (α = 0.5) a second at frames of 1/60 … 1/4 s: the largest step it takes.
use rapier3d::parry::shape::SharedShape;
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::deform::{DeformableHandle, DeformableParams};
use staggered_fluid::internals::fill_box;
use staggered_fluid::metrics::waterline;
use staggered_fluid::prelude::*;
use std::time::Instant;

const DX: f32 = 0.02;
const HALF: Vector = Vector::new(0.1, 0.05, 0.1);
const RHO: f32 = 500.0;
const G: Vector = Vector::new(0.0, -9.81, 0.0);

/// An open 0.8 × 0.6 m tank with no-slip walls.
fn world() -> FluidWorld {
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: DX,
        ..Default::default()
    })
    .unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(0.8, 0.4, 0.6), Slip::NoSlip)
        .unwrap();
    fluid
}

fn water(fluid: &mut FluidWorld, c: Vector) {
    let clear = HALF + Vector::splat(0.5 * DX * (1.0 - 1e-3));
    let pts: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.8, 0.2, 0.6), DX)
        .into_iter()
        .filter(|p| ((*p - c).abs() - clear).max_element() >= 0.0)
        .collect();
    fluid.add_particles(&pts, Vector::ZERO).unwrap();
}

/// The tank with an LSM box of stiffness α at `start` and water around it.
fn box_in_water(start: Vector, stiffness: f32) -> (FluidWorld, DeformableHandle) {
    let mut fluid = world();
    let h = fluid
        .add_deformable(
            "box",
            SharedShape::cuboid(HALF.x, HALF.y, HALF.z),
            Pose::from_translation(start),
            DeformableParams {
                density: RHO,
                stiffness,
                ..Default::default()
            },
        )
        .unwrap();
    water(&mut fluid, start);
    (fluid, h)
}

fn main() {
    if std::env::args().nth(1).as_deref() == Some("steps") {
        return soft_steps();
    }
    let seconds: f32 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(2.0);
    let frames = (seconds * 60.0).round() as usize;
    let draft = 2.0 * HALF.y * RHO / 1000.0;
    let start = Vector::new(0.4, 0.2 + HALF.y - draft + 0.1 * DX, 0.3);
    println!(
        "{:<22} {:>10} {:>12} {:>14} {:>16}",
        "body", "draft mm", "vs Archim.", "wall s / sim s", "compression %"
    );
    // the rapier rigid box
    {
        let mut physics = PhysicsWorld::new();
        physics.integration_parameters.dt = 1.0 / 60.0;
        let b = physics
            .bodies
            .insert(RigidBodyBuilder::dynamic().translation(start));
        let co = physics.colliders.insert_with_parent(
            ColliderBuilder::cuboid(HALF.x, HALF.y, HALF.z).density(RHO),
            b,
            &mut physics.bodies,
        );
        let mut fluid = world();
        fluid
            .couple_collider(&physics.bodies, &physics.colliders, co, Slip::FreeSlip)
            .unwrap();
        water(&mut fluid, start);
        let t = Instant::now();
        let (mut d, mut squeeze) = (0.0, 0.0f64);
        for _ in 0..frames {
            squeeze += fluid
                .step_physics_world(&mut physics)
                .unwrap()
                .compression_mean;
            let c = physics.bodies[b].translation();
            d = waterline(fluid.fluid().x.iter().copied(), &[c], 0.2, DX).unwrap() - (c.y - HALF.y);
        }
        let wall = t.elapsed().as_secs_f32() / seconds;
        report("rapier rigid", d, draft, wall, squeeze / frames as f64);
    }
    for (name, stiffness) in [("LSM α = 1 (w = 2)", 1.0), ("LSM α = 0.5 (w = 2)", 0.5)] {
        let (mut fluid, h) = box_in_water(start, stiffness);
        let (t, mut squeeze) = (Instant::now(), 0.0f64);
        for _ in 0..frames {
            squeeze += fluid.step(G, 1.0 / 60.0).unwrap().compression_mean;
        }
        let wall = t.elapsed().as_secs_f32() / seconds;
        let b = fluid.deformable(h).unwrap();
        let c = b.center_of_mass();
        let level = waterline(fluid.fluid().x.iter().copied(), &[c], 0.2, DX).unwrap();
        // the lowest IBP layer sits half a spacing above the bottom face
        let low = b.rest_positions().iter().map(|p| p.y).fold(1.0, f32::min);
        let (sum, n) = b
            .rest_positions()
            .iter()
            .zip(b.positions())
            .filter(|(r, _)| (r.y - low).abs() < 0.25 * DX)
            .fold((0.0, 0), |(s, n), (_, p)| (s + p.y, n + 1));
        let d = level - (sum / n as f32 - 0.5 * DX);
        report(name, d, draft, wall, squeeze / frames as f64);
    }
}

/// The soft box (α = 0.5) for a second at each frame length: whether every step returned Ok
/// (no guard tripped), its draft, the cost and the deformable stage's share of it.
fn soft_steps() {
    let draft = 2.0 * HALF.y * RHO / 1000.0;
    let start = Vector::new(0.4, 0.2 + HALF.y - draft + 0.1 * DX, 0.3);
    println!(
        "{:>8} {:>10} {:>10} {:>14} {:>12} {:>10}",
        "frame", "result", "draft mm", "wall s / sim s", "deform. %", "substeps"
    );
    for frame in [60.0f32, 30.0, 15.0, 8.0, 4.0] {
        let (mut fluid, h) = box_in_water(start, 0.5);
        let (t, mut result) = (Instant::now(), "ok".to_string());
        let (mut deform, mut total, mut substeps) = (0.0, 0.0, 0);
        for _ in 0..frame as usize {
            match fluid.step(G, 1.0 / frame) {
                Ok(r) => {
                    deform += r.stages.deformable;
                    total += r.stages.total();
                    substeps += r.substeps;
                }
                Err(e) => {
                    result = format!("failed: {e}");
                    break;
                }
            }
        }
        let wall = t.elapsed().as_secs_f32();
        let b = fluid.deformable(h).unwrap();
        let level = waterline(
            fluid.fluid().x.iter().copied(),
            &[b.center_of_mass()],
            0.2,
            DX,
        );
        let low = b.positions().iter().map(|p| p.y).fold(1.0, f32::min) - 0.5 * DX;
        println!(
            "{:>8} {:>10} {:>10.2} {:>14.2} {:>12.1} {:>10}",
            format!("1/{frame}"),
            &result[..result.len().min(10)],
            level.map_or(f32::NAN, |l| 1e3 * (l - low)),
            wall,
            100.0 * deform / total.max(1e-12),
            substeps
        );
        if result != "ok" {
            println!("  {result}");
        }
    }
}

/// One row: draft, its error, cost, and the mean compression of the inner carriers.
fn report(name: &str, d: f32, draft: f32, wall: f32, compression: f64) {
    println!(
        "{name:<22} {:>10.2} {:>+11.1}% {:>14.2} {:>16.4}",
        1e3 * d,
        100.0 * (d / draft - 1.0),
        wall,
        100.0 * compression
    );
}
