//! Diagnostic: a light ball pressed by its buoyancy against the underside of a fixed plate
//! (a dock) at the water's surface. `lid_probe [DENSITY] [SECONDS]`. Prints, averaged over
//! the frames after the first half second: the water's force on the ball against Archimedes
//! (ρ̄ g V, the ball wholly under the surface), the plate's contact force in rapier, and the
//! largest compression of the water beside the ball.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rho: f32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(300.0);
    let secs: f32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1.5);
    let (dx, r, depth) = (0.025f32, 0.06f32, 0.3f32);
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let plate = physics.colliders.insert(
        ColliderBuilder::cuboid(0.12, 0.02, 0.2).translation(Vector::new(0.12, depth + 0.02, 0.2)),
    );
    let b = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.12, depth - r, 0.2)));
    let ball = physics.colliders.insert_with_parent(
        ColliderBuilder::ball(r).density(rho),
        b,
        &mut physics.bodies,
    );
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_rapier_tank(
            &mut physics.colliders,
            Vector::ZERO,
            Vector::new(0.4, 0.6, 0.4),
            Slip::NoSlip,
        )
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, depth, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let v = 4.0 / 3.0 * std::f32::consts::PI * r.powi(3);
    let (arch, weight) = (1000.0 * 9.81 * v, rho * 9.81 * v);
    let (mut f, mut c, mut n, mut squeeze) = (0.0f64, 0.0f64, 0, 0.0f32);
    let frames = (secs * 60.0) as usize;
    for k in 0..frames {
        let rep = fluid.step_physics_world(&mut physics).unwrap();
        if (k + 1) as f32 / 60.0 <= 0.5 {
            continue;
        }
        f += fluid.rigids()[0].impulse[1] * 60.0;
        if let Some(pair) = physics.narrow_phase.contact_pair(ball, plate) {
            c += (pair.total_impulse().y * 60.0) as f64;
        }
        n += 1;
        squeeze = squeeze.max(rep.compression_max as f32);
    }
    let (f, c) = (f / n as f64, c / n as f64);
    let y = physics.bodies[b].translation().y;
    // the open water's level (x beyond the plate), and Archimedes against it: the plate's
    // underside a few pascals under water if the level stands above it
    let level = staggered_fluid::metrics::waterline(
        fluid.fluid().x.iter().copied().filter(|x| x.x > 0.28),
        &[],
        0.0,
        dx,
    )
    .unwrap_or(f32::NAN);
    println!(
        "open water's level {:.2} mm above the plate's underside",
        1e3 * (level - depth)
    );
    println!(
        "{rho} kg/m³: water on the ball {f:.3} N = {:.3} ρ̄gV; plate contact {c:.3} N = {:.3} (ρ̄gV − W); \
         ball top {:.1} mm under the plate; largest compression {:.2} %",
        f / arch as f64,
        c.abs() / (arch - weight) as f64,
        1e3 * (depth - y - r),
        100.0 * squeeze
    );
}
