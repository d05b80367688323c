//! Velocity–position correction against solids (after Shao et al. 2014 §3.3): a fluid carrier
//! found inside a solid at the end of a step is moved back onto the surface and loses its
//! velocity into the solid; the momentum it loses is handed to that solid, so the correction
//! conserves momentum. It only acts on carriers that actually penetrated.

use super::{for_rows, Ctx};
use crate::math::Vector;

/// Corrects fluid carriers at `x` with velocities `v` that lie inside a solid, judged against the
/// surface plane of the nearest solid carrier (`(x − x_s)·n_s + φ_s < 0`). Returns the per-body
/// impulses and the number of carriers corrected.
pub(crate) fn correct_penetration(
    ctx: &Ctx,
    x: &mut [Vector],
    v: &mut [Vector],
) -> (Vec<[f64; 6]>, usize) {
    let nf = ctx.n_fluid();
    let mut out: Vec<(Vector, Vector, bool)> = x
        .iter()
        .zip(v.iter())
        .map(|(&a, &b)| (a, b, false))
        .collect();
    // corrected carriers end a hair outside the surface, not on it
    let gap = 0.005 * ctx.kernel.support();
    let imp = for_rows(&mut out, ctx.bodies.len(), |i, o, acc| {
        // up to three planes: at an edge or corner the nearest carrier changes after a push
        for _ in 0..3 {
            let xi = o.0;
            let mut best: Option<(f32, usize)> = None;
            for &j in ctx.lists.row(i) {
                let j = j as usize;
                if j < nf {
                    continue;
                }
                let s = j - nf;
                let d2 = (ctx.solid_x[s] - xi).length_squared();
                if best.is_none_or(|(b, _)| d2 < b) {
                    best = Some((d2, s));
                }
            }
            let Some((_, s)) = best else { return };
            let n = ctx.solid_n[s];
            let depth = (xi - ctx.solid_x[s]).dot(n) + ctx.solid_phi[s];
            if depth >= gap || (depth >= 0.0 && !o.2) {
                return;
            }
            o.0 = xi + n * (gap - depth);
            o.2 = true;
            let u = ctx.solid_u[s];
            let vn = (o.1 - u).dot(n);
            if vn < 0.0 {
                o.1 -= n * vn;
                let b = ctx.solid_body[s];
                acc.add(
                    &ctx.bodies[b as usize],
                    b,
                    ctx.solid_x[s],
                    n * (vn * ctx.mass),
                );
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
