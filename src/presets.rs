//! Ready-made parameter sets for kinds of use, each with its measured cost and error.

use crate::params::FluidParams;

impl FluidParams {
    /// These parameters with the settings for games at rapier's 1/60 s frames: water placed at
    /// rest starts hydrostatic ([`Self::hydrostatic_start`], as by default) and the density
    /// constraint's tolerances are five times looser (mean compression 0.5 %, largest 5 %;
    /// the defaults 0.1 % and 1 %), so a splash's frames take fewer substeps. Spacing, solver
    /// and everything else stay as given.
    ///
    /// Measured on the five balls at 1/60 s (Δx 2 cm; `BENCHMARKS.md`): 237 substeps in the
    /// first second against 268 with the defaults; over 2 s 7.6 against 9.0 wall seconds per
    /// simulated second (one run each; 9.3 against 9.1 in a slower hour: after the splash
    /// both take the body-force limit's 3 substeps a frame), the floating balls' drafts over
    /// 1–2 s −4.6 / −2.8 % of Archimedes against −4.5 / −4.0 %. What it gives up: water is held to 0.5 %
    /// instead of 0.1 %. (Before the hydrostatic start was the default, its start saved a
    /// third of the five balls' substeps.)
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
