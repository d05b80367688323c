//! [`FluidParams::validate`]: every parameter checked against its range, the first invalid
//! one reported by name.

use super::FluidParams;
use crate::error::{positive, FluidError, Result};
use crate::limits::MAX_ITERATIONS;

impl FluidParams {
    /// Checks every parameter; the first invalid one is reported.
    pub fn validate(&self) -> Result<()> {
        positive("spacing", self.spacing as f64)?;
        positive("rest_density", self.rest_density as f64)?;
        positive(
            "density_error_tolerance",
            self.density_error_tolerance as f64,
        )?;
        positive("max_cfl", self.max_cfl as f64)?;
        positive("body_force_limit", self.body_force_limit as f64)?;
        within(
            "max_loop_spring",
            self.max_loop_spring,
            0.5,
            8.0,
            "[0.5, 8]",
        )?;
        within("support_factor", self.support_factor, 1.5, 4.0, "[1.5, 4]")?;
        within("xsph", self.xsph, 0.0, 1.0, "[0, 1]")?;
        if !(self.viscosity.is_finite() && self.viscosity >= 0.0) {
            return Err(FluidError::OutOfRange {
                name: "viscosity",
                value: self.viscosity as f64,
                range: ">= 0",
            });
        }
        if !(self.relative_residual.is_finite()
            && self.relative_residual > 0.0
            && self.relative_residual < 1.0)
        {
            return Err(FluidError::OutOfRange {
                name: "relative_residual",
                value: self.relative_residual as f64,
                range: "(0, 1)",
            });
        }
        if !(self.ssor_omega > 0.0 && self.ssor_omega < 2.0) {
            return Err(FluidError::OutOfRange {
                name: "ssor_omega",
                value: self.ssor_omega as f64,
                range: "(0, 2)",
            });
        }
        if self.ssor_block == 0 {
            return Err(FluidError::OutOfRange {
                name: "ssor_block",
                value: 0.0,
                range: ">= 1",
            });
        }
        for (name, v, lo) in [
            ("max_pcg_iterations", self.max_pcg_iterations, 1),
            ("density_iterations", self.density_iterations, 0),
            ("max_density_iterations", self.max_density_iterations, 0),
            ("drift_iterations", self.drift_iterations, 0),
            ("max_pcisph_iterations", self.max_pcisph_iterations, 1),
        ] {
            if !(lo..=MAX_ITERATIONS).contains(&v) {
                return Err(FluidError::OutOfRange {
                    name,
                    value: v as f64,
                    range: if lo == 0 {
                        "[0, 10000] (params::MAX_ITERATIONS)"
                    } else {
                        "[1, 10000] (params::MAX_ITERATIONS)"
                    },
                });
            }
        }
        for (name, v) in [
            ("density_mean_tolerance", self.density_mean_tolerance),
            ("density_max_tolerance", self.density_max_tolerance),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1.0) {
                return Err(FluidError::OutOfRange {
                    name,
                    value: v as f64,
                    range: "(0, 1)",
                });
            }
        }
        if !(self.density_memory.is_finite() && (0.0..1.0).contains(&self.density_memory)) {
            return Err(FluidError::OutOfRange {
                name: "density_memory",
                value: self.density_memory as f64,
                range: "[0, 1)",
            });
        }
        if !(self.density_relaxation > 0.0 && self.density_relaxation <= 1.0) {
            return Err(FluidError::OutOfRange {
                name: "density_relaxation",
                value: self.density_relaxation as f64,
                range: "(0, 1]",
            });
        }
        for (name, v) in [
            ("surface_asymmetry", self.surface_asymmetry),
            ("surface_density", self.surface_density),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1.0) {
                return Err(FluidError::OutOfRange {
                    name,
                    value: v as f64,
                    range: "(0, 1)",
                });
            }
        }
        within("neighbor_skin", self.neighbor_skin, 0.0, 1.0, "[0, 1]")?;
        within(
            "max_lost_fraction",
            self.max_lost_fraction,
            0.0,
            1.0,
            "[0, 1]",
        )?;
        positive("max_speed", self.max_speed as f64)?;
        positive("max_energy_gain", self.max_energy_gain as f64)?;
        if !(self.domain_margin.is_finite() && self.domain_margin >= 0.0) {
            return Err(FluidError::OutOfRange {
                name: "domain_margin",
                value: self.domain_margin as f64,
                range: ">= 0",
            });
        }
        if let Some((lo, hi)) = self.domain {
            for k in 0..3 {
                if !(lo[k].is_finite() && hi[k].is_finite() && hi[k] > lo[k]) {
                    return Err(FluidError::NonFinite {
                        what: format!("domain {lo:?}..{hi:?} (must be finite with maxs > mins)"),
                    });
                }
            }
        }
        Ok(())
    }
}

/// `Err(OutOfRange)` naming `name` unless `value` is finite and within `[lo, hi]` (`range` is
/// how the error states the interval).
fn within(name: &'static str, value: f32, lo: f32, hi: f32, range: &'static str) -> Result<()> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(FluidError::OutOfRange {
            name,
            value: value as f64,
            range,
        })
    }
}
