//! Ready-made parameter sets for kinds of use, each with its measured cost and error.

use crate::params::FluidParams;

impl FluidParams {
    /// These parameters with the settings for games at rapier's 1/60 s frames: water placed at
    /// rest starts hydrostatic ([`Self::hydrostatic_start`]) and the density constraint's
    /// tolerances are five times looser (mean compression 0.5 %, largest 5 %; the defaults
    /// 0.1 % and 1 %), so a frame takes fewer substeps. Spacing, solver and everything else
    /// stay as given.
    ///
    /// Measured on the five balls at 1/60 s (Δx 2 cm, 2 s; `BENCHMARKS.md`): 3.48 substeps a
    /// frame against 5.36 with the defaults, the floating balls' drafts over 1–2 s −3.8 / −2.4
    /// % of Archimedes against −4.7 / −4.1 %, mean compression 0.076 % against 0.051 %. What it
    /// gives up: the Yettou wedge brakes 3.8 % off the measurement instead of 2.9 % (the
    /// hydrostatic start), and water is held to 0.5 % instead of 0.1 %.
    ///
    /// ```
    /// use staggered_fluid::FluidParams;
    /// let p = FluidParams { spacing: 0.05, ..Default::default() }.for_games();
    /// assert!(p.hydrostatic_start);
    /// assert_eq!(p.spacing, 0.05);
    /// assert_eq!(p.density_mean_tolerance, 0.005);
    /// ```
    pub fn for_games(self) -> Self {
        FluidParams {
            hydrostatic_start: true,
            density_mean_tolerance: 0.005,
            density_max_tolerance: 0.05,
            ..self
        }
    }
}
