//! Probe (issue 23's cloth): a cloth hung as a curtain (the sheet vertical, in the x–y plane,
//! pinned along its top edge) across a tank, and a block of water thrown at it along z at
//! `SPEED` m/s (`curtain_probe SPEED [SECONDS]`). Prints per 0.05 s the carriers past the
//! curtain (z beyond the sheet's nearest point by more than Δx/2, within its x–y extent),
//! the crossings put back, the largest speed and the step's warnings.
use staggered_fluid::deform::DeformableParams;
use staggered_fluid::prelude::*;

const DX: f32 = 0.02;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let speed: f32 = a.get(1).map(|s| s.parse().unwrap()).unwrap_or(2.0);
    let seconds: f32 = a.get(2).map(|s| s.parse().unwrap()).unwrap_or(1.0);
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        on_failure: staggered_fluid::OnFailure::Warn,
        ..Default::default()
    })
    .unwrap();
    let (tx, ty, tz) = (0.4f32, 0.6f32, 0.6f32);
    w.add_open_tank(Vector::ZERO, Vector::new(tx, ty, tz), Slip::FreeSlip)
        .unwrap();
    // the sheet's local x–z plane turned to the world's x–y plane (about x by 90°)
    let pose = Pose::from_parts(
        Vector::new(0.5 * tx, 0.3, 0.5 * tz),
        staggered_fluid::math::Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
    );
    let side = 0.36;
    let h = w
        .add_cloth(
            "curtain",
            pose,
            [side, side],
            DeformableParams {
                density: 300.0,
                stiffness: 0.5,
                half_width: 2,
                damping: 0.1,
                ..Default::default()
            },
        )
        .unwrap();
    let top = 0.3 + 0.5 * side - 0.5 * DX;
    // `ALL=1`: pinned along every edge (a membrane wall), with no gravity
    let all = std::env::var("ALL").is_ok();
    let (cx, bottom) = (0.5 * tx, 0.3 - 0.5 * side + 0.5 * DX);
    let pinned = w
        .pin_deformable(h, |p| {
            p.y > top || (all && (p.y < bottom || (p.x - cx).abs() > 0.5 * side - 0.5 * DX))
        })
        .unwrap();
    let g = if all { 0.0 } else { -9.81 };
    let lo = Vector::new(0.5 * tx - 0.06, 0.24, 0.5 * tz - 0.2);
    w.add_block(
        lo,
        lo + Vector::new(0.12, 0.12, 0.1),
        Vector::new(0.0, 0.0, speed),
    )
    .unwrap();
    let n0 = w.fluid().len();
    let mut most = 0;
    let frames = (seconds * 60.0).round() as usize;
    for k in 0..frames {
        let r = w.step(Vector::new(0.0, g, 0.0), 1.0 / 60.0).unwrap();
        let pts = w.deformable(h).unwrap().positions().to_vec();
        let past = w
            .fluid()
            .x
            .iter()
            .filter(|x| (x.x - 0.5 * tx).abs() < 0.5 * side - DX && x.y > 0.3 - 0.5 * side + DX)
            .filter(|x| {
                let near = pts
                    .iter()
                    .min_by(|a, b| {
                        let (da, db) = (**a - **x, **b - **x);
                        (da.x * da.x + da.y * da.y).total_cmp(&(db.x * db.x + db.y * db.y))
                    })
                    .unwrap();
                x.z > near.z + 0.5 * DX
            })
            .count();
        most = most.max(past);
        let b = w.deformable(h).unwrap();
        let (rest, x) = (b.rest_positions(), b.positions());
        let mut stretch = 0.0f32;
        for i in 0..rest.len() {
            for j in i + 1..rest.len() {
                if ((rest[i] - rest[j]).length() - DX).abs() < 1e-4 {
                    stretch = stretch.max((x[i] - x[j]).length());
                }
            }
        }
        if (k + 1) % 3 == 0 {
            println!(
                "  largest distance between grid neighbours {:.1} mm",
                1e3 * stretch
            );
        }
        if (k + 1) % 3 == 0 {
            println!(
                "t {:.3} past {past} put back {} substeps {} vmax {:.2} warn {:?}",
                (k + 1) as f32 / 60.0,
                r.cloth_corrections,
                r.substeps,
                r.max_speed,
                r.warnings
            );
        }
    }
    println!(
        "curtain ({pinned} pinned), water at {speed} m/s: most past {most}; fluid {} of {n0}",
        w.fluid().len()
    );
}
