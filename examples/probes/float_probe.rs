//! Diagnostic: cubes of three densities floating in a tank (rapier two-way coupling).
//! `float_probe DX SECONDS DT [lock|fixed|held] [noslip]` (held: dynamic, every axis locked); `SIDE` the cube's side (m), `LIFT` its
//! start above Archimedes' draft (sides), `SHAPE=ball` balls of diameter `SIDE` instead, `SPLIT` prints one body's state through the fluid step,
//! rapier's step and the correction after it for the last frames. At the end: p^d, p^v, ρ and
//! the count of each layer of water under each body's footprint.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dx: f32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(0.02);
    let secs: f32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let dt: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(0.004);
    let lock = args.get(4).map(|s| s == "lock").unwrap_or(false);
    let fixed = args.get(4).map(|s| s == "fixed").unwrap_or(false);
    // dynamic bodies with every axis locked: held still, but coupled as dynamic bodies
    let held = args.get(4).map(|s| s == "held").unwrap_or(false);
    let lift: f32 = std::env::var("LIFT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0.02);
    let side: f32 = std::env::var("SIDE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(8.0 * dx);
    let (w, d, depth) = (7.0 * side, 2.0 * side, (1.625 * side / dx).round() * dx);
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = dt;
    let dens = [250.0f32, 500.0, 750.0];
    let ball = std::env::var("SHAPE").is_ok_and(|s| s == "ball");
    // draft of a ball of diameter `side` at relative density f: the cap holding f of its volume
    let ball_draft = |f: f32| {
        let r = 0.5 * side as f64;
        let (mut lo, mut hi) = (0.0f64, 2.0 * r);
        for _ in 0..60 {
            let m = 0.5 * (lo + hi);
            let v = std::f64::consts::PI * m * m * (3.0 * r - m) / 3.0;
            if v < f as f64 * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) {
                lo = m
            } else {
                hi = m
            }
        }
        (lo / side as f64) as f32
    };
    let expected: Vec<f32> = dens
        .iter()
        .map(|r| {
            if ball {
                ball_draft(r / 1000.0)
            } else {
                r / 1000.0
            }
        })
        .collect();
    let mut handles = Vec::new();
    for (k, rho) in dens.iter().enumerate() {
        let x = side * (1.0 + 2.0 * k as f32);
        let y0 = depth + 0.5 * side - expected[k] * side + lift * side;
        let b = physics.bodies.insert(
            (if fixed {
                RigidBodyBuilder::fixed()
            } else {
                RigidBodyBuilder::dynamic()
            })
            .translation(Vector::new(x, y0, 0.5 * d))
            .locked_axes(if held {
                LockedAxes::ROTATION_LOCKED | LockedAxes::TRANSLATION_LOCKED
            } else if lock {
                LockedAxes::ROTATION_LOCKED
            } else {
                LockedAxes::empty()
            }),
        );
        physics.colliders.insert_with_parent(
            if ball {
                ColliderBuilder::ball(0.5 * side).density(*rho)
            } else {
                ColliderBuilder::cuboid(0.5 * side, 0.5 * side, 0.5 * side).density(*rho)
            },
            b,
            &mut physics.bodies,
        );
        handles.push((b, y0));
    }
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(w, 2.0 * depth, d), Slip::NoSlip)
        .unwrap();
    let slip = if args.get(5).map(|s| s == "noslip").unwrap_or(false) {
        Slip::NoSlip
    } else {
        Slip::FreeSlip
    };
    fluid
        .couple_all(&physics.bodies, &physics.colliders, slip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(w, depth, d),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    println!(
        "fluid {} solid {}",
        fluid.fluid().len(),
        fluid.solid_carriers().len()
    );
    let steps = (secs / dt) as usize;
    let t0 = std::time::Instant::now();
    for k in 0..steps {
        let r = if std::env::var("SPLIT").is_ok() && k + 6 >= steps {
            let b0 = handles[0].0;
            let (y0, v0) = (
                physics.bodies[b0].translation().y,
                physics.bodies[b0].linvel().y,
            );
            let g = physics.gravity;
            fluid
                .step_with_rapier(g, dt, &mut physics.bodies, &physics.colliders)
                .unwrap();
            let ri = fluid.rigids().iter().position(|r| r.handle == b0).unwrap();
            let j = fluid.rigids()[ri].impulse[1];
            let (ya, va) = (
                physics.bodies[b0].translation().y,
                physics.bodies[b0].linvel().y,
            );
            physics.step();
            let (yb, vb) = (
                physics.bodies[b0].translation().y,
                physics.bodies[b0].linvel().y,
            );
            fluid
                .correct_after_rapier(&mut physics.bodies, &physics.colliders)
                .unwrap();
            let (yc, vc) = (
                physics.bodies[b0].translation().y,
                physics.bodies[b0].linvel().y,
            );
            let m = physics.bodies[b0].mass();
            println!(
                "frame {k}: y {y0:.5} v {v0:+.4} | J {j:.4} (mg dt {:.4}) after fluid y {ya:.5} v {va:+.4} | after rapier y {yb:.5} v {vb:+.4} | after correction y {yc:.5} v {vc:+.4}",
                m * 9.81 * dt
            );
            fluid.last_report().clone()
        } else {
            fluid.step_physics_world(&mut physics).unwrap()
        };
        if k < 3 || k % 25 == 0 || k + 1 == steps {
            let mut line = format!(
                "t {:.3} sub {} E {:.4} it {} pen {} vmax {:.3} |",
                r.time,
                r.substeps,
                r.error,
                r.pcg_iterations,
                r.penetrations_corrected,
                r.max_speed
            );
            // level implied by the fluid volume (incompressible, every cube straddling it)
            let bottoms: f32 = handles
                .iter()
                .map(|(b, _)| physics.bodies[*b].translation().y - 0.5 * side)
                .sum();
            let vl = (fluid.fluid().len() as f32 * dx.powi(3) - side * side * bottoms)
                / (w * d - 3.0 * side * side);
            line += &format!(
                " vol-level {:.4} carrier-level {:.4} |",
                vl,
                level(&fluid, &physics, side)
            );
            for (i, (b, _)) in handles.iter().enumerate() {
                let bot = physics.bodies[*b].translation().y - 0.5 * side;
                line += &format!(" vsub {:.3}", (vl - bot) / side);
                let rb = &physics.bodies[*b];
                let bottom = rb.translation().y - 0.5 * side;
                // water level: mean top of surface carriers away from bodies
                let sub = (level(&fluid, &physics, side) - bottom) / side;
                let co = physics.bodies[*b].colliders()[0];
                let fy = fluid.solid(fluid.solid_of(co).unwrap()).unwrap().force.y;
                let lv = level(&fluid, &physics, side);
                let expect = if ball {
                    // spherical cap of height d
                    let (r, d) = (0.5 * side, (lv - bottom).clamp(0.0, side));
                    1000.0 * 9.81 * std::f32::consts::PI * d * d * (3.0 * r - d) / 3.0
                } else {
                    1000.0 * 9.81 * side * side * (lv - bottom)
                };
                line += &format!(" F/ρgV {:.3}", fy / expect);
                line += &format!(
                    " ρ{} sub {:.3} (exp {:.3}) vy {:+.3} w {:.2}",
                    dens[i],
                    sub,
                    expected[i],
                    rb.linvel().y,
                    rb.angvel().length()
                );
            }
            println!("{line}");
            let fl = fluid.fluid();
            let mut close = [0usize; 4];
            for x in &fl.x {
                for (_, c) in physics.colliders.iter() {
                    let pp = c.shape().project_point(c.position(), *x, false);
                    let d = (pp.point - *x).length() * if pp.is_inside { -1.0 } else { 1.0 };
                    if d < 0.0 {
                        close[0] += 1
                    } else if d < 0.25 * dx {
                        close[1] += 1
                    } else if d < 0.5 * dx {
                        close[2] += 1
                    } else if d < 0.75 * dx {
                        close[3] += 1
                    }
                }
            }
            let vy: f32 = fl.v.iter().map(|v| v.y).sum::<f32>() / fl.len() as f32;
            let ymin = fl.x.iter().map(|x| x.y).fold(f32::INFINITY, f32::min);
            println!(
                "   mean vy {vy:.4} ymin {ymin:.4} floor {:?} nsolid {} pairs {} unknown {}",
                fluid.solids()[0].force,
                r.n_solid,
                r.n_pairs,
                r.n_unknown
            );
            println!(
                "   inside {} <.25dx {} <.5dx {} <.75dx {}",
                close[0], close[1], close[2], close[3]
            );
            let fl = fluid.fluid();
            let (i, v) =
                fl.v.iter()
                    .enumerate()
                    .max_by(|a, b| a.1.length().total_cmp(&b.1.length()))
                    .unwrap();
            println!(
                "   fastest at {:?} v {:?} surface {}",
                fl.x[i], v, fl.surface[i]
            );
        }
    }
    println!("wall {:.1}s", t0.elapsed().as_secs_f64());
    {
        let fl = fluid.fluid();
        let lv = level(&fluid, &physics, side);
        for (i, (b, _)) in handles.iter().enumerate() {
            let c = physics.bodies[*b].translation();
            let bottom = c.y - 0.5 * side;
            let mut acc = [(0.0f64, 0.0f64, 0.0f64, 0usize); 6];
            for k in 0..fl.len() {
                let x = fl.x[k];
                if (x.x - c.x).abs() > 0.5 * side - dx || (x.z - c.z).abs() > 0.5 * side - dx {
                    continue;
                }
                let below = (bottom - x.y) / dx;
                if !(0.0..6.0).contains(&below) {
                    continue;
                }
                let l = below as usize;
                acc[l].0 += fl.p_density[k] as f64;
                acc[l].1 += fl.p_velocity[k] as f64;
                acc[l].2 += fl.density[k] as f64;
                acc[l].3 += 1;
            }
            println!(
                "cube {i} (rho {}): layers under the footprint (p^d, p^v, rho, hyd):",
                dens[i]
            );
            for (l, a) in acc.iter().enumerate() {
                let n = a.3.max(1) as f64;
                let y = bottom - (l as f32 + 0.5) * dx;
                println!(
                    "  {l}: n {} p^d {:.0} p^v {:.0} rho {:.1} hyd {:.0}",
                    a.3,
                    a.0 / n,
                    a.1 / n,
                    a.2 / n,
                    1000.0 * 9.81 * (lv - y)
                );
            }
        }
    }
}

fn level(f: &FluidWorld, p: &PhysicsWorld, side: f32) -> f32 {
    let fl = f.fluid();
    let mut ys: Vec<f32> = Vec::new();
    for (x, s) in fl.x.iter().zip(&fl.surface) {
        if !*s {
            continue;
        }
        let far = p.colliders.iter().all(|(_, c)| {
            let q = c.position().translation;
            ((x.x - q.x).powi(2) + (x.z - q.z).powi(2)).sqrt() > side
        });
        if far && x.y > 0.5 * side {
            ys.push(x.y);
        }
    }
    ys.iter().sum::<f32>() / ys.len().max(1) as f32 + 0.5 * f.params().spacing
}
