//! Diagnostic: a light ball released under water at rapier's 1/60 s (issue 20 item 3).
//! `light_probe DENSITY SLIP SECONDS` (SLIP: free | no | bl). `SHAPE=cube` for a cube,
//! `LOCK=1` to hold its translation, `W0=ω` to start it spinning about x, `SETTLE=n` to hold it
//! fixed for `n` frames first, `G=g` for gravity of magnitude g, `DT=s` for rapier's step
//! (1/60 s); `PARAMS` overrides parameters.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;
use staggered_fluid::OnFailure;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let rho: f32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(10.0);
    let slip = match args.get(2).map(|s| s.as_str()) {
        Some("no") => Slip::NoSlip,
        Some("bl") => Slip::BoundaryLayer,
        _ => Slip::FreeSlip,
    };
    let secs: f32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let dx = 0.025;
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0 / 60.0);
    if let Ok(g) = std::env::var("G") {
        physics.gravity = Vector::new(0.0, -g.parse::<f32>().unwrap(), 0.0);
    }
    let b = physics.bodies.insert({
        let mut b = RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.12, 0.2));
        if std::env::var("SETTLE").is_ok() {
            b = b.locked_axes(LockedAxes::TRANSLATION_LOCKED | LockedAxes::ROTATION_LOCKED);
        }
        if std::env::var("LOCK").is_ok() {
            b = b.locked_axes(LockedAxes::TRANSLATION_LOCKED);
        }
        if let Ok(w) = std::env::var("W0") {
            b = b.angvel(Vector::new(w.parse().unwrap(), 0.0, 0.0));
        }
        b
    });
    let shape = if std::env::var("SHAPE").is_ok_and(|s| s == "cube") {
        ColliderBuilder::cuboid(0.05, 0.05, 0.05)
    } else {
        ColliderBuilder::ball(0.05)
    };
    physics
        .colliders
        .insert_with_parent(shape.density(rho), b, &mut physics.bodies);
    let params = FluidParams {
        spacing: dx,
        on_failure: OnFailure::Warn,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(0.4, 0.6, 0.4), Slip::NoSlip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, slip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.4, 0.25, 0.4),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let n = fluid.fluid().len();
    let (mut at, mut late) = (physics.bodies[b].translation(), 0.0f32);
    let frames = (secs / physics.integration_parameters.dt) as usize;
    for k in 0..frames {
        eprintln!("FRAME {k}");
        if std::env::var("SETTLE")
            .ok()
            .and_then(|s| s.parse::<usize>().ok())
            == Some(k)
        {
            physics.bodies[b].set_locked_axes(LockedAxes::empty(), true);
        }
        let rep = fluid.step_physics_world(&mut physics).unwrap();
        let body = &physics.bodies[b];
        let moved = body.translation() - at;
        at = body.translation();
        if k + 30 >= frames {
            late = late.max(moved.length() * 60.0);
        }
        if std::env::var("DBG_NORMALS").is_ok() {
            let sc = fluid.solid_carriers();
            let c = fluid.solids()[sc.body[sc.len() - 1] as usize].com;
            let (mut worst, mut tq) = (0.0f32, Vector::ZERO);
            for k in 0..sc.len() {
                if sc.body[k] == sc.body[sc.len() - 1] {
                    worst = worst.max((sc.x[k] - c).normalize().cross(sc.n[k]).length());
                    tq += (sc.x[k] - c).cross(sc.f[k]);
                }
            }
            eprintln!("normals off radial at most {worst:.4}, torque of carrier forces {tq}, solid torque {}", fluid.solids()[sc.body[sc.len() - 1] as usize].torque);
        }
        println!(
            "{k:4} y {:.4} v {:7.3} w {:7.2} sub {} vmax {:.3} cmax {:.3} pen {} lost {} warn {:?}",
            body.translation().y,
            body.linvel().y,
            body.angvel().length(),
            rep.substeps,
            rep.max_speed,
            rep.compression_max,
            rep.penetrations_corrected,
            n - fluid.fluid().len(),
            rep.warnings.first()
        );
    }
    let centre = physics.bodies[b].translation();
    let level =
        staggered_fluid::metrics::waterline(fluid.fluid().x.iter().copied(), &[centre], 0.1, dx)
            .unwrap();
    println!(
        "bottom {:.1} mm under the waterline, largest frame speed over the last 0.5 s {late:.3} m/s",
        1e3 * (level - (centre.y - 0.05))
    );
}
