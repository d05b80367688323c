//! Diagnostic: the vertical force on a fixed ball under water against ρ̄gV, for balls of
//! several radii in spacings, in a still tank scaled with the ball (issue 18: is the excess
//! buoyancy of small bodies a curvature effect?). Prints F_y / ρ̄gV averaged over 0.6–1.0 s.
//! `cargo run --release --example gap_radius` (`PARAMS` overrides parameters; `RADII` a comma
//! list of radii in spacings, default 3,5,8).
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let dx = 0.02f32;
    let radii: Vec<f32> = std::env::var("RADII")
        .unwrap_or_else(|_| "3,5,8".into())
        .split(',')
        .filter_map(|s| s.parse().ok())
        .collect();
    let params = FluidParams {
        spacing: dx,
        ..FluidParams::default().with_env_overrides("PARAMS").unwrap()
    };
    for rs in radii {
        let r = rs * dx;
        let w = 2.0 * r + 12.0 * dx;
        let depth = 2.0 * r + 10.0 * dx;
        let c = Vector::new(0.5 * w, 0.5 * depth - 0.5 * dx, 0.5 * w);
        let mut fluid = FluidWorld::new(params.clone()).unwrap();
        fluid
            .add_open_tank(Vector::ZERO, Vector::new(w, 2.0 * depth, w), Slip::FreeSlip)
            .unwrap();
        let mut colliders = ColliderSet::new();
        colliders.insert(ColliderBuilder::ball(r).translation(c));
        fluid
            .add_static_solid(
                "ball",
                rapier3d::parry::shape::SharedShape::ball(r),
                Pose::from_translation(c),
                Slip::FreeSlip,
            )
            .unwrap();
        fluid
            .add_block_around(
                Vector::ZERO,
                Vector::new(w, depth, w),
                Vector::ZERO,
                &colliders,
            )
            .unwrap();
        let g = Vector::new(0.0, -9.81, 0.0);
        let (mut f, mut n) = (0.0f64, 0);
        let dt = 0.004;
        let mut prof = vec![[(0.0f64, 0.0f64); 3]; 64];
        for k in 0..250 {
            fluid.step(g, dt).unwrap();
            if std::env::var("SERIES").is_ok() && k % 10 == 0 {
                let w = fluid.fluid_mass() * 9.81;
                let tot: f64 = fluid.solids().iter().map(|s| s.force.y as f64).sum();
                let b = fluid
                    .solids()
                    .iter()
                    .find(|s| s.name == "ball")
                    .unwrap()
                    .force
                    .y as f64;
                println!(
                    "  t {:.3}: all solids {:.4} W, ball {:.4} W",
                    fluid.time(),
                    tot / w,
                    b / w
                );
            }
            if k >= 150 {
                let fl = fluid.fluid();
                for (x, (pd, pv)) in fl.x.iter().zip(fl.p_density.iter().zip(&fl.p_velocity)) {
                    let dh = ((x.x - c.x).powi(2) + (x.z - c.z).powi(2)).sqrt();
                    let col = if dh < 0.5 * r {
                        0
                    } else if dh > r + 3.0 * dx {
                        2
                    } else if dh > r && dh < r + 1.0 * dx {
                        1
                    } else {
                        continue;
                    };
                    let layer = (x.y / dx).floor() as usize;
                    if layer < prof.len() {
                        prof[layer][col].0 += *pd as f64 + *pv as f64;
                        prof[layer][col].1 += 1.0;
                    }
                }
                let s = fluid.solids().iter().find(|s| s.name == "ball").unwrap();
                f += s.force.y as f64;
                n += 1;
            }
        }
        let v = 4.0 / 3.0 * std::f64::consts::PI * (r as f64).powi(3);
        let weight = fluid.fluid_mass() * 9.81;
        for s in fluid.solids() {
            println!(
                "  {}: F_y {:.4} N ({:.5} of the fluid's weight)",
                s.name,
                s.force.y,
                s.force.y as f64 / weight
            );
        }
        // the fluid next to the ball: distance of the carriers within 1.5 dx of its surface
        let fl = fluid.fluid();
        let near: Vec<(f32, f32)> =
            fl.x.iter()
                .zip(&fl.density)
                .map(|(x, &d)| ((*x - c).length() - r, d))
                .filter(|&(g, _)| g < 1.0 * dx)
                .collect();
        // control volume: carriers within r + k dx of the centre against the lattice count of
        // the shell between the ball and that sphere (F = (N_full - N) m g at rest)
        for k in [1.0f32, 2.0, 3.0, 4.0] {
            let rc = r + k * dx;
            let cnt = fl.x.iter().filter(|x| (**x - c).length() < rc).count();
            let lat = 4.0 / 3.0 * std::f32::consts::PI * (rc.powi(3) - r.powi(3)) / dx.powi(3);
            println!(
                "  CS r+{k}dx: {cnt} carriers, lattice {lat:.1}, deficit {:.1} (ball V/dx^3 {:.1})",
                lat - cnt as f32,
                4.0 / 3.0 * std::f32::consts::PI * r.powi(3) / dx.powi(3)
            );
        }
        let top = fl.x.iter().map(|x| x.y).fold(f32::MIN, f32::max) + 0.5 * dx;
        println!(
            "  level {top:.4} (top + dx/2); layer: p axis / flank / far, and rho g (level - y)"
        );
        for (l, b) in prof.iter().enumerate() {
            if b[2].1 == 0.0 {
                continue;
            }
            let y = (l as f32 + 0.5) * dx;
            let m = |k: usize| {
                if b[k].1 > 0.0 {
                    b[k].0 / b[k].1
                } else {
                    f64::NAN
                }
            };
            println!(
                "   y {:.3} ({:+.1} dx from c): {:8.1} {:8.1} {:8.1}   hyd {:8.1}",
                y,
                (y - c.y) / dx,
                m(0),
                m(1),
                m(2),
                1000.0 * 9.81 * (top - y) as f64
            );
        }
        let gap = near.iter().map(|n| n.0).sum::<f32>() / near.len() as f32;
        let rho = near.iter().map(|n| n.1).sum::<f32>() / near.len() as f32;
        println!(
            "  {} carriers within dx of the surface: mean distance {:.3} dx, density {rho:.1}",
            near.len(),
            gap / dx
        );
        let b = f / n as f64 / (1000.0 * 9.81 * v);
        println!(
            "radius {rs} dx: F_y / rho g V = {b:.4} (an outer radius r + {:.3} dx would give it)",
            ((b.cbrt() - 1.0) * rs as f64)
        );
    }
}
