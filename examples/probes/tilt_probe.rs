//! Probe (issue 20's light cubes): a cube of side 4Δx held still (kinematic), fully under
//! water, turned by `ANGLE` degrees about z; prints the fluid's force and torque on it about
//! its centre, averaged over the second half of `SECONDS`, against ρ̄gV and ρ̄gV·Δx.
//! `tilt_probe ANGLE [SECONDS] [DX]` (`PARAMS` overrides parameters as JSON).
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::internals::fill_box;
use staggered_fluid::math::Rotation;
use staggered_fluid::prelude::*;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let angle: f32 = a.get(1).map(|s| s.parse().unwrap()).unwrap_or(0.0);
    let seconds: f32 = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(1.0);
    let dx: f32 = a.get(3).map(|s| s.parse().unwrap()).unwrap_or(0.025);
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut w = FluidWorld::new(params).unwrap();
    let (tx, depth) = (0.4f32, 0.35f32);
    w.add_open_tank(Vector::ZERO, Vector::new(tx, 0.5, tx), Slip::FreeSlip)
        .unwrap();
    let half = 2.0 * dx;
    let shape = SharedShape::cuboid(half, half, half);
    let pose = Pose::from_parts(
        Vector::new(0.5 * tx, 0.15, 0.5 * tx),
        Rotation::from_rotation_z(angle.to_radians()),
    );
    let h = w
        .add_kinematic_solid("cube", shape.clone(), pose, Slip::FreeSlip)
        .unwrap();
    let water: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(tx, depth, tx), dx)
        .into_iter()
        .filter(|p| shape.distance_to_point(&pose, *p, true) > 0.5 * dx)
        .collect();
    w.add_particles(&water, Vector::ZERO).unwrap();
    let dt = 1.0 / 60.0;
    let steps = (seconds / dt).round() as usize;
    let (mut f, mut t, mut n, mut sq) = (Vector::ZERO, Vector::ZERO, 0, 0.0f32);
    for k in 0..steps {
        w.step(Vector::new(0.0, -9.81, 0.0), dt).unwrap();
        if k >= steps / 2 {
            let s = w.solid(h).unwrap();
            f += s.force;
            t += s.torque;
            sq += s.torque.length_squared();
            n += 1;
        }
    }
    let (f, t) = (f / n as f32, t / n as f32);
    let v = (2.0 * half).powi(3);
    let b = 1000.0 * 9.81 * v;
    println!(
        "angle {angle}°: force {:.3} {:.3} {:.3} of ρ̄gV ({b:.2} N); torque {:.4} {:.4} {:.4} N m = {:.3} ρ̄gVΔx about z",
        f.x / b,
        f.y / b,
        f.z / b,
        t.x,
        t.y,
        t.z,
        t.z / (b * dx)
    );
    println!(
        "  frame torques: rms {:.4} N m ({:.3} ρ̄gVΔx)",
        (sq / n as f32).sqrt(),
        (sq / n as f32).sqrt() / (b * dx)
    );
}
