//! Diagnostic: the vertical force on a fixed cube (`SHAPE=ball`: a ball) that pierces the free surface (its bottom
//! `SUB` sides below the water's volume level) against ρ̄g × the submerged volume, and the
//! pressure by depth under its centre, beside a side face and far from it.
//! `cargo run --release --example cube_probe` (`PARAMS` overrides parameters; `SUB` the
//! submerged fraction, default 0.5; `SIDE` the side in spacings, default 8).
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let dx = 0.02f32;
    let env = |k: &str, d: f32| {
        std::env::var(k)
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(d)
    };
    let (sub, side) = (env("SUB", 0.5), env("SIDE", 8.0) * dx);
    let params = FluidParams {
        spacing: dx,
        ..FluidParams::default().with_env_overrides("PARAMS").unwrap()
    };
    let w = side + 16.0 * dx;
    let depth = side + 8.0 * dx;
    let level0 = depth; // before the cube displaces water; the level is re-measured below
    let c = Vector::new(0.5 * w, level0 + (0.5 - sub) * side, 0.5 * w);
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(w, 3.0 * depth, w), Slip::FreeSlip)
        .unwrap();
    let ball = std::env::var("SHAPE").is_ok_and(|s| s == "ball");
    let shape = if ball {
        rapier3d::parry::shape::SharedShape::ball(0.5 * side)
    } else {
        rapier3d::parry::shape::SharedShape::cuboid(0.5 * side, 0.5 * side, 0.5 * side)
    };
    let mut colliders = ColliderSet::new();
    colliders.insert(ColliderBuilder::new(shape.clone()).translation(c));
    if std::env::var("KIND").is_ok_and(|k| k == "kin") {
        fluid
            .add_kinematic_solid("cube", shape, Pose::from_translation(c), Slip::FreeSlip)
            .unwrap();
    } else {
        fluid
            .add_static_solid("cube", shape, Pose::from_translation(c), Slip::FreeSlip)
            .unwrap();
    }
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(w, depth, w),
            Vector::ZERO,
            &colliders,
        )
        .unwrap();
    let g = Vector::new(0.0, -9.81, 0.0);
    let dt = 0.004;
    let mut prof = vec![[(0.0f64, 0.0f64); 3]; 64];
    let (mut f, mut n, mut lv) = (0.0f64, 0, 0.0f64);
    for k in 0..250 {
        fluid.step(g, dt).unwrap();
        if k < 150 {
            continue;
        }
        let fl = fluid.fluid();
        // the water's level away from the cube: top carriers + dx/2 beyond 3 dx from its faces
        let far = |x: &Vector| {
            (x.x - c.x).abs() > 0.5 * side + 3.0 * dx || (x.z - c.z).abs() > 0.5 * side + 3.0 * dx
        };
        let mut tops = std::collections::HashMap::new();
        for x in fl.x.iter().filter(|x| far(x)) {
            let key = ((x.x / dx).floor() as i32, (x.z / dx).floor() as i32);
            let t = tops.entry(key).or_insert(f32::MIN);
            *t = t.max(x.y);
        }
        let level =
            tops.values().map(|&y| y as f64).sum::<f64>() / tops.len() as f64 + 0.5 * dx as f64;
        lv += level;
        let s = fluid.solids().iter().find(|s| s.name == "cube").unwrap();
        f += s.force.y as f64;
        n += 1;
        for (x, (pd, pv)) in fl.x.iter().zip(fl.p_density.iter().zip(&fl.p_velocity)) {
            let (ax, az) = ((x.x - c.x).abs(), (x.z - c.z).abs());
            let col = if ax < 0.25 * side && az < 0.25 * side {
                0
            } else if az < 0.25 * side && ax > 0.5 * side && ax < 0.5 * side + dx {
                1
            } else if far(x) && (ax > 0.5 * side + 5.0 * dx || az > 0.5 * side + 5.0 * dx) {
                2
            } else {
                continue;
            };
            let layer = (x.y / dx).floor() as usize;
            if layer < prof.len() {
                prof[layer][col].0 += *pd as f64 + *pv as f64;
                prof[layer][col].1 += 1.0;
            }
        }
    }
    let level = lv / n as f64;
    let bottom = (c.y - 0.5 * side) as f64;
    let vsub = if ball {
        // spherical cap of height d
        let (r, d) = (0.5 * side as f64, (level - bottom).clamp(0.0, side as f64));
        std::f64::consts::PI * d * d * (3.0 * r - d) / 3.0
    } else {
        (side as f64).powi(2) * (level - bottom)
    };
    let fy = f / n as f64;
    println!(
        "level {level:.4} m, cube bottom {bottom:.4} m: submerged {:.3} side; F_y {fy:.3} N, ρ̄gV_sub {:.3} N: F/ρ̄gV {:.4}",
        (level - bottom) / side as f64,
        1000.0 * 9.81 * vsub,
        fy / (1000.0 * 9.81 * vsub)
    );
    println!("layer: p under centre / beside a face / far, and ρ̄g(level − y)");
    for (l, b) in prof.iter().enumerate() {
        if b[2].1 == 0.0 {
            continue;
        }
        let y = (l as f64 + 0.5) * dx as f64;
        let m = |k: usize| {
            if b[k].1 > 0.0 {
                b[k].0 / b[k].1
            } else {
                f64::NAN
            }
        };
        println!(
            "  y {y:.3} ({:+.1} dx from the bottom): {:8.1} {:8.1} {:8.1}   hyd {:8.1}",
            (y - bottom) / dx as f64,
            m(0),
            m(1),
            m(2),
            1000.0 * 9.81 * (level - y)
        );
    }
}
