//! Diagnostic: fluid carriers inside the stone of He 2012 Fig. 14 made heavy, fast and
//! spinning (a convex hull with a sharp rim), after each step: by the crate's test (the hull's
//! faces) and by parry's `contains_point`, which misjudged points within half a millimetre of
//! the rim (and placed some it called inside 4–10 mm deep).
//!
//! `SPACING=0.03 RHO=8000 VX=2 VY=-6 SPIN=150 SECS=0.3 cargo run --release --example stone_inside`
//! (`SHAPE=cuboid`: a box of the stone's extents, also spinning at `SPINZ` about z)
use staggered_fluid::{scenes, FluidParams, Slip, SolidKind};

fn env(k: &str, d: f32) -> f32 {
    std::env::var(k)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

fn main() {
    let params = FluidParams::default();
    let mut spec = scenes::stone_spec(
        env("SPACING", 0.03),
        env("SPIN", 150.0),
        Slip::FreeSlip,
        params,
    );
    let stone = &mut spec.bodies[0];
    stone.linvel = [env("VX", 2.0), env("VY", -6.0), 0.0];
    stone.colliders[0].density = Some(env("RHO", 8000.0));
    if std::env::var("SHAPE").as_deref() == Ok("cuboid") {
        stone.colliders[0].shape = scenes::ShapeSpec::Cuboid {
            half_extents: [0.1, 0.04, 0.06],
        };
        stone.angvel[2] = env("SPINZ", 40.0);
    }
    let mut sc = spec.build().unwrap();
    let (mut parry_says, mut corrected) = (0usize, 0u64);
    let r = sc
        .run(env("SECS", 0.3) as f64, |s, rep| {
            corrected += rep.penetrations_corrected;
            let inside = scenes::carriers_inside_solids(&s.world);
            if inside > 0 {
                let ph = s.physics.as_ref().unwrap();
                let b = &ph.bodies[s.tracked[0].1];
                println!(
                    "t {:.4}: {inside} inside; body at {:?}, v {:?}",
                    rep.time,
                    b.translation(),
                    b.linvel()
                );
            }
            let w = &s.world;
            let dynamic = w.solids().iter().filter(|b| b.kind == SolidKind::Dynamic);
            for b in dynamic {
                let inside: Vec<_> = w
                    .fluid()
                    .x
                    .iter()
                    .filter(|x| b.shape.contains_point(&b.pose, **x))
                    .collect();
                parry_says += !inside.is_empty() as usize;
                if std::env::var("WHERE").is_ok() {
                    for x in inside {
                        println!(
                            "   inside at {:?} (body frame)",
                            b.pose.inverse_transform_point(*x)
                        );
                    }
                }
            }
        })
        .unwrap();
    let inside = r.metric.iter().filter(|m| m.value > 0.0).count();
    println!(
        "{} steps: carriers inside the stone after {inside} steps by its faces, after \
         {parry_says} by parry's contains_point; {} corrected in all",
        r.metric.len(),
        corrected
    );
}
