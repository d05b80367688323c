//! The SPH kernel (He 2012 Eq. 6): normalisation, gradient antisymmetry, Laplacian.
use staggered_fluid::internals::CubicSpline;

#[test]
fn kernel_integrates_to_one() {
    let h = 0.04f32;
    let k = CubicSpline::new(h);
    // midpoint rule over the support ball, 80³ cells
    let n = 80;
    let d = 2.0 * h as f64 / n as f64;
    let mut s = 0.0f64;
    for i in 0..n {
        for j in 0..n {
            for l in 0..n {
                let p = |a: usize| -(h as f64) + (a as f64 + 0.5) * d;
                let r = (p(i).powi(2) + p(j).powi(2) + p(l).powi(2)).sqrt();
                s += k.w(r as f32) as f64 * d * d * d;
            }
        }
    }
    assert!((s - 1.0).abs() < 2e-3, "∫W dV = {s}");
}

#[test]
fn gradient_is_antisymmetric_and_matches_finite_differences() {
    let k = CubicSpline::new(0.04);
    for &r in &[0.001f32, 0.005, 0.013, 0.02, 0.027, 0.035, 0.039] {
        // ∇_i W(x_i − x_j) = W'(r) (x_i − x_j)/r: swapping i and j flips the sign exactly
        let e = [0.6f32, -0.48, 0.64];
        let gi: Vec<f32> = e.iter().map(|c| k.dw(r) * c).collect();
        let gj: Vec<f32> = e.iter().map(|c| k.dw(r) * -c).collect();
        for a in 0..3 {
            assert_eq!(gi[a], -gj[a]);
        }
        let eps = 1e-5f32;
        let fd = (k.w(r + eps) - k.w(r - eps)) / (2.0 * eps);
        assert!(
            (fd - k.dw(r)).abs() <= 2e-3 * k.dw(0.0133).abs(),
            "r {r}: fd {fd} vs {}",
            k.dw(r)
        );
        assert!(k.dw(r) <= 0.0);
    }
    assert_eq!(k.w(0.04), 0.0);
    assert_eq!(k.dw(0.041), 0.0);
}

#[test]
fn laplacian_matches_finite_differences() {
    let k = CubicSpline::new(0.04);
    for &r in &[0.004f32, 0.012, 0.02, 0.03] {
        let e = 1e-4f32;
        let d2 = (k.w(r + e) - 2.0 * k.w(r) + k.w(r - e)) / (e * e);
        let lap = d2 + 2.0 * k.dw(r) / r;
        assert!(
            (lap - k.laplacian(r)).abs() < 0.02 * k.laplacian(0.0).abs(),
            "r {r}: {lap} vs {}",
            k.laplacian(r)
        );
    }
}

#[test]
fn rest_lattice_sum_is_close_to_one() {
    let k = CubicSpline::new(0.04);
    let c = k.lattice_sum(0.02);
    assert!((c - 1.0).abs() < 0.05, "lattice sum {c}");
    let (_, n) = k.lattice_grad_sq_and_count(0.02);
    assert_eq!(n, 26);
}

/// The branch-free W equals the textbook two-piece cubic spline (Monaghan 1992) everywhere in
/// and beyond the support, including at the joints q = 1 and q = 2.
#[test]
fn branch_free_kernel_equals_the_piecewise_spline() {
    let h = 0.05f32;
    let k = CubicSpline::new(h);
    let hs = 0.5 * h;
    let sigma = 1.0 / (std::f32::consts::PI * hs * hs * hs);
    for i in 0..=300 {
        let r = h * 1.2 * i as f32 / 300.0;
        let q = r / hs;
        let want = if q < 1.0 {
            sigma * (1.0 - 1.5 * q * q + 0.75 * q * q * q)
        } else if q < 2.0 {
            sigma * 0.25 * (2.0 - q).powi(3)
        } else {
            0.0
        };
        assert!(
            (k.w(r) - want).abs() <= 1e-5 * sigma,
            "r = {r}: {} vs {want}",
            k.w(r)
        );
    }
}

/// The surface rest density's two kernel constants (`step/density.rs`, issue 18): a carrier
/// in the middle of a resting block's top layer reads `(1 − m) ρ̄` in the world's own density
/// sum, and its Eq. 25 asymmetry, summed here over the block, is `a`.
#[test]
fn a_flat_surface_carrier_lacks_the_kernel_share_of_its_missing_layers() {
    use staggered_fluid::prelude::*;
    let dx = 0.02f32;
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    };
    let k = CubicSpline::new(params.support_radius());
    let (m, a) = k.surface_deficit_and_asymmetry(dx);
    let mut w = FluidWorld::new(params).unwrap();
    w.add_block(Vector::ZERO, Vector::new(0.2, 0.12, 0.2), Vector::ZERO)
        .unwrap();
    // one microsecond: the densities at the block's lattice positions
    w.step(Vector::new(0.0, -9.81, 0.0), 1e-6).unwrap();
    let f = w.fluid();
    let top = f.x.iter().map(|x| x.y).fold(f32::MIN, f32::max);
    let centre = Vector::new(0.1, top, 0.1);
    let i = (0..f.len())
        .min_by(|&i, &j| {
            (f.x[i] - centre)
                .length()
                .total_cmp(&(f.x[j] - centre).length())
        })
        .unwrap();
    let rho = f.density[i] / 1000.0;
    // its asymmetry |Σ_j (x_j − x_i) W_ij| / Σ_j W_ij (self in the sum of weights)
    let (mut moment, mut wsum) = (Vector::ZERO, k.w(0.0));
    for x in &f.x {
        let d = *x - f.x[i];
        let wij = k.w(d.length());
        if d.length() > 0.0 {
            moment += d * wij;
            wsum += wij;
        }
    }
    let asym = moment.length() / wsum;
    println!(
        "m {m:.4}, ρ/ρ̄ {rho:.4}; a/Δx {:.4}, asymmetry/Δx {:.4}",
        a / dx,
        asym / dx
    );
    assert!(m > 0.05 && m < 0.3, "deficit {m}");
    assert!(
        (rho - (1.0 - m)).abs() < 2e-3,
        "ρ/ρ̄ {rho} vs 1 − m {}",
        1.0 - m
    );
    assert!((asym - a).abs() < 0.01 * dx, "asymmetry {asym} vs {a}");
}
