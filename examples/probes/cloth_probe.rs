//! Probe (issue 23's cloth, issue 19's thin solids): a pinned cloth across a tank under a
//! falling column of water; prints per 0.1 s the carriers found under the sheet where it is,
//! its sag and the water's push on it.
//!
//! `cloth_probe N DROP STIFFNESS [SECONDS]`: a column of N³ carriers whose bottom starts DROP
//! spacings over the cloth (the test: 4 2 1). `EVERY=1` prints every frame, `DR=` sets
//! `density_relaxation`.
use staggered_fluid::deform::{DeformableHandle, DeformableParams};
use staggered_fluid::prelude::*;

const DX: f32 = 0.02;
const TANK: f32 = 0.4;
const AT: f32 = 0.3;
const SIDE: f32 = 0.36;

fn through(w: &FluidWorld, h: DeformableHandle) -> usize {
    let pts = w.deformable(h).unwrap().positions();
    let c = 0.5 * TANK;
    w.fluid()
        .x
        .iter()
        .filter(|x| (x.x - c).abs() < 0.5 * SIDE && (x.z - c).abs() < 0.5 * SIDE)
        .filter(|x| {
            let near = pts
                .iter()
                .min_by(|a, b| {
                    let (da, db) = (**a - **x, **b - **x);
                    (da.x * da.x + da.z * da.z).total_cmp(&(db.x * db.x + db.z * db.z))
                })
                .unwrap();
            x.y < near.y - 0.5 * DX
        })
        .count()
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |k: usize, d: f32| a.get(k).map(|s| s.parse().unwrap()).unwrap_or(d);
    let (n, drop, stiffness, seconds) =
        (arg(1, 4.0) as usize, arg(2, 2.0), arg(3, 1.0), arg(4, 1.0));
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        on_failure: staggered_fluid::OnFailure::Warn,
        density_relaxation: std::env::var("DR")
            .map(|v| v.parse().unwrap())
            .unwrap_or(FluidParams::default().density_relaxation),
        ..Default::default()
    })
    .unwrap();
    let c = 0.5 * TANK;
    w.add_open_tank(Vector::ZERO, Vector::new(TANK, 0.7, TANK), Slip::FreeSlip)
        .unwrap();
    let params = DeformableParams {
        density: 1000.0,
        stiffness,
        half_width: 3,
        damping: 0.1,
        ..Default::default()
    };
    let h = w
        .add_cloth(
            "cloth",
            Pose::from_translation(Vector::new(c, AT, c)),
            [SIDE, SIDE],
            params,
        )
        .unwrap();
    let edge = 0.5 * SIDE - 0.5 * DX;
    w.pin_deformable(h, |p| (p.x - c).abs() > edge || (p.z - c).abs() > edge)
        .unwrap();
    let half = 0.5 * n as f32 * DX;
    let lo = Vector::new(c - half, AT + drop * DX, c - half);
    w.add_block(lo, lo + Vector::splat(2.0 * half), Vector::ZERO)
        .unwrap();
    let n0 = w.fluid().len();
    let frames = (seconds * 60.0).round() as usize;
    let mut most = 0;
    let t = std::time::Instant::now();
    for k in 0..frames {
        let r = w.step(Vector::new(0.0, -9.81, 0.0), 1.0 / 60.0).unwrap();
        let th = through(&w, h);
        most = most.max(th);
        if (k + 1) % 6 == 0 || std::env::var("EVERY").is_ok() {
            let low = w
                .deformable(h)
                .unwrap()
                .positions()
                .iter()
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min);
            println!(
                "t {:.3} through {th} sag {:.1} mm push {:.2} N substeps {} pen {} crossings {} warn {:?} n {} vmax {:.2}",
                (k + 1) as f32 / 60.0,
                1e3 * (AT - low),
                w.deformable_force(h).unwrap().y,
                r.substeps,
                r.penetrations_corrected,
                r.cloth_corrections,
                r.warnings, w.fluid().len(), r.max_speed
            );
        }
    }
    println!(
        "most through {most} of {n0}; fluid left {}; wall {:.1} s",
        w.fluid().len(),
        t.elapsed().as_secs_f64()
    );
}
