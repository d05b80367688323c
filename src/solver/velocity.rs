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

use super::staggered::{pair, Share, Slip};
use super::system::{neighbour_push, PoissonSystem};
use super::weights::{self, magnitude, pack, row_scale, unpack, Packed};
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
/// Neither `e_ij` nor `α_ij` is kept. Pass 1 computes `α e` and the moment matrix of each row,
/// pass 2 corrects the row by `L_i` and stores it in fixed point with the row's own scale
/// ([`super::weights`]); the row sums, the divergence of `ṽ` and the diagonal are taken from
/// the stored values. The force weights are not computed at all: `(1 − α_kj) L_j e_kj =
/// −α_jk L_j e_jk` (`α_jk = 1 − α_kj`, `e_jk = −e_kj`), so `q_kj` is the negated stored
/// `ec_jk` (in row j's scale), and `Dᵀ` is the exact adjoint of `D` on the stored values.
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
    sys.ec.resize(slots, weights::ZERO);
    sys.q.resize(slots, weights::ZERO);
    sys.weight_scale.resize(nf, 0.0);
    if eq13 {
        sys.diag.resize(nf, 0.0);
    } else {
        sys.diag = Vec::new();
    }
    sys.adj_diag.resize(nf, 0.0);
    sys.rhs.resize(nf, 0.0);
    sys.own.resize(nf, Vector::ZERO);
    sys.wall.resize(nf, Vector::ZERO);
    sys.unknown.clear();
    sys.unknown.extend(surface.iter().map(|s| !s));
    let offsets = &ctx.lists.offsets;
    let mut coef_blocks = if eq13 {
        row_blocks(offsets, &mut sys.coef)
    } else {
        Vec::new()
    };
    coef_blocks.resize_with(nf.div_ceil(ROWS), Default::default);
    let vol = ctx.mass / ctx.rest_density;
    let inv_m = 1.0 / ctx.mass as f64;
    // the per-row results, written in place block by block
    let mut row_out: Vec<RowOut> = sys
        .weight_scale
        .chunks_mut(ROWS)
        .zip(sys.own.chunks_mut(ROWS))
        .zip(sys.wall.chunks_mut(ROWS))
        .zip(sys.adj_diag.chunks_mut(ROWS))
        .zip(sys.rhs.chunks_mut(ROWS).zip(sys.unknown.chunks_mut(ROWS)))
        .map(
            |((((scale, own), wall), adj_diag), (rhs, unknown))| RowOut {
                scale,
                own,
                wall,
                diag: &mut [],
                adj_diag,
                rhs,
                unknown,
            },
        )
        .collect();
    if eq13 {
        for (o, d) in row_out.iter_mut().zip(sys.diag.chunks_mut(ROWS)) {
            o.diag = d;
        }
    }
    let a = RowInputs {
        ctx,
        x,
        v,
        shares,
        dt,
        c,
        correct,
        eq13,
        h,
        vol,
        inv_m,
    };
    // passes 1 and 2, per row
    coef_blocks
        .into_par_iter()
        .zip(row_blocks(offsets, &mut sys.ec))
        .zip(row_out)
        .enumerate()
        .for_each(|(b, ((coef, cv), mut o))| {
            let base = offsets[b * ROWS] as usize;
            let end = ((b + 1) * ROWS).min(nf);
            // one row's weights at full precision before they are stored
            let mut eb = Vec::<Vector>::new();
            for i in b * ROWS..end {
                assemble_row(&a, i, base, coef, cv, &mut eb, &mut o, i - b * ROWS);
            }
        });
    force_weights(ctx.lists, &sys.ec, &mut sys.q);
    // E (Eq. 29) is the relative volume change per step, Δt |D v|_i / V_i, V_i = m/ρ̄
    sys.error_scale = ctx.rest_density as f64 / ctx.mass as f64;
}

/// What every row of [`assemble`] reads.
struct RowInputs<'a> {
    ctx: &'a Ctx<'a>,
    x: &'a [Vector],
    v: &'a [Vector],
    shares: &'a [Share],
    dt: f32,
    /// Lattice normalisation of the divergence.
    c: f32,
    /// Apply the gradient correction `L_i`.
    correct: bool,
    /// Also store Eq. 13's coefficients (block-SSOR preconditioner).
    eq13: bool,
    /// Support radius.
    h: f32,
    /// Carrier volume `m/ρ̄`.
    vol: f32,
    /// `1/m`.
    inv_m: f64,
}

/// Passes 1 and 2 of [`assemble`] for row `i` (its block starts at slot `base`; `k` is the
/// row's index in its block's outputs `o`); `eb` is a reusable buffer.
#[allow(clippy::too_many_arguments)]
fn assemble_row(
    a: &RowInputs,
    i: usize,
    base: usize,
    coef: &mut [f32],
    cv: &mut [Packed],
    eb: &mut Vec<Vector>,
    o: &mut RowOut,
    k: usize,
) {
    let RowInputs {
        ctx,
        x,
        v,
        shares,
        dt,
        c,
        correct,
        eq13,
        h,
        vol,
        inv_m,
    } = *a;
    let nf = ctx.n_fluid();
    let (xi, vi, si) = (x[i], v[i], shares[i]);
    let row = ctx.lists.range(i);
    let nfl = ctx.lists.fluid_range(i).len();
    eb.clear();
    eb.resize(row.len(), Vector::ZERO);
    let mut d13 = 0.0f64;
    let mut bm = Matrix::ZERO;
    // pass 1: α e, Eq. 13 coefficients and the moment matrix B_i
    for (k, slot) in ctx.lists.fluid_range(i).enumerate() {
        let j = ctx.lists.indices[slot] as usize;
        let d = x[j] - xi;
        let r = d.length();
        let cij = if r >= h || r <= 1e-9 {
            0.0
        } else {
            let gw = ctx.kernel.grad_mag(0.5 * r);
            let sj = shares[j];
            let st = pair(si, vi, sj, v[j]);
            let e = d * (c * st.volume * st.volume * gw / r);
            eb[k] = e * (sj.mass / st.mass);
            bm += outer(eb[k], d);
            st.volume * st.volume * gw / (st.mass * r)
        };
        d13 += cij as f64;
        if eq13 {
            coef[slot - base] = cij;
        }
    }
    for (k, slot) in ctx.lists.solid_range(i).enumerate() {
        if eq13 {
            coef[slot - base] = 0.0;
        }
        let s = ctx.lists.indices[slot] as usize - nf;
        let d = ctx.solid_x[s] - xi;
        let r = d.length();
        if r >= h || r <= 1e-9 {
            continue;
        }
        let gw = ctx.kernel.grad_mag(0.5 * r);
        let body = &ctx.bodies[ctx.solid_body[s] as usize];
        let st = pair(si, vi, body.share, ctx.solid_u[s]);
        let e = wall_weight(d * (c * st.volume * st.volume * gw / r), ctx.solid_n[s]);
        eb[nfl + k] = e;
        bm += outer(e, d);
    }
    let l = if correct {
        correction(bm, vol)
    } else {
        Matrix::IDENTITY
    };
    // pass 2: the corrected weights and the row's largest component
    let mut max = 0.0f32;
    for e in &mut eb[..nfl] {
        *e = l * *e;
        max = max.max(magnitude(*e));
    }
    for (k, slot) in ctx.lists.solid_range(i).enumerate() {
        // corrected, then back onto the wall normal: a free-slip wall takes no
        // tangential force
        let n = ctx.solid_n[ctx.lists.indices[slot] as usize - nf];
        let e = &mut eb[nfl + k];
        *e = n * n.dot(l * *e);
        max = max.max(magnitude(*e));
    }
    // stored, and the row sums, the divergence of ṽ and the Jacobi diagonal taken
    // from the stored weights, so that the operator, its adjoint and the
    // right-hand side all use the same values (sums of the stored integers are
    // exact in f32)
    let (scale, inv) = row_scale(max);
    let stored = &mut cv[row.start - base..row.end - base];
    let (mut sq, mut div_f, mut div_w) = (0.0f64, 0.0f32, 0.0f32);
    let (mut s_f, mut s_w) = (Vector::ZERO, Vector::ZERO);
    for (k, (e, &j)) in eb.iter().zip(ctx.lists.row(i)).enumerate() {
        let q = pack(*e, inv);
        stored[k] = q;
        let le = unpack(q);
        let j = j as usize;
        if k < nfl {
            sq += le.length_squared() as f64;
            div_f += le.dot(v[j] - vi);
            s_f += le;
        } else {
            div_w += le.dot(ctx.solid_u[j - nf] - vi);
            s_w += le;
        }
    }
    let (s_f, s_w) = (s_f * scale, s_w * scale);
    let div = ((div_f + div_w) * scale) as f64;
    let mut dadj = sq * (scale as f64 * scale as f64) * inv_m;
    let own = s_f + s_w;
    dadj += own.length_squared() as f64 * inv_m;
    o.scale[k] = scale;
    o.own[k] = own;
    o.wall[k] = s_w;
    if eq13 {
        o.diag[k] = if d13 > 0.0 { d13 } else { 1.0 };
    }
    o.adj_diag[k] = if dadj > 0.0 { dadj } else { 1.0 };
    if d13 <= 0.0 {
        // an inner carrier whose fluid neighbours all left the support: p = 0
        o.unknown[k] = false;
    }
    o.rhs[k] = if o.unknown[k] { -div / dt as f64 } else { 0.0 };
}

/// The force weights of `Dᵀ` (see [`assemble`]).
fn force_weights(lists: &crate::neighbors::NeighborLists, ec: &[Packed], q: &mut [Packed]) {
    let offsets = &lists.offsets;
    let nf = lists.offsets.len() - 1;
    // the force weights q_kj = −ec_jk, stored as row j's integers (the scale of row j is
    // applied to p_j).
    //
    // Rows are sorted and the lists symmetric, so the rows k that list j, taken in increasing
    // order, meet k in row j in increasing order too: a cursor per j walks row j (the neighbour
    // search's tests check both properties). Each block starts a cursor by counting the
    // neighbours of j below its first row.
    row_blocks(offsets, q)
        .into_par_iter()
        .enumerate()
        .for_each(|(b, qv)| {
            let base = offsets[b * ROWS] as usize;
            let rows = b * ROWS..((b + 1) * ROWS).min(nf);
            let first = |k: usize| lists.indices[lists.fluid_range(k)].first().copied();
            let last = |k: usize| lists.indices[lists.fluid_range(k)].last().copied();
            let lo = rows.clone().filter_map(first).min().unwrap_or(0) as usize;
            let hi = rows.clone().filter_map(last).max().unwrap_or(0) as usize;
            let mut cursor = vec![u32::MAX; hi + 1 - lo.min(hi + 1)];
            let k0 = rows.start as u32;
            for k in rows {
                for slot in lists.fluid_range(k) {
                    let j = lists.indices[slot] as usize;
                    // the slot of k in row j
                    let c = &mut cursor[j - lo];
                    if *c == u32::MAX {
                        let rj = lists.fluid_range(j);
                        let below = lists.indices[rj.clone()].iter().filter(|&&n| n < k0);
                        *c = (rj.start + below.count()) as u32;
                    }
                    let at = *c as usize;
                    *c += 1;
                    debug_assert_eq!(lists.indices[at], k as u32, "pair listed in one row only");
                    qv[slot - base] = weights::neg(ec[at]);
                }
            }
        });
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
            if sys.ec[slot] == weights::ZERO {
                continue;
            }
            let e = unpack(sys.ec[slot]) * sys.weight_scale[i];
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

/// One block's rows of the assembled system, written in place by the assembly.
struct RowOut<'a> {
    /// Scale of each row's stored weights.
    scale: &'a mut [f32],
    /// Own-pressure weight `L_i Σ_j α_ij e_ij + Σ_s ê_is`.
    own: &'a mut [Vector],
    /// Wall sum `Σ_s ê_is`.
    wall: &'a mut [Vector],
    /// Eq. 13 diagonal (only with the SSOR preconditioner, else empty).
    diag: &'a mut [f64],
    /// Diagonal of `D M⁻¹ Dᵀ`.
    adj_diag: &'a mut [f64],
    /// `−(D ṽ)_i / Δt`.
    rhs: &'a mut [f64],
    /// Whether the row is an unknown (surface rows come in false).
    unknown: &'a mut [bool],
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
                    sys.ec[slot] != weights::ZERO && {
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
        let n = neighbour_push(sys, ctx.lists, k, |j| p[j] as f32 * sys.weight_scale[j]);
        if pk != 0.0 {
            // the solids' share: +p_k ê_ks on each wall carrier
            for slot in ctx.lists.solid_range(k) {
                if sys.ec[slot] != weights::ZERO {
                    let e = unpack(sys.ec[slot]) * sys.weight_scale[k];
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
        |_, body, rel, n| {
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
    part: impl Fn(usize, &super::BodyView, Vector, Vector) -> Option<Vector> + Sync,
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    // a row reads only its own carrier's velocity (its solid pairs), so v is updated in place
    for_rows(v, |i, vi_out, acc| {
        if !rows(i) {
            return;
        }
        let (xi, vi, si) = (x[i], *vi_out, shares[i]);
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
            if let Some(c) = part(b as usize, body, st.velocity - u, ctx.solid_n[s]) {
                let d = -c * inv_n;
                dv += d;
                acc.add(s, -d * ctx.mass);
            }
        }
        *vi_out = vi + dv;
    })
}

/// No-slip walls ([`Slip::NoSlip`], Eq. 26): the tangential velocity of every fluid–solid
/// staggered particle is set to the wall's, and the change is remapped onto the carrier as in
/// Eq. 19. Returns the per-body reaction impulses. Other walls are left alone (their normal
/// condition is in the projection, their friction in Eq. 24).
pub(crate) fn no_slip(
    ctx: &Ctx,
    x: &[Vector],
    shares: &[Share],
    counts: &[u32],
    v: &mut [Vector],
    kappa: &[f32],
) -> super::Impulses {
    if !ctx.bodies.iter().any(|b| b.slip == Slip::NoSlip) {
        return super::Impulses::new();
    }
    wall_remap(
        ctx,
        x,
        shares,
        counts,
        v,
        |_| true,
        |b, body, rel, n| {
            (body.slip == Slip::NoSlip)
                .then(|| (rel - n * rel.dot(n)) * kappa.get(b).copied().unwrap_or(1.0))
        },
    )
}
