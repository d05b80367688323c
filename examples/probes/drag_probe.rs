//! Diagnostic: the vertical force on a submerged kinematic cube (side 0.1 m, `DX` 2.5 cm) held at
//! rest, then moved up at a constant speed, against ρ̄gV. An ideal fluid pushes a body moving
//! at constant velocity with its buoyancy alone (d'Alembert); a real cube's drag at 0.1 m/s is
//! ½ρC_dAv² ≈ 0.05 N. `drag_probe [SPEED]` (m/s, default 0.1; `PARAMS` overrides parameters,
//! `DT` the step, default 1/60 s; `SLIP=no|bl` for a no-slip or boundary-layer cube;
//! `LAYERS=1` prints the water a spacing over and under it; `DIR=x` moves it sideways;
//! `DEPTH` the water's depth, default 0.35 m; `REST` the seconds held at rest, default 0.5).
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let speed: f32 = std::env::args()
        .nth(1)
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(0.1);
    let dt: f32 = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0 / 60.0);
    let dx: f32 = std::env::var("DX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.025);
    let half = 0.05f32;
    // `DEPTH`: the water's depth (m, default 0.35; the cube's centre stays 0.12 m up)
    let depth: f32 = std::env::var("DEPTH")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.35);
    let params = FluidParams {
        spacing: dx,
        ..FluidParams::default().with_env_overrides("PARAMS").unwrap()
    };
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_open_tank(
            Vector::ZERO,
            Vector::new(0.4, depth + 0.45, 0.4),
            Slip::NoSlip,
        )
        .unwrap();
    let c0 = Vector::new(0.2, 0.12, 0.2);
    let shape = SharedShape::cuboid(half, half, half);
    let mut colliders = ColliderSet::new();
    colliders.insert(ColliderBuilder::new(shape.clone()).translation(c0));
    let h = fluid
        .add_kinematic_solid(
            "cube",
            shape,
            Pose::from_translation(c0),
            match std::env::var("SLIP").as_deref() {
                Ok("no") => Slip::NoSlip,
                Ok("bl") => Slip::BoundaryLayer,
                _ => Slip::FreeSlip,
            },
        )
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, depth, 0.4),
            Vector::ZERO,
            &colliders,
        )
        .unwrap();
    // `G=0`: without gravity (no hydrostatic pressure for the drag to take from)
    let g = Vector::new(
        0.0,
        -std::env::var("G")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(9.81f32),
        0.0,
    );
    let weight = 1000.0 * 9.81 * (2.0 * half).powi(3);
    // `REST`: seconds held at rest before moving (default 0.5; the force at rest is
    // averaged over the last half of it), then 0.5 s moving
    let rest_secs: f32 = std::env::var("REST")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.5);
    let frames = (0.5 / dt).round() as usize;
    let held = ((rest_secs / dt).round() as usize).max(2);
    let (mut rest, mut moving, mut n_rest, mut n_moving) = (0.0f64, 0.0f64, 0, 0);
    // `DIR=x`: moved sideways instead (the force along the motion is printed too)
    let dir = if std::env::var("DIR").as_deref() == Ok("x") {
        Vector::X
    } else {
        Vector::Y
    };
    let mut along = 0.0f64;
    for k in 0..held + frames {
        let t = k as f32 * dt;
        let v = if k < held { 0.0 } else { speed };
        let centre = c0 + dir * (speed * (t - held as f32 * dt).max(0.0));
        let y = centre.y;
        fluid
            .set_kinematic(h, Pose::from_translation(centre), dir * v, Vector::ZERO)
            .unwrap();
        let rep = fluid.step(g, dt).unwrap();
        let force = fluid
            .solids()
            .iter()
            .find(|s| s.name == "cube")
            .unwrap()
            .force;
        let f = force.y as f64;
        if k >= held / 2 && k < held {
            rest += f;
            n_rest += 1;
        } else if k >= held + frames / 4 {
            moving += f;
            along += force.dot(dir) as f64;
            n_moving += 1;
        }
        if (k + 1 == held || k + 1 == held + frames) && std::env::var("SIDES").is_ok() {
            // beside the faces across the motion: p^d against the column's ρ̄g·depth and
            // ρ − ρ̄, within 1.5Δx ahead of the leading face and behind the trailing one
            let fl = fluid.fluid();
            let level = fl.x.iter().map(|x| x.y).fold(0.0f32, f32::max) + 0.5 * dx;
            let side = |sign: f32| {
                let (mut dp, mut dr, mut m, mut surf) = (0.0f64, 0.0f64, 0, 0);
                for i in 0..fl.len() {
                    let r = fl.x[i] - centre;
                    let gap = sign * r.dot(dir) - half;
                    let off = r - dir * r.dot(dir);
                    if gap > 0.0 && gap < 1.5 * dx && off.abs().max_element() < half {
                        dp += (fl.p_density[i] + 1000.0 * g.y * (level - fl.x[i].y)) as f64;
                        dr += (fl.density[i] - 1000.0) as f64;
                        m += 1;
                        surf += fl.surface[i] as usize;
                    }
                }
                let n = m;
                let m = m.max(1) as f64;
                (dp / m, dr / m, surf, n)
            };
            let deep: Vec<usize> = (0..fl.len())
                .filter(|&i| fl.surface[i] && level - fl.x[i].y > 3.0 * dx)
                .collect();
            let by_cube = deep
                .iter()
                .filter(|&&i| (fl.x[i] - centre).abs().max_element() < half + 1.5 * dx)
                .count();
            println!(
                "   surface carriers deeper than 3Δx: {} ({by_cube} beside the cube)",
                deep.len()
            );
            if std::env::var("SIDES").as_deref() == Ok("2") {
                for &i in &deep {
                    let r = (fl.x[i] - centre) / dx;
                    println!(
                        "      at {:+.2} {:+.2} {:+.2} Δx from the centre, ρ {:.1}",
                        r.x, r.y, r.z, fl.density[i]
                    );
                }
            }
            let ((ap, ar, asf, an), (bp, br, bsf, bn)) = (side(1.0), side(-1.0));
            println!(
                "   ahead: p^d − ρ̄g·depth {ap:+.1} Pa, ρ − ρ̄ {ar:+.2}, surface {asf}/{an} | behind: {bp:+.1} Pa, {br:+.2}, surface {bsf}/{bn}"
            );
        }
        if k % 5 == 4 && std::env::var("LAYERS").is_ok() {
            // the water a spacing under the bottom and over the top, in the footprint:
            // its distance from the face and its vertical velocity
            let fl = fluid.fluid();
            let layer = |below: bool| {
                let (mut d, mut vy, mut pd, mut m) = (0.0f64, 0.0f64, 0.0f64, 0);
                for i in 0..fl.len() {
                    let p = fl.x[i];
                    let gap = if below {
                        y - half - p.y
                    } else {
                        p.y - y - half
                    };
                    if (p.x - c0.x).abs() < half
                        && (p.z - c0.z).abs() < half
                        && gap > 0.0
                        && gap < 1.5 * dx
                    {
                        d += gap as f64;
                        vy += fl.v[i].y as f64;
                        pd += fl.density[i] as f64;
                        m += 1;
                    }
                }
                let m = m.max(1) as f64;
                (d / m / dx as f64, vy / m, pd / m, m)
            };
            let (bd, bv, bp, bn) = layer(true);
            let (td, tv, tp, tn) = layer(false);
            println!(
                "   under: gap {bd:.3} dx, v_y {bv:+.4}, ρ {bp:.1} ({bn}) | over: gap {td:.3} dx, v_y {tv:+.4}, ρ {tp:.1} ({tn})"
            );
        }
        if k % 5 == 4 {
            println!(
                "t {:.3} centre {y:.4} v {v:.2} force {:.3} ρ̄gV ({} substeps)",
                t + dt,
                f / weight as f64,
                rep.substeps
            );
        }
    }
    let (rest, moving) = (rest / n_rest as f64, moving / n_moving as f64);
    if dir == Vector::X {
        println!(
            "sideways: force along the motion {:.3} N",
            along / n_moving as f64
        );
    }
    println!(
        "at rest {:.3} ρ̄gV, moving at {speed} m/s {:.3} ρ̄gV: drag {:.3} N (a real cube ≈ {:.3} N)",
        rest / weight as f64,
        moving / weight as f64,
        rest - moving,
        0.5 * 1000.0 * 1.05 * 0.01 * speed * speed
    );
}
