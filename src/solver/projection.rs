//! Velocity constraint (He 2012 Algorithm 3): staggered particles between each carrier pair
//! (Eqs. 7–9), solid-wall conditions on fluid–solid staggered particles (Eqs. 26–27), assembly
//! of the approximate-projection Poisson equation (Eqs. 10–13), and the remap of the projected
//! staggered velocities onto the fluid carriers (Eq. 19).

use super::pcg::PoissonSystem;
use super::staggered::{pair, wall_velocity, Share};
use super::{for_rows, row_blocks, Ctx, ROWS};
use crate::math::Vector;
use crate::params::Remap;
use rapier3d::math::Matrix;
use rayon::prelude::*;

/// Tikhonov weight δ of the `B_i⁻¹` correction, relative to `tr B_i`: bounds the gain in
/// directions with few neighbours.
const B_REGULARISATION: f32 = 0.1;

/// Assembles Eq. 13 for fluid carriers at `x` with predicted velocities `v`, shares `shares`
/// (Eq. 7/9) and surface flags. Row i reads
/// `Σ_j c_ij (p_i − p_j) = −(∇·ṽ)_i/Δt`, `c_ij = V_ij |∇W(r_ij/2)| / (ρ_ij r_ij)`, where
/// the divergence (Eq. 10) uses ṽ_{i−j} on fluid pairs and the wall velocity v^new_{i−j}
/// (Eqs. 26–27) on fluid–solid pairs.
pub(crate) fn assemble(
    ctx: &Ctx,
    x: &[Vector],
    v: &[Vector],
    shares: &[Share],
    surface: &[bool],
    dt: f32,
    sys: &mut PoissonSystem,
) {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    sys.coef.resize(ctx.lists.pair_count(), 0.0);
    sys.diag.resize(nf, 0.0);
    sys.rhs.resize(nf, 0.0);
    sys.unknown.clear();
    sys.unknown.extend(surface.iter().map(|s| !s));
    sys.adjoint = false;
    sys.error_scale = 1.0;
    let blocks = row_blocks(&ctx.lists.offsets, &mut sys.coef);
    blocks
        .into_par_iter()
        .zip(
            sys.diag
                .par_chunks_mut(ROWS)
                .zip(sys.rhs.par_chunks_mut(ROWS)),
        )
        .zip(sys.unknown.par_chunks_mut(ROWS))
        .enumerate()
        .for_each(|(b, ((coef, (diag, rhs)), unknown))| {
            let base = ctx.lists.offsets[b * ROWS] as usize;
            for k in 0..diag.len() {
                let i = b * ROWS + k;
                let slots = ctx.lists.range(i);
                if surface[i] {
                    coef[slots.start - base..slots.end - base].fill(0.0);
                    diag[k] = 1.0;
                    rhs[k] = 0.0;
                    continue;
                }
                let (xi, vi, si) = (x[i], v[i], shares[i]);
                let (mut d, mut div) = (0.0f64, 0.0f64);
                for (slot, &j) in slots.clone().zip(ctx.lists.row(i)) {
                    let j = j as usize;
                    let c = &mut coef[slot - base];
                    *c = 0.0;
                    let (xj, fluid) = if j < nf {
                        (x[j], true)
                    } else {
                        (ctx.solid_x[j - nf], false)
                    };
                    let e = xj - xi;
                    let r = e.length();
                    if r >= h || r <= 1e-9 {
                        continue;
                    }
                    let n = e / r;
                    let gw = ctx.kernel.grad_mag(0.5 * r);
                    if fluid {
                        let st = pair(si, vi, shares[j], v[j]);
                        let cij = st.volume * st.volume * gw / (st.mass * r);
                        *c = cij;
                        d += cij as f64;
                        div += (st.volume * gw * st.velocity.dot(n)) as f64;
                    } else {
                        let s = j - nf;
                        let body = &ctx.bodies[ctx.solid_body[s] as usize];
                        let st = pair(si, vi, body.share, ctx.solid_u[s]);
                        let vn = wall_velocity(
                            body.slip,
                            body.stick,
                            st.velocity,
                            ctx.solid_u[s],
                            ctx.solid_n[s],
                        )
                        .unwrap_or(st.velocity);
                        div += (st.volume * gw * vn.dot(n)) as f64;
                    }
                }
                if d > 0.0 {
                    diag[k] = d;
                    rhs[k] = -div / dt as f64;
                } else {
                    // an inner carrier whose fluid neighbours all left the support: p = 0
                    unknown[k] = false;
                    diag[k] = 1.0;
                    rhs[k] = 0.0;
                }
            }
        });
}

/// Remaps the projected staggered velocities onto the fluid carriers (Eq. 19) and returns the
/// per-body reaction impulses of the wall conditions (Eq. 28, as Newton's third law).
///
/// `p` is p^v (zero on surface carriers). With [`Remap::Conservative`] only the wall part is
/// applied here; the pressure part is the generalized pressure force of p^v
/// ([`crate::solver::density::pressure_accel`]), applied by the caller. With [`Remap::Corrected`] the pressure part is
/// multiplied by `B_i⁻¹`, `B_i = (1/N_i) Σ_fluid n_ij n_ijᵀ` (regularised), so that a uniform
/// pressure gradient is recovered in full rather than about one third of it in 3-D.
#[allow(clippy::too_many_arguments)]
pub(crate) fn remap(
    ctx: &Ctx,
    x: &[Vector],
    v_pred: &[Vector],
    shares: &[Share],
    counts: &[u32],
    p: &[f64],
    dt: f32,
    mode: Remap,
    v_out: &mut [Vector],
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    for_rows(v_out, |i, vo, acc| {
        let (xi, vi, si) = (x[i], v_pred[i], shares[i]);
        let inv_n = 1.0 / counts[i].max(1) as f32;
        let mut dv_p = Vector::ZERO;
        let mut dv_w = Vector::ZERO;
        let mut b = Matrix::ZERO;
        for &j in ctx.lists.row(i) {
            let j = j as usize;
            let (xj, fluid) = if j < nf {
                (x[j], true)
            } else {
                (ctx.solid_x[j - nf], false)
            };
            let e = xj - xi;
            let r = e.length();
            if r >= h || r <= 1e-9 {
                continue;
            }
            let n = e / r;
            if fluid {
                if mode == Remap::Conservative {
                    continue;
                }
                let st = pair(si, vi, shares[j], v_pred[j]);
                // Δv from Gp_{i−j} = (p_j − p_i)/r n (Eq. 11)
                let g = ((p[j] - p[i]) as f32) / (st.density() * r);
                dv_p -= n * (dt * g);
                if mode == Remap::Corrected {
                    b += Matrix::from_cols(n * n.x, n * n.y, n * n.z);
                }
            } else {
                let s = j - nf;
                let bi = ctx.solid_body[s];
                let body = &ctx.bodies[bi as usize];
                let st = pair(si, vi, body.share, ctx.solid_u[s]);
                if let Some(vn) = wall_velocity(
                    body.slip,
                    body.stick,
                    st.velocity,
                    ctx.solid_u[s],
                    ctx.solid_n[s],
                ) {
                    // Gp_{i−j} = ρ_{i−j}/Δt (ṽ_{i−j} − v^new_{i−j}) (Eqs. 26–28)
                    let dvw = (vn - st.velocity) * inv_n;
                    dv_w += dvw;
                    acc.add(s, -dvw * ctx.mass);
                }
            }
        }
        dv_p *= inv_n;
        if mode == Remap::Corrected {
            let bm = b * inv_n;
            let eps = B_REGULARISATION * (bm.x_axis.x + bm.y_axis.y + bm.z_axis.z);
            if eps > 0.0 {
                let reg = bm + Matrix::from_diagonal(Vector::splat(eps));
                // (1 + 3δ)(B + δ tr B I)⁻¹ equals B⁻¹ exactly for an isotropic B
                dv_p = reg.inverse() * dv_p * (1.0 + 3.0 * B_REGULARISATION);
            }
        }
        *vo = vi + dv_p + dv_w;
    })
}
