//! Velocity–position correction against solids (after Shao et al. 2014 §3.3): a fluid carrier
//! found inside a solid at the end of a step is moved back onto the surface and loses its
//! velocity into the solid; the momentum it loses is handed to that solid, so the correction
//! conserves momentum. It only acts on carriers that actually penetrated.
//!
//! Inside-ness is decided on the solid's exact shape (parry's point projection), not on the
//! sampled carriers: at a convex edge the nearest carrier's plane says "inside" for fluid that is
//! well outside (measured: ≈ 190 false corrections per step around three floating cubes).

use super::{for_rows, Ctx};
use crate::math::{Pose, Vector};
use rapier3d::parry::shape::SharedShape;

/// Corrects fluid carriers at `x` with velocities `v` that lie inside one of the solids next to
/// them (`shapes[b]`: shape and world pose of solid b). Returns the impulses on the solids and
/// the number of carriers corrected.
pub(crate) fn correct_penetration(
    ctx: &Ctx,
    shapes: &[(SharedShape, Pose)],
    x: &mut [Vector],
    v: &mut [Vector],
) -> (super::Impulses, usize) {
    let nf = ctx.n_fluid();
    let mut out: Vec<(Vector, Vector, bool)> = x
        .iter()
        .zip(v.iter())
        .map(|(&a, &b)| (a, b, false))
        .collect();
    // corrected carriers end a hair outside the surface, not on it
    let gap = 0.005 * ctx.kernel.support();
    let imp = for_rows(&mut out, |i, o, acc| {
        // the nearest carrier of each solid next to carrier i (few solids per carrier)
        let mut near: [(u32, u32, f32); 4] = [(u32::MAX, 0, f32::INFINITY); 4];
        for &j in ctx.lists.row(i) {
            let j = j as usize;
            if j < nf {
                continue;
            }
            let s = j - nf;
            let b = ctx.solid_body[s];
            let d2 = (ctx.solid_x[s] - o.0).length_squared();
            if let Some(e) = near.iter_mut().find(|e| e.0 == b || e.0 == u32::MAX) {
                if e.0 == u32::MAX || d2 < e.2 {
                    *e = (b, s as u32, d2);
                }
            }
        }
        // overlapping solids (tank walls) may need more than one push
        let mut last_n: Option<Vector> = None;
        for round in 0..8 {
            let mut moved = false;
            for &(b, s, _) in near.iter().take_while(|e| e.0 != u32::MAX) {
                let (shape, pose) = &shapes[b as usize];
                let local = pose.inverse_transform_point(o.0);
                let pp = shape.project_local_point(local, false);
                let dist = (pp.point - local).length();
                // inside, or on the surface closer than the gap (a carrier exactly on the
                // boundary counts as inside the shape)
                if !pp.is_inside && dist >= gap {
                    continue;
                }
                let n = match (pp.point - local).try_normalize() {
                    Some(d) if pp.is_inside => pose.rotation * d,
                    Some(d) => -(pose.rotation * d),
                    None => ctx.solid_n[s as usize],
                };
                let depth = if pp.is_inside { dist } else { -dist };
                match last_n {
                    // squeezed between two solids (a ball resting on the floor): slide along
                    // the other solid's surface, out of the wedge
                    Some(m) if round >= 2 => {
                        let t = (n - m * n.dot(m)).try_normalize().unwrap_or(n);
                        o.0 += t * ((depth + gap) / t.dot(n).max(0.2));
                    }
                    _ => o.0 = pose.transform_point(pp.point) + n * gap,
                }
                last_n = Some(n);
                o.2 = true;
                moved = true;
                let s = s as usize;
                let u = ctx.solid_u[s];
                let vn = (o.1 - u).dot(n);
                if vn < 0.0 {
                    o.1 -= n * vn;
                    acc.add(s, n * (vn * ctx.mass));
                }
            }
            if !moved {
                break;
            }
        }
    });
    let mut count = 0;
    for (k, (xo, vo, c)) in out.into_iter().enumerate() {
        x[k] = xo;
        v[k] = vo;
        count += c as usize;
    }
    (imp, count)
}
