//! Krylov solve of the velocity constraint (He 2012 §6–7.1): preconditioned conjugate residuals
//! by default, the paper's preconditioned conjugate gradients as an option, both stopping on
//! the incompressibility error E of Eq. 29 and on the relative residual.

pub use super::system::{PoissonSystem, RigidLink};
use super::system::{Real, Scratch};
use super::{det_sum, ROWS};
use crate::neighbors::NeighborLists;
use crate::params::{Krylov, Preconditioner};
use rayon::prelude::*;

impl PoissonSystem {
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
