//! Probe (issue 19's thin solids): `thin_probe jet THICKNESS SPEED` — a jet onto a fixed plate
//! THICKNESS spacings thick at SPEED m/s (the test: 0.5 6); `thin_probe paddle THICKNESS SPEED`
//! — a kinematic paddle THICKNESS spacings thick, spanning a tank's width and taller than the
//! water, swept along x at SPEED m/s. Prints the most carriers found past or inside the solid.
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::internals::fill_box;
use staggered_fluid::prelude::*;

const DX: f32 = 0.02;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let kind = a.get(1).map(String::as_str).unwrap_or("jet");
    let t: f32 = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.5) * DX;
    let speed: f32 = a.get(3).map(|s| s.parse().unwrap()).unwrap_or(6.0);
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        domain: Some(([-0.6, -0.5, -0.6], [0.6, 0.5, 0.6])),
        max_lost_fraction: 1.0,
        on_failure: staggered_fluid::OnFailure::Warn,
        ..Default::default()
    })
    .unwrap();
    let g = Vector::new(0.0, -9.81, 0.0);
    let (mut past, mut inside, mut corrected) = (0usize, 0usize, 0u64);
    let shape;
    let h;
    if kind == "jet" {
        shape = SharedShape::cuboid(0.5, 0.5 * t, 0.5);
        h = w
            .add_static_solid("plate", shape.clone(), Pose::IDENTITY, Slip::FreeSlip)
            .unwrap();
        w.add_block(
            Vector::new(-0.06, 0.05, -0.06),
            Vector::new(0.06, 0.25, 0.06),
            Vector::new(0.0, -speed, 0.0),
        )
        .unwrap();
    } else {
        // a tank 0.6 × 0.3 × 0.2 m with 0.15 m of water, the paddle at x = 0.15 spanning its
        // width, 0.4 m tall
        w.add_open_tank(Vector::ZERO, Vector::new(0.6, 0.45, 0.2), Slip::FreeSlip)
            .unwrap();
        shape = SharedShape::cuboid(0.5 * t, 0.2, 0.1);
        let start = Pose::from_translation(Vector::new(0.15, 0.2, 0.1));
        h = w
            .add_kinematic_solid("paddle", shape.clone(), start, Slip::FreeSlip)
            .unwrap();
        let water: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.6, 0.15, 0.2), DX)
            .into_iter()
            .filter(|p| (p.x - 0.15).abs() > 0.5 * t + 0.5 * DX)
            .collect();
        w.add_particles(&water, Vector::ZERO).unwrap();
        w.set_kinematic(h, start, Vector::new(speed, 0.0, 0.0), Vector::ZERO)
            .unwrap();
    }
    // which side each carrier starts on (by id)
    let side0: std::collections::HashMap<u32, f32> = w
        .fluid()
        .id
        .iter()
        .zip(&w.fluid().x)
        .map(|(&id, x)| {
            let s = w.solid(h).unwrap();
            let l = s.pose.inverse_transform_point(*x);
            (
                id,
                if kind == "jet" {
                    l.y.signum()
                } else {
                    l.x.signum()
                },
            )
        })
        .collect();
    let dt = if kind == "jet" { 1.0 / 240.0 } else { 0.005 };
    let steps = if kind == "jet" {
        36
    } else {
        (0.3 / speed / dt).ceil() as usize
    };
    let t0 = std::time::Instant::now();
    for k in 0..steps {
        let r = w.step(g, dt).unwrap();
        corrected += r.penetrations_corrected;
        let s = w.solid(h).unwrap();
        let fl = w.fluid();
        let (mut p, mut i) = (0, 0);
        for (id, x) in fl.id.iter().zip(&fl.x) {
            let l = s.pose.inverse_transform_point(*x);
            let (along, across) = if kind == "jet" {
                (l.y, l.x.abs().max(l.z.abs()) < 0.5)
            } else {
                (l.x, l.y.abs() < 0.2 && l.z.abs() < 0.1)
            };
            if !across {
                continue;
            }
            if along.abs() < 0.5 * t {
                i += 1;
            } else if along.signum() != side0[id] {
                p += 1;
            }
        }
        past = past.max(p);
        inside = inside.max(i);
        if std::env::var("EVERY").is_ok() {
            println!(
                "step {k}: past {p} inside {i} substeps {} vmax {:.2} warnings {:?}",
                r.substeps, r.max_speed, r.warnings
            );
        }
    }
    println!(
        "{kind} thickness {:.3} dx speed {speed}: most past {past}, inside {inside}; corrected {corrected}; fluid {}; wall {:.1} s",
        t / DX,
        w.fluid().len(),
        t0.elapsed().as_secs_f64()
    );
}
