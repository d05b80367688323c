//! The Poisson operator of the velocity constraint: the assembled system `A p = b` (Eq. 13, or
//! the consistent `D M⁻¹ Dᵀ` of [`super::velocity`]) stored along the neighbour lists, and its
//! matrix-free application (the staggered divergence `D` and its adjoint, the pressure force
//! `Dᵀ`), which the Krylov solves of [`super::pcg`] call.

use super::weights::{unpack, Packed};
use crate::math::Vector;
use crate::neighbors::NeighborLists;
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
    /// If true, A is the consistent operator `D M⁻¹ Dᵀ` of `solver::velocity`,
    /// applied matrix-free; `coef`/`diag` (Eq. 13) then only serve the SSOR preconditioner.
    pub adjoint: bool,
    /// Per-slot corrected divergence weight `α_ij L_i e_ij` (fluid) or `ê_is` (solid), in
    /// 16-bit fixed point (see `solver::weights`); times `weight_scale[i]` of its row.
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
    pub(crate) fn apply_with<X: Real, Y: Real>(
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
            pressure_force(self, lists, p, &sc.ps, inv_m, &mut sc.g);
            divergence(self, lists, &sc.g, y);
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
}

/// Buffers of the matrix-free operator, kept across the iterations of one solve.
#[derive(Default)]
pub(crate) struct Scratch {
    /// The operand in f32 (when it is f64).
    p: Vec<f32>,
    /// The operand times each row's weight scale.
    ps: Vec<f32>,
    /// `M⁻¹ Dᵀ p`.
    g: Vec<Vector>,
}

/// `F = Dᵀ p` on every fluid carrier (p is zero on surface carriers), times `scale`:
/// `F_k = −p_k (L_k Σ_j α_kj e_kj + Σ_s ê_ks) − Σ_j p_j (1 − α_kj) L_j e_kj`, with the wall
/// weights `ê_ks = n_s n_s·(L_k ẽ_ks)` stored already corrected and the bracket precomputed per
/// carrier (`PoissonSystem::own`). `ps` is p times each carrier's weight scale (see
/// [`neighbour_push`]).
pub(crate) fn pressure_force(
    sys: &PoissonSystem,
    lists: &NeighborLists,
    p: &[f32],
    ps: &[f32],
    scale: f32,
    f: &mut [Vector],
) {
    f.par_iter_mut().enumerate().for_each(|(k, fk)| {
        *fk = (-(sys.own[k] * p[k]) - neighbour_push(sys, lists, k, |j| ps[j])) * scale;
    });
}

/// `Σ_j p_j (1 − α_kj) L_j e_kj` of carrier k: the push of its fluid neighbours' pressures.
/// The stored `q_kj` are the integers of `−ec_jk`, in row j's scale, so `ps(j)` must return
/// `p_j` times `weight_scale[j]`.
#[inline]
pub(crate) fn neighbour_push(
    sys: &PoissonSystem,
    lists: &NeighborLists,
    k: usize,
    ps: impl Fn(usize) -> f32,
) -> Vector {
    let r = lists.fluid_range(k);
    let mut n = Vector::ZERO;
    for (q, &j) in sys.q[r.clone()].iter().zip(&lists.indices[r]) {
        n += unpack(*q) * ps(j as usize);
    }
    n
}

/// `y = D g` on unknown rows for carrier velocities `g` (solids at rest: the homogeneous
/// operator). Each row sums its ≈ 30 terms in f32 and hands the sum on in f64.
///
/// `s_i Σ_j ec_ij·(g_j − g_i) − wall_i·g_i` is summed as `s_i Σ_j ec_ij·g_j − own_i·g_i`:
/// `own_i` is the row's stored weight sum the pressure force uses too, so `D` stays the exact
/// adjoint of [`pressure_force`], and the pair loop does three operations fewer (solve
/// −14 %). The right-hand side keeps the difference form, where a fast uniform flow would
/// otherwise cancel to round-off of the size of the divergence a step must remove.
pub(crate) fn divergence<Y: Real>(
    sys: &PoissonSystem,
    lists: &NeighborLists,
    g: &[Vector],
    y: &mut [Y],
) {
    y.par_iter_mut().enumerate().for_each(|(i, yi)| {
        if !sys.unknown[i] {
            *yi = Y::of(0.0);
            return;
        }
        let r = lists.fluid_range(i);
        let mut s = 0.0f32;
        for (e, &j) in sys.ec[r.clone()].iter().zip(&lists.indices[r]) {
            s += unpack(*e).dot(g[j as usize]);
        }
        *yi = Y::of((s * sys.weight_scale[i] - sys.own[i].dot(g[i])) as f64);
    });
}
