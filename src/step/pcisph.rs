//! PCISPH with Akinci boundaries and the velocity–position correction of Shao et al. 2014
//! (their Algorithm 1): forces and prediction, then the density loop to a tolerance on the
//! mean compression with the full stiffness of Eq. 5, Akinci boundary forces (Eq. 7) and
//! Eq. 12's position correction inside it, then the bodies' end pose and the correction
//! (Eqs. 11–17) against it. No velocity constraint follows.

use super::density::DensityLoop;
use super::{PressureSolver, Substep};
use crate::error::Result;
use crate::math::Vector;
use crate::metrics::{StageTimes, StepReport};
use crate::params::FluidParams;
use crate::solver::{contact, det_sum};
use crate::world::FluidWorld;
use rayon::prelude::*;
use std::time::Instant;

/// Largest CFL number the PCISPH solver runs at, whatever [`FluidParams::max_cfl`] says.
///
/// PCISPH has no velocity constraint: where two bodies of water close on each other by more
/// than ≈ 0.2 Δx in one step its iterations diverge (measured: slabs meeting at ±1 m/s
/// explode at CFL 0.4 and 0.2, are fine at 0.1; a 3 m/s impact on a plate is fine at 0.2,
/// with Shao's correction); the staggered solver takes 0.4.
pub const PCISPH_MAX_CFL: f32 = 0.1;

/// Body-force step limit of the PCISPH solver, `Δt ≤ c √(Δx/|g|)`, whatever
/// [`FluidParams::body_force_limit`] says when that is longer.
///
/// PCISPH starts every substep from zero pressure and stops at a mean compression of
/// [`FluidParams::density_error_tolerance`]; at longer substeps the water settles at that
/// compression and its loop then diverges. A still tank 0.3 m deep at Δx 2 cm and rapier's
/// 1/60 s erupted at 0.13 s with the shared limit (0.15: substeps of 3–6 ms; likewise at 1/120
/// and 1/240 s), at 0.12 s with 0.1, swung between 0.24 and 1.1 of its weight on the floor with
/// 0.07; with 0.05 (2.3 ms substeps) it runs, its floor carrying 0.995 of the weight over the
/// last 0.2 s of 1 s (frame to frame ±20 %, as at the 2 ms steps of its tests).
pub const PCISPH_BODY_FORCE_LIMIT: f32 = 0.05;

/// Shao et al. 2014, *Stable and fast fluid–solid coupling for incompressible SPH*.
pub(crate) struct Pcisph;

impl PressureSolver for Pcisph {
    fn max_cfl(&self, p: &FluidParams) -> f32 {
        p.max_cfl.min(PCISPH_MAX_CFL)
    }

    fn max_substep(&self, w: &FluidWorld, gravity: Vector) -> Option<f32> {
        w.body_force_step(PCISPH_BODY_FORCE_LIMIT, gravity)
    }

    /// Its loop's own tolerance on the mean compression of all carriers.
    fn mean_tolerance(&self, p: &FluidParams) -> f32 {
        p.density_error_tolerance
    }

    fn substep(
        &self,
        w: &mut FluidWorld,
        s: &Substep,
        times: &mut StageTimes,
        rep: &mut StepReport,
    ) -> Result<()> {
        let t = Instant::now();
        w.predict(s);
        let p = &w.params;
        let cfg = DensityLoop {
            stiffness: w.loop_stiffness(s),
            min_iterations: p.density_iterations.max(1),
            max_iterations: p.max_pcisph_iterations.max(1),
            tolerance: p.density_error_tolerance,
            max_tolerance: f32::INFINITY,
            inner_only: false,
            stop_on_stall: false,
            anchor: false,
            max_shift: None,
            akinci: true,
            asymmetry: false,
            memory: 0.0,
            surface_extrapolation: false,
            hydrostatic_walls: false,
            wall_support: false,
            position_relaxation: 1.0,
            position_only: false,
            surface_rest: false,
            pressure_scale: false,
        };
        // the mass a solid carrier of each body stands for in the correction (Eqs. 13–17)
        let solid_mass = w.carrier_masses();
        let in_loop = |w: &mut FluidWorld, s: &Substep| {
            if w.solid.x.is_empty() {
                return;
            }
            // Eq. 12 on the positions the iteration predicted, with the predicted velocities
            let sc = &mut w.scratch;
            sc.v_old.clear();
            sc.v_old.par_extend(
                w.fluid
                    .v
                    .par_iter()
                    .zip(sc.accel.par_iter())
                    .map(|(&v, &a)| v + a * s.dt),
            );
            contact::shao_correction(
                &ctx!(w, &s.bodies),
                w.params.spacing,
                &solid_mass,
                &sc.v_old,
                &mut w.fluid.x,
                None,
            );
        };
        let d = w.density_constraint(s, &cfg, Some(&in_loop));
        times.density += t.elapsed().as_secs_f64();
        rep.density_iterations += d.iterations;
        // the substep controller's inputs: a loop that ended beyond its tolerance failed
        let met = d.compression <= cfg.tolerance as f64;
        w.substep_diverged = d.diverged || !met;
        w.substep_compression = d.compression;
        let t = Instant::now();
        // the bodies take their end pose; the correction then sees the true penetrations
        w.finish_rigids(s.dt);
        let v_now = w.fluid.v.clone();
        let (imp, corrected) = contact::shao_correction(
            &ctx!(w, &s.bodies),
            w.params.spacing,
            &solid_mass,
            &v_now,
            &mut w.fluid.x,
            Some(&mut w.fluid.v),
        );
        w.absorb(imp);
        rep.penetrations_corrected += corrected as u64;
        let n = w.fluid.len();
        let sc = &w.scratch;
        let fl = &mut w.fluid;
        fl.p_velocity.iter_mut().for_each(|p| *p = 0.0);
        fl.density.clone_from(&sc.rho);
        fl.neighbors.clone_from(&sc.count);
        fl.surface.clear();
        fl.surface.resize(n, false);
        w.check_finite()?;
        times.other += t.elapsed().as_secs_f64();
        rep.error = rep.error.max(d.compression);
        rep.converged &= met;
        rep.n_surface = 0;
        rep.n_unknown = n;
        let rest = w.params.rest_density;
        let rho = &w.scratch.rho;
        rep.density_deviation =
            det_sum(n, |i| ((rho[i] - rest).abs() / rest) as f64) / n.max(1) as f64;
        // the loop's last evaluation, over all carriers
        rep.compression_mean = rep.compression_mean.max(d.compression);
        rep.compression_max = rep.compression_max.max(d.largest);
        rep.density_converged &= met;
        Ok(())
    }
}
