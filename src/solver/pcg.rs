//! Krylov solve of the velocity constraint (He 2012 §6–7.1): preconditioned conjugate residuals
//! by default, the paper's preconditioned conjugate gradients as an option, both stopping on
//! the incompressibility error E of Eq. 29 and on the relative residual.

use super::weights::Packed;
use super::{det_sum, ROWS};
use crate::math::Vector;
use crate::neighbors::NeighborLists;
use crate::params::{Krylov, Preconditioner};
use rayon::prelude::*;

/// Storage of the solve's vectors: the Krylov vectors are `f32` (the operator itself gathers
/// and sums in f32), the solution `f64`; every dot product and norm is summed in f64.
pub(crate) trait Real: Copy + Send + Sync + 'static {
    /// The value in f64.
    fn f(self) -> f64;
    /// `v` rounded to this type.
    fn of(v: f64) -> Self;
    /// The slice itself if it is f32 already.
    fn as_f32(x: &[Self]) -> Option<&[f32]>;
}

impl Real for f32 {
    #[inline]
    fn f(self) -> f64 {
        self as f64
    }
    #[inline]
    fn of(v: f64) -> Self {
        v as f32
    }
    fn as_f32(x: &[Self]) -> Option<&[f32]> {
        Some(x)
    }
}

impl Real for f64 {
    #[inline]
    fn f(self) -> f64 {
        self
    }
    #[inline]
    fn of(v: f64) -> Self {
        v
    }
    fn as_f32(_: &[Self]) -> Option<&[f32]> {
        None
    }
}

/// The assembled approximate-Laplacian system `A p = b` of Eq. 13 (sign flipped so A is
/// symmetric positive semi-definite), stored along the neighbour lists.
pub struct PoissonSystem {
    /// Off-diagonal magnitudes `c_ij` per neighbour slot (`A_ij = −c_ij` for unknown j).
    pub coef: Vec<f32>,
    /// Diagonal `A_ii = Σ_j c_ij` over all fluid neighbours (surface ones included). Empty
    /// for the consistent operator unless the block-SSOR preconditioner needs it.
    pub diag: Vec<f64>,
    /// Right-hand side `b_i = −(∇·ṽ)_i / Δt`.
    pub rhs: Vec<f64>,
    /// Whether row i is an unknown (inner fluid carrier); other rows are p = 0.
    pub unknown: Vec<bool>,
    /// If true, A is the consistent operator `D M⁻¹ Dᵀ` of [`crate::solver::velocity`],
    /// applied matrix-free; `coef`/`diag` (Eq. 13) then only serve the SSOR preconditioner.
    pub adjoint: bool,
    /// Per-slot corrected divergence weight `α_ij L_i e_ij` (fluid) or `ê_is` (solid), in
    /// 16-bit fixed point (see [`super::weights`]); times `weight_scale[i]` of its row.
    pub ec: Vec<Packed>,
    /// Per-slot neighbour-side force weight `(1 − α_kj) L_j e_kj = −ec_jk` (fluid slots only;
    /// solid slots are unused): the integers of `−ec_jk`, so times `weight_scale[j]`.
    pub q: Vec<Packed>,
    /// Per-row scale of the stored weights.
    pub weight_scale: Vec<f32>,
    /// Per-carrier wall sum `Σ_s ê_is` (the solid slots' part of the divergence of a carrier
    /// velocity: `−Σ_s ê_is·g_i`).
    pub wall: Vec<Vector>,
    /// Per-carrier own-pressure weight `L_k Σ_j α_kj e_kj + Σ_s ê_ks` of `Dᵀ`.
    pub own: Vec<Vector>,
    /// Diagonal of the consistent operator (Jacobi preconditioner).
    pub adj_diag: Vec<f64>,
    /// Factor turning `Δt²·|r_i|` into E (Eq. 29): `ρ̄/m` for the consistent operator, 1 for
    /// Eq. 13's.
    pub error_scale: f64,
    /// Fluid carrier mass (the M of `D M⁻¹ Dᵀ`).
    pub mass: f64,
    /// Rows beside moving dynamic bodies, whose velocities are unknowns of the same solve.
    pub links: Vec<RigidLink>,
    /// Inverse mass (per axis) and world inverse inertia of each dynamic body.
    pub rigid_inv: Vec<(Vector, rapier3d::math::Matrix)>,
}

/// Coupling of one row of the consistent operator to one dynamic body: the body's velocity
/// `(U, ω)` enters the row's divergence as `lin·U + ang·ω` (`lin = Σ_s ê_is`,
/// `ang = Σ_s (x_s − X) × ê_is` over the body's carriers s), and the row's pressure pushes
/// the body with `p_i (lin, ang)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidLink {
    /// Fluid row.
    pub row: u32,
    /// Index of the body in [`PoissonSystem::rigid_inv`].
    pub rigid: u32,
    /// Σ ê over the body's carriers in the row.
    pub lin: Vector,
    /// Σ (x_s − X) × ê.
    pub ang: Vector,
}

impl PoissonSystem {
    pub(crate) fn new() -> Self {
        Self {
            coef: Vec::new(),
            diag: Vec::new(),
            rhs: Vec::new(),
            unknown: Vec::new(),
            adjoint: false,
            own: Vec::new(),
            ec: Vec::new(),
            q: Vec::new(),
            weight_scale: Vec::new(),
            wall: Vec::new(),
            adj_diag: Vec::new(),
            error_scale: 1.0,
            mass: 1.0,
            links: Vec::new(),
            rigid_inv: Vec::new(),
        }
    }

    /// `y = A x` over unknown rows (zero elsewhere). `x` must be zero on non-unknown rows.
    pub fn apply(&self, lists: &NeighborLists, x: &[f64], y: &mut [f64]) {
        self.apply_with(lists, x, y, &mut Scratch::default());
    }

    /// [`Self::apply`] with reusable buffers (one set per solve, not per iteration).
    fn apply_with<X: Real, Y: Real>(
        &self,
        lists: &NeighborLists,
        x: &[X],
        y: &mut [Y],
        sc: &mut Scratch,
    ) {
        let nf = self.unknown.len();
        if self.adjoint {
            // the neighbour loops gather p in f32 (the Krylov vectors are f32 already; an f64
            // operand, the solution, is rounded into a buffer)
            let p: &[f32] = match X::as_f32(x) {
                Some(p) => p,
                None => {
                    sc.p.clear();
                    sc.p.par_extend(x.par_iter().map(|&v| v.f() as f32));
                    &sc.p
                }
            };
            sc.ps.clear();
            sc.ps
                .par_extend(p.par_iter().zip(&self.weight_scale).map(|(&p, &s)| p * s));
            sc.g.resize(nf, Vector::ZERO);
            let inv_m = (1.0 / self.mass) as f32;
            crate::solver::velocity::pressure_force(self, lists, p, &sc.ps, inv_m, &mut sc.g);
            crate::solver::velocity::divergence(self, lists, &sc.g, y);
            self.apply_rigid(x, y);
            return;
        }
        y.par_iter_mut().enumerate().for_each(|(i, yi)| {
            if !self.unknown[i] {
                *yi = Y::of(0.0);
                return;
            }
            let mut s = self.diag[i] * x[i].f();
            for k in lists.fluid_range(i) {
                s -= self.coef[k] as f64 * x[lists.indices[k] as usize].f();
            }
            *yi = Y::of(s);
        });
    }

    /// Adds the dynamic bodies' part `J M_b⁻¹ Jᵀ x` of the operator (monolithic coupling: the
    /// bodies move with the pressure that the solve finds, so light bodies stay stable).
    fn apply_rigid<X: Real, Y: Real>(&self, x: &[X], y: &mut [Y]) {
        if self.links.is_empty() {
            return;
        }
        let mut g = vec![[0.0f64; 6]; self.rigid_inv.len()];
        for l in &self.links {
            let p = x[l.row as usize].f();
            let e = &mut g[l.rigid as usize];
            for (k, v) in [l.lin.x, l.lin.y, l.lin.z, l.ang.x, l.ang.y, l.ang.z]
                .into_iter()
                .enumerate()
            {
                e[k] += p * v as f64;
            }
        }
        let dv: Vec<(Vector, Vector)> = g
            .iter()
            .zip(&self.rigid_inv)
            .map(|(e, (im, ii))| {
                let f = Vector::new(e[0] as f32, e[1] as f32, e[2] as f32);
                let t = Vector::new(e[3] as f32, e[4] as f32, e[5] as f32);
                (*im * f, *ii * t)
            })
            .collect();
        for l in &self.links {
            let i = l.row as usize;
            if self.unknown[i] {
                let (du, dw) = dv[l.rigid as usize];
                y[i] = Y::of(y[i].f() + (l.lin.dot(du) + l.ang.dot(dw)) as f64);
            }
        }
    }

    /// Dense copy of A restricted to unknown rows and columns (tests only; O(n²) memory; the
    /// consistent operator is built column by column from [`Self::apply`]).
    pub fn to_dense(&self, lists: &NeighborLists) -> (Vec<usize>, Vec<Vec<f64>>) {
        let n = self.unknown.len();
        let idx: Vec<usize> = (0..n).filter(|&i| self.unknown[i]).collect();
        let mut pos = vec![usize::MAX; n];
        for (a, &i) in idx.iter().enumerate() {
            pos[i] = a;
        }
        let mut m = vec![vec![0.0; idx.len()]; idx.len()];
        if self.adjoint {
            let (mut x, mut y) = (vec![0.0; n], vec![0.0; n]);
            for (c, &j) in idx.iter().enumerate() {
                x[j] = 1.0;
                self.apply(lists, &x, &mut y);
                x[j] = 0.0;
                for (r, &i) in idx.iter().enumerate() {
                    m[r][c] = y[i];
                }
            }
            return (idx, m);
        }
        for (a, &i) in idx.iter().enumerate() {
            m[a][a] = self.diag[i];
            for (k, &j) in lists.range(i).zip(lists.row(i)) {
                let j = j as usize;
                if j < n && self.unknown[j] {
                    m[a][pos[j]] -= self.coef[k] as f64;
                }
            }
        }
        (idx, m)
    }

    fn precondition<T: Real>(
        &self,
        lists: &NeighborLists,
        kind: Preconditioner,
        omega: f64,
        block: usize,
        r: &[T],
        z: &mut [T],
    ) {
        match kind {
            Preconditioner::None => z.par_iter_mut().zip(r).for_each(|(z, &r)| *z = r),
            Preconditioner::Jacobi => z.par_iter_mut().enumerate().for_each(|(i, z)| {
                let d = if self.adjoint {
                    self.adj_diag[i]
                } else {
                    self.diag[i]
                };
                *z = T::of(if self.unknown[i] { r[i].f() / d } else { 0.0 })
            }),
            Preconditioner::BlockSsor => {
                z.par_chunks_mut(block).enumerate().for_each(|(b, zb)| {
                    let lo = b * block;
                    let hi = lo + zb.len();
                    // forward sweep (D/ω + L) y = r
                    for i in lo..hi {
                        if !self.unknown[i] {
                            zb[i - lo] = T::of(0.0);
                            continue;
                        }
                        let mut s = r[i].f();
                        for k in lists.fluid_range(i) {
                            let j = lists.indices[k] as usize;
                            if j >= lo && j < i {
                                s += self.coef[k] as f64 * zb[j - lo].f();
                            }
                        }
                        zb[i - lo] = T::of(s * omega / self.diag[i]);
                    }
                    // scale by D/ω, then backward sweep (D/ω + Lᵀ) z = (D/ω) y
                    for i in (lo..hi).rev() {
                        if !self.unknown[i] {
                            continue;
                        }
                        let mut s = zb[i - lo].f() * self.diag[i] / omega;
                        for k in lists.fluid_range(i) {
                            let j = lists.indices[k] as usize;
                            if j > i && j < hi {
                                s += self.coef[k] as f64 * zb[j - lo].f();
                            }
                        }
                        zb[i - lo] = T::of(s * omega / self.diag[i]);
                    }
                    for v in zb.iter_mut() {
                        *v = T::of(v.f() * (2.0 - omega));
                    }
                });
            }
        }
    }
}

/// Buffers of the matrix-free operator, kept across the iterations of one solve.
#[derive(Default)]
struct Scratch {
    /// The operand in f32 (when it is f64).
    p: Vec<f32>,
    /// The operand times each row's weight scale.
    ps: Vec<f32>,
    /// `M⁻¹ Dᵀ p`.
    g: Vec<Vector>,
}

/// Outcome of one PCG solve.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PcgStats {
    /// Iterations performed.
    pub iterations: u32,
    /// E (Eq. 29) before the first iteration (of the warm start).
    pub initial_error: f64,
    /// E at exit.
    pub error: f64,
    /// `‖r‖₂/‖b‖₂` at exit.
    pub relative_residual: f64,
    /// Whether both criteria were reached.
    pub converged: bool,
}

/// PCG settings.
#[derive(Debug, Clone, Copy)]
pub struct PcgSettings {
    /// Preconditioner.
    pub kind: Preconditioner,
    /// Conjugate gradients or conjugate residuals.
    pub krylov: Krylov,
    /// SSOR ω.
    pub omega: f64,
    /// SSOR block size in rows.
    pub block: usize,
    /// Target E (fraction).
    pub tolerance: f64,
    /// Required `‖r‖₂/‖b‖₂` as well.
    pub relative_residual: f64,
    /// Iteration cap.
    pub max_iterations: u32,
    /// Time step (E = Δt² · mean |r_i|).
    pub dt: f64,
}

fn dot<A: Real, B: Real>(a: &[A], b: &[B]) -> f64 {
    det_sum(a.len(), |i| a[i].f() * b[i].f())
}

/// E of Eq. 29 from the residual: `Δt·|∇·v^new_i| = Δt²·|r_i|`, averaged over unknowns.
pub fn incompressibility_error(sys: &PoissonSystem, r: &[f64], dt: f64, n_unknown: usize) -> f64 {
    error_of(sys, r, dt, n_unknown)
}

fn error_of<T: Real>(sys: &PoissonSystem, r: &[T], dt: f64, n_unknown: usize) -> f64 {
    if n_unknown == 0 {
        return 0.0;
    }
    det_sum(
        r.len(),
        |i| {
            if sys.unknown[i] {
                r[i].f().abs()
            } else {
                0.0
            }
        },
    ) * sys.error_scale
        * dt
        * dt
        / n_unknown as f64
}

/// Solves `A x = b` (x holds the warm start, zero on non-unknown rows) until E ≤ tolerance.
pub fn solve(
    sys: &PoissonSystem,
    lists: &NeighborLists,
    x: &mut [f64],
    s: PcgSettings,
) -> PcgStats {
    let n = sys.unknown.len();
    let n_unknown = sys.unknown.iter().filter(|&&u| u).count();
    // the residual, like every Krylov vector, in f32 (sums in f64)
    let mut r = vec![0.0f32; n];
    let mut scratch = Scratch::default();
    sys.apply_with(lists, x, &mut r, &mut scratch);
    r.par_iter_mut().enumerate().for_each(|(i, r)| {
        *r = if sys.unknown[i] {
            (sys.rhs[i] - *r as f64) as f32
        } else {
            0.0
        }
    });
    let e0 = error_of(sys, &r, s.dt, n_unknown);
    let bnorm = det_sum(n, |i| {
        if sys.unknown[i] {
            sys.rhs[i] * sys.rhs[i]
        } else {
            0.0
        }
    })
    .sqrt()
    .max(1e-300);
    let rel = |r: &[f32]| dot(r, r).sqrt() / bnorm;
    let rel0 = rel(&r);
    let done = |e: f64, q: f64| e <= s.tolerance && q <= s.relative_residual;
    let mut stats = PcgStats {
        iterations: 0,
        initial_error: e0,
        error: e0,
        relative_residual: rel0,
        converged: done(e0, rel0),
    };
    if stats.converged {
        return stats;
    }
    if s.krylov == Krylov::ConjugateResidual {
        conjugate_residual(sys, lists, x, &mut r, s, &mut scratch, |r, it| {
            stats.iterations = it;
            stats.error = error_of(sys, r, s.dt, n_unknown);
            stats.relative_residual = rel(r);
            stats.converged = done(stats.error, stats.relative_residual);
            stats.converged
        });
        return stats;
    }
    let mut q = vec![0.0f32; n];
    let mut z = vec![0.0f32; n];
    sys.precondition(lists, s.kind, s.omega, s.block, &r, &mut z);
    let mut d = z.clone();
    let mut rz = dot(&r, &z);
    for it in 1..=s.max_iterations {
        sys.apply_with(lists, &d, &mut q, &mut scratch);
        let dq = dot(&d, &q);
        if dq.is_nan() || dq <= 0.0 || !rz.is_finite() {
            break;
        }
        let alpha = rz / dq;
        x.par_chunks_mut(ROWS)
            .zip(r.par_chunks_mut(ROWS))
            .zip(d.par_chunks(ROWS).zip(q.par_chunks(ROWS)))
            .for_each(|((x, r), (d, q))| {
                let a = alpha as f32;
                for k in 0..x.len() {
                    x[k] += alpha * d[k] as f64;
                    r[k] -= a * q[k];
                }
            });
        stats.iterations = it;
        stats.error = error_of(sys, &r, s.dt, n_unknown);
        stats.relative_residual = rel(&r);
        if done(stats.error, stats.relative_residual) {
            stats.converged = true;
            break;
        }
        sys.precondition(lists, s.kind, s.omega, s.block, &r, &mut z);
        let rz_new = dot(&r, &z);
        let beta = (rz_new / rz) as f32;
        rz = rz_new;
        d.par_iter_mut()
            .zip(z.par_iter())
            .for_each(|(d, &z)| *d = z + beta * *d);
    }
    stats
}

/// Preconditioned conjugate residuals (Saad 2003, Alg. 6.20 with a symmetric positive
/// preconditioner M): one operator application `A z` and one preconditioner application
/// `M⁻¹ A d` per iteration; `A d` follows by recurrence. Each iterate minimises
/// `‖M⁻¹ r‖_M` over the Krylov space, so the residual falls monotonically (CG's rose and
/// stalled). `stop(r, it)` is called after every update of `x` and `r`.
fn conjugate_residual(
    sys: &PoissonSystem,
    lists: &NeighborLists,
    x: &mut [f64],
    r: &mut [f32],
    s: PcgSettings,
    scratch: &mut Scratch,
    mut stop: impl FnMut(&[f32], u32) -> bool,
) {
    let n = x.len();
    let mut z = vec![0.0f32; n];
    sys.precondition(lists, s.kind, s.omega, s.block, r, &mut z);
    let mut az = vec![0.0f32; n];
    sys.apply_with(lists, &z, &mut az, scratch);
    let mut d = z.clone();
    let mut ad = az.clone();
    let mut mad = vec![0.0f32; n];
    let mut zaz = dot(&z, &az);
    for it in 1..=s.max_iterations {
        sys.precondition(lists, s.kind, s.omega, s.block, &ad, &mut mad);
        let den = dot(&ad, &mad);
        if den.is_nan() || den <= 0.0 || !zaz.is_finite() {
            break;
        }
        let alpha = zaz / den;
        x.par_chunks_mut(ROWS)
            .zip(r.par_chunks_mut(ROWS))
            .zip(z.par_chunks_mut(ROWS))
            .zip(
                d.par_chunks(ROWS)
                    .zip(ad.par_chunks(ROWS))
                    .zip(mad.par_chunks(ROWS)),
            )
            .for_each(|(((x, r), z), ((d, ad), mad))| {
                let a = alpha as f32;
                for k in 0..x.len() {
                    x[k] += alpha * d[k] as f64;
                    r[k] -= a * ad[k];
                    z[k] -= a * mad[k];
                }
            });
        if stop(r, it) {
            break;
        }
        sys.apply_with(lists, &z, &mut az, scratch);
        let zaz_new = dot(&z, &az);
        let beta = (zaz_new / zaz) as f32;
        zaz = zaz_new;
        d.par_chunks_mut(ROWS)
            .zip(ad.par_chunks_mut(ROWS))
            .zip(z.par_chunks(ROWS).zip(az.par_chunks(ROWS)))
            .for_each(|((d, ad), (z, az))| {
                for k in 0..d.len() {
                    d[k] = z[k] + beta * d[k];
                    ad[k] = az[k] + beta * ad[k];
                }
            });
    }
}
