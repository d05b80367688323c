//! Stages: the velocity constraint (He 2012 §4–§5, Eqs. 10–13, 26–27): assembly of the Poisson
//! system with its wall conditions (Table 3 t_assemble) and its Krylov solve (t_solving),
//! warm-started from the last step's p^v.

use super::Substep;
use crate::params::{Preconditioner, Remap};
use crate::rigid::Rigid;
use crate::solver::pcg::{self, PcgSettings, PcgStats};
use crate::solver::{projection, velocity};
use crate::world::FluidWorld;
use rapier3d::math::Matrix;
use rapier3d::math::Vector;
use rayon::prelude::*;

impl FluidWorld {
    /// Assembles `A p = b`: the consistent operator `D M⁻¹ Dᵀ` with the moving bodies' rows
    /// ([`Remap::Consistent`], the default), or Eq. 13 as printed for the approximate remaps.
    pub(crate) fn assemble_velocity_constraint(&mut self, s: &Substep) {
        let sc = &self.scratch;
        if self.params.remap == Remap::Consistent {
            let ctx = ctx!(self, &s.bodies);
            velocity::assemble(
                &ctx,
                &self.fluid.x,
                &self.fluid.v,
                &sc.shares,
                &sc.surface,
                s.dt,
                self.div_norm,
                self.params.gradient_correction,
                self.params.preconditioner == Preconditioner::BlockSsor,
                &mut self.system,
            );
            let inv: Vec<(Vector, Matrix)> = self.rigids.iter().map(inverse_inertia).collect();
            velocity::link_rigids(&ctx, &inv, &mut self.system);
        } else {
            projection::assemble(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &self.fluid.v,
                &sc.shares,
                &sc.surface,
                s.dt,
                &mut self.system,
            );
        }
    }

    /// Solves for p^v (into the scratch's `p`), then, with the §5.2 no-stick inequality on,
    /// releases carriers that a wall would hold back and solves again.
    pub(crate) fn solve_velocity_constraint(&mut self, s: &Substep) -> PcgStats {
        let sc = &mut self.scratch;
        // p^v scales as 1/Δt: the last substep's pressure is a warm start only for a substep of
        // about its length (a 1 µs step after 5 ms ones would start 5 000× too low)
        let ratio = s.dt / self.last_substep;
        let warm = (0.25..=4.0).contains(&ratio);
        self.last_substep = s.dt;
        sc.p.clear();
        sc.p.par_extend(
            self.fluid
                .p_velocity
                .par_iter()
                .zip(self.system.unknown.par_iter())
                .map(|(&p, &u)| if u && warm { p as f64 } else { 0.0 }),
        );
        let settings = PcgSettings {
            kind: self.params.preconditioner,
            krylov: self.params.krylov,
            omega: self.params.ssor_omega as f64,
            block: self.params.ssor_block,
            tolerance: self.params.density_error_tolerance as f64,
            relative_residual: self.params.relative_residual as f64,
            max_iterations: self.params.max_pcg_iterations,
            dt: s.dt as f64,
        };
        let mut stats = pcg::solve(&self.system, &self.lists, &mut sc.p, settings);
        if self.params.remap == Remap::Consistent
            && self.params.no_stick
            && velocity::release_wall_suction(
                &ctx!(self, &s.bodies),
                &self.fluid.v,
                &mut self.system,
                &mut sc.p,
            ) > 0
        {
            let again = pcg::solve(&self.system, &self.lists, &mut sc.p, settings);
            stats = PcgStats {
                iterations: stats.iterations + again.iterations,
                initial_error: stats.initial_error,
                ..again
            };
        }
        stats
    }
}

/// A body's inverse mass per axis and world inverse inertia.
fn inverse_inertia(r: &Rigid) -> (Vector, Matrix) {
    (r.inv_mass(), r.inv_inertia())
}
