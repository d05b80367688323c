//! Velocity constraint with a consistent projection: the staggered divergence of He 2012
//! Eq. 10 (taken relative to the carrier, so a uniform motion has none) and, as the pressure
//! force, its exact adjoint.
//!
//! For a fluid pair the staggered particle `P_{i−j}` carries the weight
//! `e_ij = c V_{i−j}² |∇W(r_ij/2)| n_ij` (an area) and the share `α_ij = m_{j−}/m_{i−j}` of
//! carrier j (Eqs. 7–9); for a fluid–solid pair the staggered particle takes the solid's
//! velocity (α = 1, the wall condition of Eqs. 26–27) and only its wall-normal part counts
//! (free slip). Then
//!
//! * divergence (volume rate): `(D v)_i = Σ_j α_ij e_ij·(v_j − v_i) + Σ_s ẽ_is·(u_s − v_i)`,
//! * pressure force: `F_k = (Dᵀ p)_k = −Σ_j (α_kj p_k + (1 − α_kj) p_j) e_kj − Σ_s p_k ẽ_ks`,
//!   equal and opposite within every pair (the solid gets `+p_k ẽ_ks`), so momentum is
//!   conserved exactly and a wall feels the fluid pressure on it,
//! * Poisson equation: `D M⁻¹ Dᵀ p = −D ṽ / Δt` on inner carriers (surface carriers p = 0),
//!   symmetric positive definite, solved matrix-free by PCG, then `v = ṽ + Δt M⁻¹ Dᵀ p`.
//!
//! Because the force is the adjoint of the divergence, the update is an exact projection in
//! the kinetic-energy norm: it can remove kinetic energy, never add it. The paper's remap
//! (Eq. 19) loses two thirds of a pressure gradient in 3-D and is not momentum conserving,
//! and applying p^v of Eq. 13 through Eq. 23 overshoots near walls (measured, ARCHITECTURE.md).
//! Eq. 13's compact matrix is still assembled: it is the block-SSOR preconditioner.

use super::pcg::PoissonSystem;
use super::staggered::{pair, Share, Slip};
use super::{for_rows, row_blocks, Ctx, ROWS};
use crate::math::Vector;
use rapier3d::math::Matrix;
use rayon::prelude::*;

/// Wall-normal weight `ẽ = min(e·n, 0) n` of a fluid–solid pair: only the part of the pair that
/// looks at the wall from the fluid side counts.
#[inline]
fn wall_weight(e: Vector, n: Vector) -> Vector {
    n * e.dot(n).min(0.0)
}

/// Fills `sys` with the consistent system for fluid carriers at `x` with predicted velocities
/// `v`: the per-slot weights `α_ij L_i e_ij` / `ê_is` and `(1 − α_ij) L_j e_ij`, the per-row
/// wall sums, the Jacobi diagonal, the right-hand side `−D ṽ/Δt` and, if `eq13` (the block-SSOR
/// preconditioner needs them), Eq. 13's compact coefficients. `c` is the lattice
/// normalisation of the divergence.
///
/// Neither `e_ij` nor `α_ij` is kept: pass 1 stores `α e` in `ec` and `(1 − α) e` in `q`, pass
/// 2 multiplies `ec` by `L_i`, and a last pass multiplies `q` by `L_j`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn assemble(
    ctx: &Ctx,
    x: &[Vector],
    v: &[Vector],
    shares: &[Share],
    surface: &[bool],
    dt: f32,
    c: f32,
    correct: bool,
    eq13: bool,
    sys: &mut PoissonSystem,
) {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    let slots = ctx.lists.pair_count();
    sys.adjoint = true;
    sys.mass = ctx.mass as f64;
    if eq13 {
        sys.coef.resize(slots, 0.0);
    } else {
        sys.coef = Vec::new();
    }
    sys.ec.resize(slots, Vector::ZERO);
    sys.q.resize(slots, Vector::ZERO);
    sys.diag.resize(nf, 0.0);
    sys.adj_diag.resize(nf, 0.0);
    sys.rhs.resize(nf, 0.0);
    sys.row_scale.resize(nf, 0.0);
    sys.unknown.clear();
    sys.unknown.extend(surface.iter().map(|s| !s));
    // per-slot data, row by row
    let offsets = &ctx.lists.offsets;
    let mut coef_blocks = if eq13 {
        row_blocks(offsets, &mut sys.coef)
    } else {
        Vec::new()
    };
    coef_blocks.resize_with(nf.div_ceil(ROWS), Default::default);
    let items: Vec<_> = coef_blocks
        .into_iter()
        .zip(row_blocks(offsets, &mut sys.ec))
        .zip(row_blocks(offsets, &mut sys.q))
        .collect();
    let vol = ctx.mass / ctx.rest_density;
    let per_row: Vec<Vec<RowData>> = items
        .into_par_iter()
        .enumerate()
        .map(|(b, ((coef, cv), qv))| {
            let base = offsets[b * ROWS] as usize;
            let end = ((b + 1) * ROWS).min(nf);
            let mut out = Vec::with_capacity(end - b * ROWS);
            for i in b * ROWS..end {
                let (xi, vi, si) = (x[i], v[i], shares[i]);
                let mut d13 = 0.0f64;
                let mut bm = Matrix::ZERO;
                // pass 1: α e and (1 − α) e, Eq. 13 coefficients and the moment matrix B_i
                for slot in ctx.lists.fluid_range(i) {
                    let k = slot - base;
                    let j = ctx.lists.indices[slot] as usize;
                    cv[k] = Vector::ZERO;
                    qv[k] = Vector::ZERO;
                    let d = x[j] - xi;
                    let r = d.length();
                    let cij = if r >= h || r <= 1e-9 {
                        0.0
                    } else {
                        let gw = ctx.kernel.grad_mag(0.5 * r);
                        let sj = shares[j];
                        let st = pair(si, vi, sj, v[j]);
                        let e = d * (c * st.volume * st.volume * gw / r);
                        let alpha = sj.mass / st.mass;
                        cv[k] = e * alpha;
                        qv[k] = e * (1.0 - alpha);
                        bm += outer(cv[k], d);
                        st.volume * st.volume * gw / (st.mass * r)
                    };
                    d13 += cij as f64;
                    if eq13 {
                        coef[k] = cij;
                    }
                }
                for slot in ctx.lists.solid_range(i) {
                    let k = slot - base;
                    let s = ctx.lists.indices[slot] as usize - nf;
                    cv[k] = Vector::ZERO;
                    if eq13 {
                        coef[k] = 0.0;
                    }
                    let d = ctx.solid_x[s] - xi;
                    let r = d.length();
                    if r >= h || r <= 1e-9 {
                        continue;
                    }
                    let gw = ctx.kernel.grad_mag(0.5 * r);
                    let body = &ctx.bodies[ctx.solid_body[s] as usize];
                    let st = pair(si, vi, body.share, ctx.solid_u[s]);
                    let e = wall_weight(d * (c * st.volume * st.volume * gw / r), ctx.solid_n[s]);
                    cv[k] = e;
                    bm += outer(e, d);
                }
                let l = if correct {
                    correction(bm, vol)
                } else {
                    Matrix::IDENTITY
                };
                // pass 2: divergence of ṽ and the Jacobi diagonal with the corrected weights
                let (mut dadj, mut div) = (0.0f64, 0.0f64);
                let (mut s_f, mut s_w) = (Vector::ZERO, Vector::ZERO);
                for slot in ctx.lists.fluid_range(i) {
                    let k = slot - base;
                    let j = ctx.lists.indices[slot] as usize;
                    let ae = cv[k];
                    let le = l * ae;
                    cv[k] = le;
                    dadj += le.length_squared() as f64 / ctx.mass as f64;
                    div += le.dot(v[j] - vi) as f64;
                    s_f += ae;
                }
                for slot in ctx.lists.solid_range(i) {
                    // corrected, then back onto the wall normal: a free-slip wall takes no
                    // tangential force
                    let k = slot - base;
                    let s = ctx.lists.indices[slot] as usize - nf;
                    let n = ctx.solid_n[s];
                    let le = n * n.dot(l * cv[k]);
                    cv[k] = le;
                    div += le.dot(ctx.solid_u[s] - vi) as f64;
                    s_w += le;
                }
                let own = l * s_f + s_w;
                dadj += own.length_squared() as f64 / ctx.mass as f64;
                out.push(RowData {
                    d13,
                    dadj,
                    rhs: -div / dt as f64,
                    l,
                    own,
                    wall: s_w,
                });
            }
            out
        })
        .collect();
    sys.l.resize(nf, Matrix::IDENTITY);
    sys.own.resize(nf, Vector::ZERO);
    sys.wall.resize(nf, Vector::ZERO);
    for (i, r) in per_row.into_iter().flatten().enumerate() {
        let (d13, dadj, b, ok, l) = (r.d13, r.dadj, r.rhs, r.d13 > 0.0, r.l);
        sys.l[i] = l;
        sys.own[i] = r.own;
        sys.wall[i] = r.wall;
        sys.diag[i] = if ok { d13 } else { 1.0 };
        sys.adj_diag[i] = if dadj > 0.0 { dadj } else { 1.0 };
        sys.rhs[i] = b;
        if !ok {
            // an inner carrier whose fluid neighbours all left the support: p = 0
            sys.unknown[i] = false;
        }
        if !sys.unknown[i] {
            sys.rhs[i] = 0.0;
        }
    }
    // neighbour-side force weights q_kj = (1 − α_kj) L_j e_kj, once L of every carrier is known
    let l = &sys.l;
    row_blocks(offsets, &mut sys.q)
        .into_par_iter()
        .enumerate()
        .for_each(|(b, qv)| {
            let base = offsets[b * ROWS] as usize;
            for i in b * ROWS..((b + 1) * ROWS).min(nf) {
                for slot in ctx.lists.fluid_range(i) {
                    let j = ctx.lists.indices[slot] as usize;
                    qv[slot - base] = l[j] * qv[slot - base];
                }
            }
        });
    // E (Eq. 29) is the relative volume change per step, Δt |D v|_i / V_i, V_i = m/ρ̄
    let scale = ctx.rest_density as f64 / ctx.mass as f64;
    sys.row_scale.par_iter_mut().for_each(|s| *s = scale);
}

/// Couples the assembled system to the moving dynamic bodies (`inv[k]`: inverse mass per axis
/// and world inverse inertia of body k): one [`super::pcg::RigidLink`] per unknown row and body,
/// and the body part of the Jacobi diagonal. The right-hand side already holds the bodies'
/// current velocities through `u_s`.
pub(crate) fn link_rigids(ctx: &Ctx, inv: &[(Vector, Matrix)], sys: &mut PoissonSystem) {
    sys.links.clear();
    sys.rigid_inv.clear();
    if !ctx.bodies.iter().any(|b| b.rigid != u32::MAX) {
        return;
    }
    sys.rigid_inv.extend_from_slice(inv);
    let nf = ctx.n_fluid();
    let links = for_rows_collect(nf, |i| {
        let mut out: Vec<super::pcg::RigidLink> = Vec::new();
        if !sys.unknown[i] {
            return out;
        }
        for slot in ctx.lists.solid_range(i) {
            let e = sys.ec[slot];
            if e == Vector::ZERO {
                continue;
            }
            let s = ctx.lists.indices[slot] as usize - nf;
            let body = &ctx.bodies[ctx.solid_body[s] as usize];
            if body.rigid == u32::MAX {
                continue;
            }
            let ang = (ctx.solid_x[s] - body.com).cross(e);
            match out.iter_mut().find(|l| l.rigid == body.rigid) {
                Some(l) => {
                    l.lin += e;
                    l.ang += ang;
                }
                None => out.push(super::pcg::RigidLink {
                    row: i as u32,
                    rigid: body.rigid,
                    lin: e,
                    ang,
                }),
            }
        }
        out
    });
    for l in &links {
        let (im, ii) = inv[l.rigid as usize];
        sys.adj_diag[l.row as usize] += (l.lin.dot(im * l.lin) + l.ang.dot(ii * l.ang)) as f64;
    }
    sys.links = links;
}

/// Runs `f(i)` over all rows in parallel with fixed chunking and concatenates the results in
/// row order.
fn for_rows_collect<T: Send>(n: usize, f: impl Fn(usize) -> Vec<T> + Sync) -> Vec<T> {
    let parts: Vec<Vec<T>> = (0..n.div_ceil(ROWS))
        .into_par_iter()
        .map(|c| (c * ROWS..((c + 1) * ROWS).min(n)).flat_map(&f).collect())
        .collect();
    parts.into_iter().flatten().collect()
}

/// Per-row results of the assembly.
struct RowData {
    /// Eq. 13 diagonal (0 when the row has no fluid neighbour).
    d13: f64,
    /// Diagonal of `D M⁻¹ Dᵀ`.
    dadj: f64,
    /// `−(D ṽ)_i / Δt`.
    rhs: f64,
    /// Gradient correction `L_i`.
    l: Matrix,
    /// Own-pressure weight `L_i Σ_j α_ij e_ij + Σ_s ê_is`.
    own: Vector,
    /// Wall sum `Σ_s ê_is`.
    wall: Vector,
}

/// Outer product `a bᵀ`.
#[inline]
fn outer(a: Vector, b: Vector) -> Matrix {
    Matrix::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Tikhonov weight δ of the gradient correction, relative to `tr B/3`.
const CORRECTION_REGULARISATION: f32 = 0.1;

/// First-order correction `L_i = V (1 + δ)(B_i + δ tr(B_i)/3 I)⁻¹` of the divergence weights,
/// `B_i = Σ_j α_ij e_ij (x_j − x_i)ᵀ + Σ_s ẽ_is (x_s − x_i)ᵀ`, so that `D` is exact for linear
/// velocity fields (`L = I` on a full rest lattice). Beside a free-slip wall B has only half
/// its tangential moment, and without L a carrier there gets half the vertical pressure
/// support of the bulk. δ bounds the gain where neighbours are few.
fn correction(b: Matrix, vol: f32) -> Matrix {
    let tr = (b.x_axis.x + b.y_axis.y + b.z_axis.z) / 3.0;
    if tr.is_nan() || tr <= 1e-3 * vol {
        return Matrix::IDENTITY;
    }
    let reg = b + Matrix::from_diagonal(Vector::splat(CORRECTION_REGULARISATION * tr));
    let det = reg.determinant();
    if det.is_nan() || det.abs() <= 1e-9 * tr * tr * tr {
        return Matrix::IDENTITY;
    }
    reg.inverse() * (vol * (1.0 + CORRECTION_REGULARISATION))
}

/// §5.2 no-stick inequality as an active set: a wall may push fluid but never hold it back, so
/// an inner carrier that moves away from a non-sticky solid (predicted velocity `v`) and whose
/// solved pressure is negative (the wall would pull it back) is released, like a free-surface
/// carrier (p = 0), before a second solve. Returns the number of carriers released.
pub(crate) fn release_wall_suction(
    ctx: &Ctx,
    v: &[Vector],
    sys: &mut PoissonSystem,
    p: &mut [f64],
) -> usize {
    let nf = ctx.n_fluid();
    let release: Vec<bool> = (0..nf)
        .into_par_iter()
        .map(|i| {
            sys.unknown[i]
                && p[i] < 0.0
                && ctx.lists.solid_range(i).any(|slot| {
                    sys.ec[slot] != Vector::ZERO && {
                        let s = ctx.lists.indices[slot] as usize - nf;
                        !ctx.bodies[ctx.solid_body[s] as usize].stick
                            && (v[i] - ctx.solid_u[s]).dot(ctx.solid_n[s]) > 0.0
                    }
                })
        })
        .collect();
    let mut n = 0;
    for (i, r) in release.into_iter().enumerate() {
        if r {
            sys.unknown[i] = false;
            sys.rhs[i] = 0.0;
            p[i] = 0.0;
            n += 1;
        }
    }
    n
}

/// `F = Dᵀ p` on every fluid carrier (p is zero on surface carriers), times `scale`:
/// `F_k = −p_k (L_k Σ_j α_kj e_kj + Σ_s ê_ks) − Σ_j p_j (1 − α_kj) L_j e_kj`, with the wall
/// weights `ê_ks = n_s n_s·(L_k ẽ_ks)` stored already corrected and the bracket precomputed per
/// carrier (`PoissonSystem::own`).
pub(crate) fn pressure_force(
    sys: &PoissonSystem,
    lists: &crate::neighbors::NeighborLists,
    p: &[f32],
    scale: f32,
    f: &mut [Vector],
) {
    f.par_iter_mut().enumerate().for_each(|(k, fk)| {
        *fk = (-(sys.own[k] * p[k]) - neighbour_push(sys, lists, k, p)) * scale;
    });
}

/// `Σ_j p_j (1 − α_kj) L_j e_kj` of carrier k: the push of its fluid neighbours' pressures.
#[inline]
fn neighbour_push<P: Copy + Into<f64>>(
    sys: &PoissonSystem,
    lists: &crate::neighbors::NeighborLists,
    k: usize,
    p: &[P],
) -> Vector {
    let r = lists.fluid_range(k);
    let mut n = Vector::ZERO;
    for (q, &j) in sys.q[r.clone()].iter().zip(&lists.indices[r]) {
        n += *q * p[j as usize].into() as f32;
    }
    n
}

/// `y = D g` on unknown rows for carrier velocities `g` (solids at rest: the homogeneous
/// operator). Each row sums its ≈ 30 terms in f32 and hands the sum on in f64.
pub(crate) fn divergence(
    sys: &PoissonSystem,
    lists: &crate::neighbors::NeighborLists,
    g: &[Vector],
    y: &mut [f64],
) {
    y.par_iter_mut().enumerate().for_each(|(i, yi)| {
        if !sys.unknown[i] {
            *yi = 0.0;
            return;
        }
        let gi = g[i];
        let mut s = -sys.wall[i].dot(gi);
        let r = lists.fluid_range(i);
        for (e, &j) in sys.ec[r.clone()].iter().zip(&lists.indices[r]) {
            s += e.dot(g[j as usize] - gi);
        }
        *yi = s as f64;
    });
}

/// Applies the solved pressure: `v += Δt M⁻¹ Dᵀ p`; returns the per-body impulses
/// (`+p_k ẽ_ks Δt` on the solid of every fluid–solid pair).
pub(crate) fn apply_pressure(
    ctx: &Ctx,
    sys: &PoissonSystem,
    p: &[f64],
    dt: f32,
    v: &mut [Vector],
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let inv_m = dt / ctx.mass;
    for_rows(v, |k, vk, acc| {
        let pk = p[k] as f32;
        let n = neighbour_push(sys, ctx.lists, k, p);
        if pk != 0.0 {
            // the solids' share: +p_k ê_ks on each wall carrier
            for slot in ctx.lists.solid_range(k) {
                let e = sys.ec[slot];
                if e != Vector::ZERO {
                    acc.add(ctx.lists.indices[slot] as usize - nf, e * (pk * dt));
                }
            }
        }
        *vk += (-(sys.own[k] * pk) - n) * inv_m;
    })
}

/// Free-surface carriers beside a wall (Eq. 27 on their staggered particles): p^v = 0 on a
/// surface carrier, so the projection cannot stop it from moving into a wall; here the normal
/// velocity of every approaching fluid–solid staggered particle is set to the wall's, and the
/// change is remapped onto the carrier as in Eq. 19 (§5.2 no-stick: leaving pairs are free).
/// Returns the per-body reaction impulses.
pub(crate) fn surface_walls(
    ctx: &Ctx,
    x: &[Vector],
    shares: &[Share],
    counts: &[u32],
    unknown: &[bool],
    v: &mut [Vector],
) -> super::Impulses {
    wall_remap(
        ctx,
        x,
        shares,
        counts,
        v,
        |i| !unknown[i],
        |body, rel, n| {
            let vn = rel.dot(n);
            (vn < 0.0 || body.stick).then(|| n * vn)
        },
    )
}

/// Sets part of the relative velocity of fluid–solid staggered particles to the wall's and
/// remaps the change onto the carriers as in Eq. 19 (`Δv_i = −Σ_s c_is / N_i` over the carriers
/// `i` with `rows(i)`, `c_is = part(body, ṽ_is − u_s, n_s)`), handing each solid the opposite
/// impulse. Returns the per-body impulses.
fn wall_remap(
    ctx: &Ctx,
    x: &[Vector],
    shares: &[Share],
    counts: &[u32],
    v: &mut [Vector],
    rows: impl Fn(usize) -> bool + Sync,
    part: impl Fn(&super::BodyView, Vector, Vector) -> Option<Vector> + Sync,
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    let v0 = v.to_vec();
    for_rows(v, |i, vi_out, acc| {
        if !rows(i) {
            return;
        }
        let (xi, vi, si) = (x[i], v0[i], shares[i]);
        let inv_n = 1.0 / counts[i].max(1) as f32;
        let mut dv = Vector::ZERO;
        for &j in ctx.lists.row(i) {
            let j = j as usize;
            if j < nf {
                continue;
            }
            let s = j - nf;
            let r = (ctx.solid_x[s] - xi).length();
            if r >= h || r <= 1e-9 {
                continue;
            }
            let b = ctx.solid_body[s];
            let body = &ctx.bodies[b as usize];
            let u = ctx.solid_u[s];
            let st = pair(si, vi, body.share, u);
            if let Some(c) = part(body, st.velocity - u, ctx.solid_n[s]) {
                let d = -c * inv_n;
                dv += d;
                acc.add(s, -d * ctx.mass);
            }
        }
        *vi_out = vi + dv;
    })
}

/// No-slip walls (Eq. 26): the tangential velocity of every fluid–solid staggered particle is
/// set to the wall's, and the change is remapped onto the carrier as in Eq. 19. Returns the
/// per-body reaction impulses. Free-slip and partial-slip walls are left alone (their normal
/// condition is in the projection, their friction in Eq. 24).
pub(crate) fn no_slip(
    ctx: &Ctx,
    x: &[Vector],
    shares: &[Share],
    counts: &[u32],
    v: &mut [Vector],
) -> super::Impulses {
    if !ctx.bodies.iter().any(|b| b.slip == Slip::NoSlip) {
        return Vec::new();
    }
    wall_remap(
        ctx,
        x,
        shares,
        counts,
        v,
        |_| true,
        |body, rel, n| (body.slip == Slip::NoSlip).then(|| rel - n * rel.dot(n)),
    )
}
