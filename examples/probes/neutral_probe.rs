//! Diagnostic: a neutrally buoyant ball released at rest, fully submerged in a still tank.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let dx: f32 = std::env::var("DX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.02);
    let rho: f32 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000.0);
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 0.004;
    let fixed = std::env::args().nth(2).is_some_and(|s| s == "fixed");
    let shape = std::env::args().nth(3).unwrap_or("ball".into());
    let b = physics.bodies.insert(
        if fixed {
            RigidBodyBuilder::kinematic_velocity_based()
        } else {
            RigidBodyBuilder::dynamic()
        }
        .translation(Vector::new(0.2, 0.14, 0.2)),
    );
    let cb = if shape == "cube" {
        ColliderBuilder::cuboid(0.06, 0.06, 0.06)
    } else {
        ColliderBuilder::ball(0.06)
    };
    physics
        .colliders
        .insert_with_parent(cb.density(rho), b, &mut physics.bodies);
    let vol = if shape == "cube" {
        0.12f32.powi(3)
    } else {
        4.0 / 3.0 * std::f32::consts::PI * 0.06f32.powi(3)
    };
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(0.4, 0.6, 0.4), Slip::NoSlip)
        .unwrap();
    fluid
        .couple_all(
            &physics.bodies,
            &physics.colliders,
            if std::env::var("NOSLIP").is_ok() {
                Slip::NoSlip
            } else {
                Slip::FreeSlip
            },
        )
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, 0.3, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let w = rho * vol * 9.81;
    let bw = 1000.0 * vol * 9.81;
    let steps: usize = std::env::var("STEPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(250);
    for k in 0..steps {
        let r = fluid.step_physics_world(&mut physics).unwrap();
        if k % 25 == 0 || k + 1 == steps {
            let rb = &physics.bodies[b];
            let fy = fluid.solids().last().unwrap().force.y;
            let fl = fluid.fluid();
            let c0 = Vector::new(0.2, 0.14, 0.2);
            let mut hist = [0usize; 8];
            for x in &fl.x {
                let d = (*x - c0).length();
                let k = ((d - 0.05) / 0.005).floor();
                if (0.0..8.0).contains(&k) {
                    hist[k as usize] += 1;
                }
            }
            let sc = fluid.solid_carriers();
            let so = fluid.solids().last().unwrap();
            let rmax = so
                .range
                .clone()
                .map(|i| (sc.x[i] - c0).length())
                .fold(0.0f32, f32::max);
            let rmean_out: f32 = {
                let v: Vec<f32> = so
                    .range
                    .clone()
                    .map(|i| (sc.x[i] - c0).length())
                    .filter(|r| *r > 0.045)
                    .collect();
                v.iter().sum::<f32>() / v.len().max(1) as f32
            };
            let (mut top, mut bot) = (0.0f32, 0.0f32);
            for i in so.range.clone() {
                if sc.x[i].y > c0.y {
                    top += sc.f[i].y
                } else {
                    bot += sc.f[i].y
                }
            }
            let (mut pt, mut nt, mut pb, mut nb, mut ht, mut hb) =
                (0.0f32, 0, 0.0f32, 0, 0.0f32, 0.0f32);
            for k in 0..fl.len() {
                let d = fl.x[k] - c0;
                let r = d.length();
                if r > 0.06 && r < 0.06 + dx && (d.y / r).abs() > 0.85 {
                    let p = fl.p_density[k] + fl.p_velocity[k];
                    let hyd = 1000.0 * 9.81 * (0.3 - fl.x[k].y);
                    if d.y > 0.0 {
                        pt += p;
                        ht += hyd;
                        nt += 1
                    } else {
                        pb += p;
                        hb += hyd;
                        nb += 1
                    }
                }
            }
            println!("   p near top {:.0} (hydrostatic {:.0}, n {nt}), near bottom {:.0} (hydrostatic {:.0}, n {nb})", pt / nt.max(1) as f32, ht / nt.max(1) as f32, pb / nb.max(1) as f32, hb / nb.max(1) as f32);
            println!("   hemispheres: top {top:.2} bottom {bot:.2} (hydrostatic -13.31, 22.19 at the default size)");
            println!("   fluid count by radius (0.05..0.09 step 5mm): {hist:?}; solid outer layer mean r {rmean_out:.4} max {rmax:.4}");
            let mut idx: Vec<usize> = (0..fl.len()).collect();
            idx.sort_by(|a, b| fl.v[*b].length().total_cmp(&fl.v[*a].length()));
            for &i in idx.iter().take(3) {
                let d = fl.x[i] - Vector::new(0.2, 0.14, 0.2);
                println!(
                    "   fast: rel {:?} |rel| {:.4} v {:?} surf {}",
                    d,
                    d.length(),
                    fl.v[i],
                    fl.surface[i]
                );
            }
            println!(
                "t {:.2} y {:.4} vy {:+.4} fluid Fy/ρgV {:.3} (weight/ρgV {:.3}) vmax {:.3}",
                r.time,
                rb.translation().y,
                rb.linvel().y,
                fy / bw,
                w / bw,
                r.max_speed
            );
        }
    }
}
