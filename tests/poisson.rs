//! The velocity-constraint systems (the consistent operator and He 2012 Eq. 13) are symmetric
//! positive semi-definite and PCG reaches the requested tolerance.
#![allow(clippy::needless_range_loop)] // index loops read as matrix algebra here
use staggered_fluid::internals::pcg::{self, PcgSettings};
use staggered_fluid::prelude::*;
use staggered_fluid::{Krylov, Remap};

/// A column with a sideways velocity in a tank, stepped `steps` times: a non-trivial,
/// non-lattice configuration. Returns the world and the last step's report.
fn sloshing_world(params: FluidParams, steps: usize) -> (FluidWorld, StepReport) {
    let mut w = FluidWorld::new(FluidParams {
        spacing: 0.02,
        ..params
    })
    .unwrap();
    w.add_open_tank(Vector::ZERO, Vector::new(0.3, 0.4, 0.2), Slip::FreeSlip)
        .unwrap();
    w.add_block(
        Vector::ZERO,
        Vector::new(0.14, 0.24, 0.2),
        Vector::new(0.5, 0.0, 0.0),
    )
    .unwrap();
    let mut r = StepReport::default();
    for _ in 0..steps {
        r = w.step(Vector::new(0.0, -9.81, 0.0), 0.002).unwrap();
    }
    (w, r)
}

/// x·Ax ≥ 0 on a few pseudo-random vectors.
fn assert_psd(a: &[Vec<f64>]) {
    let n = a.len();
    for s in 0..5u64 {
        let x: Vec<f64> = (0..n)
            .map(|i| (((i as u64 * 2654435761 + s * 97) % 1000) as f64 / 500.0) - 1.0)
            .collect();
        let q: f64 = (0..n)
            .map(|r| x[r] * (0..n).map(|c| a[r][c] * x[c]).sum::<f64>())
            .sum();
        assert!(q >= 0.0, "xᵀAx = {q}");
    }
}

#[test]
fn consistent_operator_is_symmetric_positive_and_matches_its_diagonal() {
    let p = FluidParams {
        density_error_tolerance: 1e-4,
        relative_residual: 1e-3,
        ..Default::default()
    };
    assert_eq!(p.remap, Remap::Consistent);
    let (w, _) = sloshing_world(p, 10);
    let sys = w.poisson_system();
    let (idx, a) = sys.to_dense(w.neighbor_lists());
    assert!(
        idx.len() > 500,
        "needs a real system ({} unknowns)",
        idx.len()
    );
    let scale = idx.iter().map(|&i| sys.adj_diag[i]).fold(0.0, f64::max);
    for r in 0..idx.len() {
        // D M⁻¹ Dᵀ: symmetric up to rounding, positive diagonal equal to the Jacobi diagonal
        assert!((a[r][r] - sys.adj_diag[idx[r]]).abs() < 1e-5 * scale);
        assert!(a[r][r] > 0.0);
        for c in 0..r {
            assert!(
                (a[r][c] - a[c][r]).abs() < 1e-6 * scale,
                "A[{r}][{c}] = {} vs {}",
                a[r][c],
                a[c][r]
            );
        }
    }
    assert_psd(&a);
}

#[test]
fn poisson_matrix_is_symmetric_and_diagonally_dominant() {
    // Eq. 13 as assembled for the approximate-projection remaps (and the SSOR preconditioner)
    let p = FluidParams {
        density_error_tolerance: 1e-4,
        relative_residual: 1e-3,
        remap: Remap::Paper,
        ..Default::default()
    };
    let (w, _) = sloshing_world(p, 10);
    let (idx, a) = w.poisson_system().to_dense(w.neighbor_lists());
    assert!(
        idx.len() > 500,
        "needs a real system ({} unknowns)",
        idx.len()
    );
    let mut offdiag = 0;
    for r in 0..idx.len() {
        let mut off = 0.0;
        for c in 0..idx.len() {
            assert_eq!(a[r][c], a[c][r], "A[{r}][{c}] != A[{c}][{r}]");
            if r != c {
                assert!(a[r][c] <= 0.0);
                off += a[r][c].abs();
                offdiag += (a[r][c] != 0.0) as usize;
            }
        }
        // weighted graph Laplacian with Dirichlet rows: diagonally dominant ⇒ PSD (Gershgorin)
        assert!(
            a[r][r] >= off * (1.0 - 1e-6),
            "row {r}: diag {} < {off}",
            a[r][r]
        );
    }
    assert!(offdiag > 10 * idx.len());
    assert_psd(&a);
}

#[test]
fn pcg_reaches_the_requested_tolerance() {
    for (pre, krylov) in [
        (Preconditioner::BlockSsor, Krylov::ConjugateGradient),
        (Preconditioner::Jacobi, Krylov::ConjugateGradient),
        (Preconditioner::None, Krylov::ConjugateGradient),
        (Preconditioner::BlockSsor, Krylov::ConjugateResidual),
        (Preconditioner::Jacobi, Krylov::ConjugateResidual),
        (Preconditioner::None, Krylov::ConjugateResidual),
    ] {
        let p = FluidParams {
            krylov,
            density_error_tolerance: 1e-5,
            relative_residual: 1e-4,
            preconditioner: pre,
            max_pcg_iterations: 2000,
            ..Default::default()
        };
        let (w, r) = sloshing_world(p, 1);
        assert!(
            r.converged,
            "{pre:?} {krylov:?}: not converged after {} iterations",
            r.pcg_iterations
        );
        assert!(
            r.pcg_iterations > 0,
            "{pre:?} {krylov:?}: the solve must do work"
        );
        // recompute the residual independently: E = Δt² mean |b − A p|
        let sys = w.poisson_system();
        let lists = w.neighbor_lists();
        let p: Vec<f64> = w.fluid().p_velocity.iter().map(|&v| v as f64).collect();
        let mut ap = vec![0.0; p.len()];
        sys.apply(lists, &p, &mut ap);
        let n_unknown = sys.unknown.iter().filter(|&&u| u).count();
        let e: f64 = (0..p.len())
            .filter(|&i| sys.unknown[i])
            .map(|i| (sys.rhs[i] - ap[i]).abs() * sys.error_scale)
            .sum::<f64>()
            * 0.002f64.powi(2)
            / n_unknown as f64;
        // p^v is stored in f32, so allow its rounding on top of the tolerance
        assert!(
            e <= 1e-5 * 1.5 + 1e-7,
            "{pre:?} {krylov:?}: recomputed E {e}"
        );
    }
}

/// Conjugate residuals minimise the residual over the Krylov space: unpreconditioned, its
/// 2-norm never rises from one iteration to the next and is never above CG's after as many
/// iterations from the same start, and run to a tight tolerance both methods find the same
/// pressure.
#[test]
fn conjugate_residuals_never_raise_the_residual_and_agree_with_cg() {
    let (w, _) = sloshing_world(FluidParams::default(), 5);
    let sys = w.poisson_system();
    let lists = w.neighbor_lists();
    let n = sys.unknown.len();
    // a solve from p = 0; only ‖r‖/‖b‖ stops it (E is not what this test is about)
    let run = |krylov, kind, rr: f64, max| {
        let mut x = vec![0.0; n];
        let settings = PcgSettings {
            kind,
            krylov,
            omega: 1.0,
            block: 256,
            tolerance: 1.0,
            relative_residual: rr,
            max_iterations: max,
            dt: 0.002,
        };
        (pcg::solve(sys, lists, &mut x, settings), x)
    };
    let mut last = 1.0;
    let mut below = 0;
    for it in 1..=40 {
        let (s, _) = run(Krylov::ConjugateResidual, Preconditioner::None, 0.0, it);
        assert_eq!(s.iterations, it);
        assert!(
            s.relative_residual <= last * (1.0 + 1e-9),
            "CR residual rose at iteration {it}: {last} -> {}",
            s.relative_residual
        );
        last = s.relative_residual;
        let (c, _) = run(Krylov::ConjugateGradient, Preconditioner::None, 0.0, it);
        // both search the same Krylov space; CR takes its smallest residual
        assert!(
            s.relative_residual <= c.relative_residual * (1.0 + 1e-6),
            "iteration {it}: CR {} above CG {}",
            s.relative_residual,
            c.relative_residual
        );
        below += (s.relative_residual < 0.99 * c.relative_residual) as u32;
    }
    assert!(last < 0.05, "40 CR iterations left ‖r‖/‖b‖ = {last}");
    assert!(
        below >= 10,
        "CR clearly below CG at only {below} of 40 iterations"
    );

    // 1e-6: the Krylov vectors are stored in f32 (sums in f64), so the residual bottoms out
    // near 1e-7; five orders below the default 0.1
    let solve = |krylov| {
        let (s, x) = run(krylov, Preconditioner::Jacobi, 1e-6, 5000);
        assert!(s.converged, "{krylov:?} did not converge: {s:?}");
        x
    };
    let (a, b) = (
        solve(Krylov::ConjugateResidual),
        solve(Krylov::ConjugateGradient),
    );
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(scale > 1.0, "a real pressure field (max {scale} Pa)");
    // the same pressure as far as the tolerance can tell: both residuals, recomputed here, at
    // the 1e-6 asked (plus the f32 rounding of stored vectors), so their difference's residual
    // is at most twice that (the difference itself scales with the system's condition number)
    let norm = |v: &[f64]| {
        (0..n)
            .filter(|&i| sys.unknown[i])
            .map(|i| v[i] * v[i])
            .sum::<f64>()
            .sqrt()
    };
    let residual = |x: &[f64]| {
        let mut ax = vec![0.0; n];
        sys.apply(lists, x, &mut ax);
        let r: Vec<f64> = (0..n).map(|i| sys.rhs[i] - ax[i]).collect();
        norm(&r) / norm(&sys.rhs)
    };
    let (ra, rb) = (residual(&a), residual(&b));
    let d: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x - y).collect();
    let mut ad = vec![0.0; n];
    sys.apply(lists, &d, &mut ad);
    let rd = norm(&ad) / norm(&sys.rhs);
    let diff = d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    println!("residuals CR {ra:.2e}, CG {rb:.2e}, of the difference {rd:.2e}; max |Δp| {diff:.3} Pa of {scale:.0}");
    assert!(ra <= 2e-6 && rb <= 2e-6, "residuals CR {ra}, CG {rb}");
    assert!(
        rd <= 4e-6,
        "CR and CG differ by a residual {rd} (max {diff} Pa of {scale})"
    );
}
