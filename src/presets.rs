//! Ready-made parameter sets for kinds of use, each with its measured cost and error.

use crate::params::FluidParams;

impl FluidParams {
    /// These parameters with the settings for games at rapier's 1/60 s frames: water placed at
    /// rest starts hydrostatic ([`Self::hydrostatic_start`], as by default), the density
    /// constraint's tolerances are five times looser (mean compression 0.5 %, largest 5 %;
    /// the defaults 0.1 % and 1 %), so a splash's frames take fewer substeps, and the
    /// substep may be longer: the body-force limit 0.2 √(Δx/|g|) instead of 0.15 and the
    /// density loop's spring up to μ = 4 instead of 2 ([`Self::max_loop_spring`]), so water
    /// 0.3 m deep at Δx 2 cm takes two substeps of a 1/60 s frame instead of three, each
    /// iteration relaxed further. Spacing, solver and everything else stay as given.
    ///
    /// Measured on the five balls at 1/60 s (Δx 2 cm, `rest_noise`; `BENCHMARKS.md`,
    /// thirty-sixth session, interleaved in one hour): 7.35–7.37 wall seconds per simulated
    /// second over 2 s against 8.5–9.3 with the looser tolerances alone and 10.3 with the
    /// defaults; two substeps a frame after the splash; the floating balls' drafts over 1–2 s
    /// −2.4 / −1.9 % of Archimedes (−2.0 / −1.6 % with the tolerances alone, −0.2 / −1.4 % by
    /// default); mean compression 0.12 % at 2 s. The still tank (0.3 m, Δx 2 cm) at 1/60 s:
    /// 3.1–3.2 wall s per simulated s against 3.7–3.8, level 2.3 mm lower, floor 0.998 of
    /// the weight. A world with deformable bodies keeps the default body-force limit (their
    /// stiffness is set against it). What it gives up: water held to 0.5 % instead of 0.1 %,
    /// half a point to two points of draft, and a longer step in a splash.
    ///
    /// ```
    /// use staggered_fluid::FluidParams;
    /// let p = FluidParams { spacing: 0.05, ..Default::default() }.for_games();
    /// assert!(p.hydrostatic_start);
    /// assert_eq!(p.spacing, 0.05);
    /// assert_eq!(p.density_mean_tolerance, 0.005);
    /// assert_eq!(p.max_loop_spring, 4.0);
    /// ```
    pub fn for_games(self) -> Self {
        FluidParams {
            hydrostatic_start: true,
            density_mean_tolerance: 0.005,
            density_max_tolerance: 0.05,
            body_force_limit: 0.2,
            max_loop_spring: 4.0,
            ..self
        }
    }
}
