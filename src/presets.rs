//! Ready-made parameter sets for kinds of use, each with its measured cost and error.

use crate::params::FluidParams;

impl FluidParams {
    /// These parameters with the settings for games at rapier's 1/60 s frames: water placed at
    /// rest starts hydrostatic ([`Self::hydrostatic_start`], as by default) and the density
    /// constraint's tolerances are five times looser (mean compression 0.5 %, largest 5 %;
    /// the defaults 0.1 % and 1 %), so each substep runs fewer density iterations and a
    /// splash's frames take fewer substeps. Spacing, solver and everything else stay as given.
    ///
    /// Measured on the five balls at 1/60 s (Δx 2 cm; `BENCHMARKS.md`, thirty-seventh
    /// session): about half the default's density iterations over the first second (617
    /// against 1158), two substeps a frame after the splash as by default. What it gives up:
    /// water held to 0.5 % instead of 0.1 %, and a longer step in a splash.
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
