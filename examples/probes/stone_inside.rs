//! Diagnostic: fluid carriers inside the stone of He 2012 Fig. 14 made heavy, fast and
//! spinning (a convex hull with a sharp rim), after each step: by the crate's test (the hull's
//! faces) and by parry's `contains_point`, which misjudged points within half a millimetre of
//! the rim (and placed some it called inside 4–10 mm deep).
//!
//! `SPACING=0.03 RHO=8000 VX=2 VY=-6 SPIN=150 SECS=0.3 cargo run --release --example stone_inside`
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
    let mut sc = spec.build().unwrap();
    let (mut parry_says, mut corrected) = (0usize, 0u64);
    let r = sc
        .run(env("SECS", 0.3) as f64, |s, rep| {
            corrected += rep.penetrations_corrected;
            let w = &s.world;
            let dynamic = w.solids().iter().filter(|b| b.kind == SolidKind::Dynamic);
            for b in dynamic {
                let n = w
                    .fluid()
                    .x
                    .iter()
                    .filter(|x| b.shape.contains_point(&b.pose, **x))
                    .count();
                parry_says += (n > 0) as usize;
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
