//! The SPH smoothing kernel (He 2012 Eq. 6): the 3-D cubic B-spline with compact support `h`.
//!
//! One kernel is used everywhere (density, pressure forces, staggered gradients, viscosity).

/// Cubic B-spline kernel in 3-D with support radius `h` (smoothing length `h/2`).
///
/// ```
/// use staggered_fluid::internals::CubicSpline;
/// let k = CubicSpline::new(0.04);
/// assert!(k.w(0.0) > k.w(0.02));
/// assert_eq!(k.w(0.04), 0.0);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicSpline {
    h: f32,
    inv_hs: f32,
    sigma: f32,
}

impl CubicSpline {
    /// Kernel with support radius `h` (> 0).
    pub fn new(h: f32) -> Self {
        let hs = 0.5 * h;
        Self {
            h,
            inv_hs: 1.0 / hs,
            sigma: 1.0 / (std::f32::consts::PI * hs * hs * hs),
        }
    }

    /// Support radius.
    #[inline]
    pub fn support(&self) -> f32 {
        self.h
    }

    /// W(r), Eq. 6: `σ/4 [(2 − q)₊³ − 4 (1 − q)₊³]`, `q = 2r/h`, written without branches (the
    /// two-piece form mispredicted on about every other neighbour pair).
    #[inline]
    pub fn w(&self, r: f32) -> f32 {
        let q = r * self.inv_hs;
        let t2 = (2.0 - q).max(0.0);
        let t1 = (1.0 - q).max(0.0);
        0.25 * self.sigma * (t2 * t2 * t2 - 4.0 * t1 * t1 * t1)
    }

    /// dW/dr (≤ 0): `−3σ/(4 h/2) [(2 − q)₊² − 4 (1 − q)₊²]`. The gradient is
    /// `∇_i W(|x_i − x_j|) = dW/dr · (x_i − x_j)/r`.
    #[inline]
    pub fn dw(&self, r: f32) -> f32 {
        let q = r * self.inv_hs;
        let t2 = (2.0 - q).max(0.0);
        let t1 = (1.0 - q).max(0.0);
        -0.75 * self.sigma * self.inv_hs * (t2 * t2 - 4.0 * t1 * t1)
    }

    /// `|dW/dr|`, the magnitude used by the directional derivatives of Eqs. 10–13 and 23.
    #[inline]
    pub fn grad_mag(&self, r: f32) -> f32 {
        -self.dw(r)
    }

    /// Analytic Laplacian ∇²W = W'' + (2/r) W' (3-D).
    ///
    /// The cubic spline's Laplacian changes sign inside `r < h/3`, which makes Eq. 24 with the
    /// analytic ∇²W anti-diffusive for close pairs; the viscous force therefore uses
    /// [`CubicSpline::viscous_laplacian`] (see ARCHITECTURE.md).
    pub fn laplacian(&self, r: f32) -> f32 {
        let q = r * self.inv_hs;
        let s2 = self.sigma * self.inv_hs * self.inv_hs;
        let d2 = if q < 1.0 {
            s2 * (-3.0 + 4.5 * q)
        } else if q < 2.0 {
            1.5 * s2 * (2.0 - q)
        } else {
            0.0
        };
        if r <= 0.0 {
            // limit of W'' + 2W'/r at r → 0: -3 s2 + 2·(-3 s2) = -9 s2
            return -9.0 * s2;
        }
        d2 + 2.0 * self.dw(r) / r
    }

    /// Positive Laplacian weight `2|W'(r)|/r` (Brookshaw 1985 / Morris et al. 1997) that stands
    /// for ∇²W in the generalized viscous force (Eq. 24): `∇²v_i ≈ Σ V_j (v_j − v_i) 2|W'|/r`.
    #[inline]
    pub fn viscous_laplacian(&self, r: f32) -> f32 {
        if r <= 1e-12 {
            0.0
        } else {
            2.0 * self.grad_mag(r) / r
        }
    }

    /// Distances from the origin to every other point of a simple cubic lattice of spacing `dx`
    /// that lies inside the support (the rest neighbourhood of a carrier).
    fn lattice_distances(&self, dx: f32) -> impl Iterator<Item = f32> + '_ {
        let n = (self.h / dx).ceil() as i32 + 1;
        (-n..=n)
            .flat_map(move |i| (-n..=n).flat_map(move |j| (-n..=n).map(move |k| (i, j, k))))
            .map(move |(i, j, k)| dx * ((i * i + j * j + k * k) as f32).sqrt())
            .filter(move |&r| r > 0.0 && r < self.h)
    }

    /// Sum of W over a simple cubic lattice of spacing `dx` (self included), times `dx³`.
    /// Equals 1 for an exactly normalised kernel on an infinitely fine lattice; the density
    /// estimate divides by it so that a rest lattice has exactly the rest density.
    pub fn lattice_sum(&self, dx: f32) -> f32 {
        let s = self.w(0.0) as f64
            + self
                .lattice_distances(dx)
                .map(|r| self.w(r) as f64)
                .sum::<f64>();
        (s * (dx as f64).powi(3)) as f32
    }

    /// A carrier of a flat rest surface on the simple cubic lattice of spacing `dx` (the
    /// lattice points at or below its height): the share of [`CubicSpline::lattice_sum`] its
    /// missing upper layers would add, and its Eq. 25 asymmetry `|Σ_j (x_j − x_i) W_ij| /
    /// Σ_j W_ij` (self in the sum of weights), in metres.
    pub fn surface_deficit_and_asymmetry(&self, dx: f32) -> (f32, f32) {
        let n = (self.h / dx).ceil() as i32 + 1;
        let (mut below, mut all, mut moment) = (self.w(0.0) as f64, self.w(0.0) as f64, 0.0f64);
        for i in -n..=n {
            for j in -n..=n {
                for k in -n..=n {
                    if (i, j, k) == (0, 0, 0) {
                        continue;
                    }
                    let w = self.w(dx * ((i * i + j * j + k * k) as f32).sqrt()) as f64;
                    all += w;
                    if j <= 0 {
                        below += w;
                        moment += w * (j as f64) * dx as f64;
                    }
                }
            }
        }
        ((1.0 - below / all) as f32, (moment.abs() / below) as f32)
    }

    /// PCISPH-style sum `Σ_j |∇W_ij|²` and neighbour count over a full rest lattice
    /// (self excluded), used by the density-constraint stiffness and the static-solid share.
    pub fn lattice_grad_sq_and_count(&self, dx: f32) -> (f32, u32) {
        let (s, c) = self
            .lattice_distances(dx)
            .fold((0.0f64, 0u32), |(s, c), r| {
                let g = self.grad_mag(r) as f64;
                (s + g * g, c + 1)
            });
        (s as f32, c)
    }

    /// `Σ_j |∇W(r_j/2)| r_j` over a full rest lattice of spacing `dx` (self excluded): the
    /// first moment of the staggered-particle gradient weight of Eqs. 10–13, used to normalise
    /// the staggered divergence so that `∇·x = 3` on a rest lattice.
    pub fn lattice_half_grad_moment(&self, dx: f32) -> f32 {
        self.lattice_distances(dx)
            .map(|r| (self.grad_mag(0.5 * r) * r) as f64)
            .sum::<f64>() as f32
    }
}
