//! Diagnostic (issue 19 item 2): a light block released at rest on the floor of a rapier tank
//! under water. `rest_probe DENSITY SLIP SECONDS [GAP]` (SLIP: free | no | bl; GAP: the
//! block's bottom above the floor, in spacings). Prints the block's height per frame and
//! when its centre has risen half its side.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rho: f32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(800.0);
    let slip = match args.get(2).map(|s| s.as_str()) {
        Some("no") => Slip::NoSlip,
        Some("bl") => Slip::BoundaryLayer,
        _ => Slip::FreeSlip,
    };
    let secs: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1.5);
    let gap: f32 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let dx = 0.025;
    let half = 0.05;
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let y0 = half + gap * dx;
    let b = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, y0, 0.2)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(half, half, half).density(rho),
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
        .couple_all(&physics.bodies, &physics.colliders, slip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, 0.35, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let a = (1.0 - rho / 1000.0) * 9.81 / (rho / 1000.0 + 0.6);
    let t_free = (2.0 * half / a).sqrt();
    println!(
        "fluid {} · frictionless rise of half a side in {t_free:.3} s",
        fluid.fluid().len()
    );
    let mut risen = None;
    for k in 0..(secs * 60.0) as usize {
        let rep = fluid.step_physics_world(&mut physics).unwrap();
        if k < 3 {
            println!(
                "sealed faces {} (over {} substeps)",
                rep.sealed_faces, rep.substeps
            );
        }
        let y = physics.bodies[b].translation().y;
        let t = (k + 1) as f32 / 60.0;
        if risen.is_none() && y - y0 >= half {
            risen = Some(t);
        }
        if k % 6 == 5 || k < 6 {
            println!("t {t:.3} y {y:.4} vy {:.3}", physics.bodies[b].linvel().y);
            // the pressures a spacing over the top and under the bottom, against the
            // water column's (the level taken as the highest carrier + Δx/2)
            let fl = fluid.fluid();
            let level = fl.x.iter().map(|x| x.y).fold(0.0f32, f32::max) + 0.5 * dx;
            let face = |lo: f32, hi: f32| {
                let (mut pd, mut pv, mut hy, mut n) = (0.0f64, 0.0f64, 0.0f64, 0);
                for i in 0..fl.len() {
                    let x = fl.x[i];
                    if (x.x - 0.2).abs() < half && (x.z - 0.2).abs() < half && x.y > lo && x.y < hi
                    {
                        pd += fl.p_density[i] as f64;
                        pv += fl.p_velocity[i] as f64;
                        hy += 1000.0 * 9.81 * (level - x.y) as f64;
                        n += 1;
                    }
                }
                let n = n.max(1) as f64;
                (pd / n, pv / n, hy / n)
            };
            let (td, tv, th) = face(y + half, y + half + dx);
            let (bd, bv, bh) = face(y - half - dx, y - half);
            println!(
                "   top p^d {td:.0} p^v {tv:.0} hydro {th:.0} | bottom p^d {bd:.0} p^v {bv:.0} hydro {bh:.0} | (bottom-top) p^d {:.0} p^v {:.0} hydro {:.0}",
                bd - td, bv - tv, bh - th
            );
        }
    }
    // the carriers under the block
    {
        let fl = fluid.fluid();
        let y = physics.bodies[b].translation().y - half;
        for i in 0..fl.len() {
            let x = fl.x[i];
            if (x.x - 0.2).abs() < half && (x.z - 0.2).abs() < half && x.y < y {
                println!(
                    "under: y {:.4} surface {} rho {:.0} p^d {:.0} p^v {:.0}",
                    x.y, fl.surface[i], fl.density[i], fl.p_density[i], fl.p_velocity[i]
                );
            }
        }
    }
    // the pressures against depth, away from the block
    let fl = fluid.fluid();
    let level = fl.x.iter().map(|x| x.y).fold(0.0f32, f32::max);
    for band in [0.05f32, 0.15, 0.25] {
        let (mut pd, mut pv, mut n) = (0.0f64, 0.0f64, 0);
        for i in 0..fl.len() {
            let x = fl.x[i];
            if (level - x.y - band).abs() < 0.5 * dx && (x.x - 0.2).abs() > 0.12 {
                pd += fl.p_density[i] as f64;
                pv += fl.p_velocity[i] as f64;
                n += 1;
            }
        }
        println!(
            "depth {band}: p^d {:.0} Pa, p^v {:.0} Pa, rho g d {:.0} Pa ({n} carriers)",
            pd / n as f64,
            pv / n as f64,
            1000.0 * 9.81 * band
        );
    }
    match risen {
        Some(t) => println!(
            "risen half a side at {t:.3} s = {:.2} × frictionless",
            t / t_free
        ),
        None => println!("never rose half a side"),
    }
}
