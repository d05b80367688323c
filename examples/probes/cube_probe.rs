//! Diagnostic: where a floating cube settles and why. The coupling test's three cubes
//! (rotation locked), rapier at 1/60 s; prints the real far waterline, the volume waterline,
//! each cube's draft against Archimedes, and the pressure of the carriers under it.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::metrics::waterline;
use staggered_fluid::{FluidParams, FluidWorld, Slip};

fn main() {
    let dx: f32 = std::env::var("DX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.02);
    let dt: f32 = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0 / 60.0);
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let side = 8.0 * dx;
    let (w, d, depth) = (7.0 * side, 2.0 * side, 13.0 * dx);
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = dt;
    let dens = [250.0f32, 500.0, 750.0];
    let mut cubes = Vec::new();
    for (k, rho) in dens.iter().enumerate() {
        let y0 = depth + 0.5 * side - rho / 1000.0 * side + 0.02 * side;
        let b = physics.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(side * (1.0 + 2.0 * k as f32), y0, 0.5 * d))
                .locked_axes(LockedAxes::ROTATION_LOCKED),
        );
        physics.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.5 * side, 0.5 * side, 0.5 * side).density(*rho),
            b,
            &mut physics.bodies,
        );
        cubes.push(b);
    }
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: dx,
        ..params
    })
    .unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(w, 2.0 * depth, d), Slip::NoSlip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(w, depth, d),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let n0 = fluid.fluid().len();
    let frames = (std::env::var("SECS")
        .ok()
        .and_then(|s| s.parse::<f32>().ok())
        .unwrap_or(1.5)
        / dt) as usize;
    for k in 0..frames {
        let r = fluid.step_physics_world(&mut physics).unwrap().clone();
        if (k + 1)
            % std::env::var("EVERY")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(frames / 6)
            == 0
        {
            let bottoms: Vec<f32> = cubes
                .iter()
                .map(|b| physics.bodies[*b].translation().y - 0.5 * side)
                .collect();
            let vlevel = (n0 as f32 * dx.powi(3) - side * side * bottoms.iter().sum::<f32>())
                / (w * d - 3.0 * side * side);
            let centres: Vec<_> = cubes
                .iter()
                .map(|b| physics.bodies[*b].translation())
                .collect();
            let level =
                waterline(fluid.fluid().x.iter().copied(), &centres, 0.75 * side, dx).unwrap();
            println!("t {:.2} substeps {} compression {:.3}% max {:.2}% | far level {level:.4} volume level {vlevel:.4}", fluid.time(), r.substeps, 100.0 * r.compression_mean, 100.0 * r.compression_max);
            let fl = fluid.fluid();
            for (c, b) in centres.iter().enumerate() {
                let bot = bottoms[c];
                let want = dens[c] / 1000.0 * side;
                // carriers right under the cube (inner columns), nearest layer
                let mut under: Vec<(f32, f32, f32, f32)> = Vec::new();
                for i in 0..fl.len() {
                    let x = fl.x[i];
                    if (x.x - b.x).abs() < 0.5 * side - dx
                        && (x.z - b.z).abs() < 0.5 * side - dx
                        && x.y < bot
                        && x.y > bot - 1.5 * dx
                    {
                        under.push((bot - x.y, fl.p_density[i], fl.p_velocity[i], fl.density[i]));
                    }
                }
                let nu = under.len().max(1) as f32;
                let gap = under.iter().map(|u| u.0).sum::<f32>() / nu;
                let pd = under.iter().map(|u| u.1).sum::<f32>() / nu;
                let pv = under.iter().map(|u| u.2).sum::<f32>() / nu;
                let rho = under.iter().map(|u| u.3).sum::<f32>() / nu;
                let y_mean = bot - gap;
                println!(
                    "  cube {}: draft {:.2} dx vs {:.2} dx ({:+.1}%), under: {} carriers at {:.2} dx below, p^d {:.0} p^v {:.0} (rho g depth {:.0}), rho {:.1}",
                    dens[c], (level - bot) / dx, want / dx, 100.0 * ((level - bot) - want) / want, under.len(), gap / dx, pd, pv, 1000.0 * 9.81 * (level - y_mean), rho
                );
            }
            // far-field hydrostatics: carriers away from cubes, a few depths
            let mut rows = std::collections::BTreeMap::new();
            for i in 0..fl.len() {
                let x = fl.x[i];
                if centres.iter().all(|c| (x.x - c.x).hypot(x.z - c.z) > side) {
                    let e = rows
                        .entry((x.y / dx).floor() as i32)
                        .or_insert((0.0f64, 0.0f64, 0u32));
                    e.0 += if std::env::var("RHO").is_ok() {
                        fl.density[i] as f64
                    } else {
                        (fl.p_density[i] + fl.p_velocity[i]) as f64
                    };
                    e.1 += x.y as f64;
                    e.2 += 1;
                }
            }
            let line: Vec<String> = rows
                .iter()
                .rev()
                .take(13)
                .map(|(_, e)| {
                    format!(
                        "{:.0}/{:.0}",
                        e.0 / e.2 as f64,
                        9810.0 * (level as f64 - e.1 / e.2 as f64)
                    )
                })
                .collect();
            println!("  far p vs rho g depth: {}", line.join(" "));
        }
    }
}
