//! Heat (Shao et al. 2014 §3.4.2, Eq. 20): temperatures carried by fluid carriers and by the
//! lattice points of melting bodies, exchanged by implicit diffusion.
//!
//! Every particle stands for one lattice cell `Δx³` of material, and every material holds the
//! same heat per volume and degree (Shao's model has neither heat capacity nor latent heat),
//! so the heat the exchange conserves is the sum of the temperatures. A conductivity `K` is the
//! diffusivity of `∂T/∂t = ∇·(K ∇T)`, m²/s; a pair of particles exchanges with the mean
//! `(K_i + K_j)/2` (Eq. 20 writes the sum; halved, a uniform material diffuses at its own `K`).

use crate::deform::lattice::Rows;
use crate::error::Result;
use crate::kernel::CubicSpline;
use serde::{Deserialize, Serialize};

/// The fluid's heat: the temperature carriers are made at and the water's conductivity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FluidHeat {
    /// Temperature of the fluid (each carrier's when heat is switched on, and that of carriers
    /// made later), °C.
    pub temperature: f32,
    /// Heat conductivity K of the fluid, m²/s (≥ 0). 0 (the default; water's own, 1.4e-7
    /// m²/s, is as good as none at a game's scale) leaves heat to move between the fluid and
    /// the solids only, and with the flow.
    pub conductivity: f32,
}

impl Default for FluidHeat {
    /// Water at 20 °C that conducts no heat of its own.
    fn default() -> Self {
        FluidHeat {
            temperature: 20.0,
            conductivity: 0.0,
        }
    }
}

impl FluidHeat {
    pub(crate) fn validate(&self) -> Result<()> {
        finite_temperature("FluidHeat::temperature", self.temperature)?;
        check_conductivity("FluidHeat::conductivity", self.conductivity)
    }
}

/// A solid held at a fixed temperature — a hot plate, a heater, a cold wall — exchanging heat
/// with the fluid beside it ([`crate::FluidWorld::set_heat_source`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeatSource {
    /// Its temperature, °C.
    pub temperature: f32,
    /// Its heat conductivity K, m²/s (≥ 0).
    pub conductivity: f32,
}

impl HeatSource {
    pub(crate) fn validate(&self) -> Result<()> {
        finite_temperature("HeatSource::temperature", self.temperature)?;
        check_conductivity("HeatSource::conductivity", self.conductivity)
    }
}

/// A heat conductivity must be finite and not negative.
pub(crate) fn check_conductivity(name: &'static str, k: f32) -> Result<()> {
    if k.is_finite() && k >= 0.0 {
        Ok(())
    } else {
        Err(crate::error::FluidError::OutOfRange {
            name,
            value: k as f64,
            range: ">= 0 m²/s",
        })
    }
}

fn finite_temperature(name: &str, t: f32) -> Result<()> {
    if t.is_finite() {
        Ok(())
    } else {
        Err(crate::error::FluidError::NonFinite {
            what: format!("{name} ({t})"),
        })
    }
}

/// Largest Jacobi sweeps of one exchange.
const MAX_SWEEPS: u32 = 200;

/// A sweep's largest temperature change that ends the iteration, °C.
const TOLERANCE: f32 = 1e-4;

/// The implicit exchange of one step: per particle row the pairs `(j, a_ij)` with
/// `a_ij = Δt K_ij V F_ij` symmetric, and per row the fixed-temperature neighbours
/// (heat sources) as `(Σ a, Σ a T)`.
#[derive(Debug, Default)]
pub(crate) struct Exchange {
    pub pairs: Rows<(u32, f32)>,
    pub fixed: Vec<(f32, f32)>,
}

impl Exchange {
    fn row(&self, i: usize) -> &[(u32, f32)] {
        self.pairs.row(i)
    }

    /// Advances the temperatures `t` by the backward-Euler step of the exchange
    /// (`T' = T + Σ_j a_ij (T'_j − T'_i) + Σ_s a_is (T_s − T'_i)`, Eq. 20's implicit update),
    /// solved by Jacobi sweeps to [`TOLERANCE`], then applied as fluxes between pairs: each
    /// pair's `a_ij (T'_j − T'_i)` leaves one particle and enters the other, so the sum of
    /// the temperatures is kept whatever the sweeps reached (Shao's two ordered sweeps after
    /// [DGP12] are sequential; Jacobi sweeps run in parallel and the same on any thread
    /// count). Returns the sweeps taken.
    pub fn apply(&self, t: &mut [f32]) -> u32 {
        use rayon::prelude::*;
        let n = t.len();
        let t0 = t.to_vec();
        let mut cur = t0.clone();
        let mut next = vec![0.0f32; n];
        let mut sweeps = 0;
        while sweeps < MAX_SWEEPS {
            sweeps += 1;
            let change = next
                .par_iter_mut()
                .enumerate()
                .map(|(i, out)| {
                    let (mut num, mut den) = (t0[i] as f64, 1.0f64);
                    for &(j, a) in self.row(i) {
                        num += a as f64 * cur[j as usize] as f64;
                        den += a as f64;
                    }
                    let (fa, fat) = self.fixed[i];
                    num += fat as f64;
                    den += fa as f64;
                    *out = (num / den) as f32;
                    (*out - cur[i]).abs()
                })
                .reduce(|| 0.0, f32::max);
            std::mem::swap(&mut cur, &mut next);
            if change < TOLERANCE {
                break;
            }
        }
        t.par_iter_mut().enumerate().for_each(|(i, ti)| {
            let mut q = 0.0f64;
            for &(j, a) in self.row(i) {
                q += a as f64 * (cur[j as usize] - cur[i]) as f64;
            }
            let (fa, fat) = self.fixed[i];
            q += fat as f64 - fa as f64 * cur[i] as f64;
            *ti = (t0[i] as f64 + q) as f32;
        });
        sweeps
    }
}

/// `F(r) = 2 |∇W(r)| / r` (Brookshaw's Laplacian, `∇²T_i ≈ Σ_j V_j F_ij (T_j − T_i)`),
/// normalised so that it is exact for a quadratic temperature on the cubic lattice of spacing
/// `dx` (the cubic spline's form falls short there by a few per cent).
pub(crate) struct Laplacian {
    kernel: CubicSpline,
    scale: f32,
}

impl Laplacian {
    pub fn new(kernel: CubicSpline, dx: f32) -> Self {
        // Σ_j V F(r_j) x_j² / 2 over the lattice is 1 for an exact Laplacian
        let reach = (kernel.support() / dx).ceil() as i32;
        let mut sum = 0.0f64;
        for a in -reach..=reach {
            for b in -reach..=reach {
                for c in -reach..=reach {
                    let d = crate::math::Vector::new(a as f32, b as f32, c as f32) * dx;
                    let r = d.length();
                    if r > 0.0 && r < kernel.support() {
                        sum += (2.0 * kernel.grad_mag(r) / r * d.x * d.x) as f64;
                    }
                }
            }
        }
        Laplacian {
            kernel,
            scale: (2.0 / sum) as f32,
        }
    }

    /// `V F(r)` for a pair `r` apart.
    #[inline]
    pub fn weight(&self, r: f32) -> f32 {
        if r <= 1e-6 * self.kernel.support() {
            return 0.0;
        }
        self.scale * 2.0 * self.kernel.grad_mag(r) / r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vector;

    /// On a lattice, the normalised form gives ∇²(x²) = 2 and the exchange keeps the sum.
    #[test]
    fn lattice_laplacian_is_exact_for_a_quadratic_and_the_exchange_conserves() {
        let dx = 0.1;
        let lap = Laplacian::new(CubicSpline::new(2.0 * dx), dx);
        let mut s = 0.0;
        let mut pts = Vec::new();
        for a in -3..=3 {
            for b in -3..=3 {
                for c in -3..=3 {
                    let d = Vector::new(a as f32, b as f32, c as f32) * dx;
                    pts.push(d);
                    s += lap.weight(d.length()) * d.x * d.x;
                }
            }
        }
        assert!((s - 2.0).abs() < 1e-4, "∇²x² = {s}");
        // a hot point among cold ones: the implicit exchange spreads it, keeps the sum and
        // stays within the initial range (a maximum principle)
        let n = pts.len();
        let mut rows = vec![Vec::new(); n];
        let k = 1e-2;
        for i in 0..n {
            for j in 0..n {
                let w = lap.weight((pts[i] - pts[j]).length());
                if i != j && w > 0.0 {
                    rows[i].push((j as u32, 0.5 * k * w));
                }
            }
        }
        let ex = Exchange {
            pairs: Rows::from_rows(rows),
            fixed: vec![(0.0, 0.0); n],
        };
        let mut t = vec![0.0f32; n];
        t[n / 2] = 100.0;
        ex.apply(&mut t);
        let sum: f64 = t.iter().map(|&v| v as f64).sum();
        assert!((sum - 100.0).abs() < 1e-3, "sum {sum}");
        assert!(t.iter().all(|&v| (-1e-4..=100.0).contains(&v)));
        assert!(
            t[n / 2] < 90.0 && t[n / 2 + 1] > 0.1,
            "{} {}",
            t[n / 2],
            t[n / 2 + 1]
        );
    }
}
