//! Stage: the density constraint (He 2012 Algorithm 2): iterations of density (Eq. 22) → EOS
//! pressure p^d ≥ 0, accumulated with the PCISPH stiffness → generalized pressure force
//! (Eq. 23) moving the predicted positions. Dynamic bodies move with the force of each
//! iteration too, so a body the fluid pushes gives way instead of the fluid alone taking up the
//! compression. Shao et al. 2014's PCISPH loop is the same loop with other settings
//! ([`DensityLoop`]) and the velocity–position correction inside it.

use super::{predict_positions, Substep};
use crate::math::Vector;
use crate::solver::{density, det_sum, Impulses};
use crate::world::FluidWorld;
use rayon::prelude::*;

/// Settings of one run of the density loop.
pub(crate) struct DensityLoop {
    /// EOS stiffness `k` of `p^d += k (ρ − ρ̄)`, Pa per kg/m³.
    pub stiffness: f32,
    /// Iterations always run.
    pub min_iterations: u32,
    /// Iteration cap.
    pub max_iterations: u32,
    /// Mean compression `mean(max(ρ − ρ̄, 0))/ρ̄` (fraction) below which the loop stops once
    /// `min_iterations` ran.
    pub tolerance: f32,
    /// Solid carriers push as Akinci et al. 2012 boundary particles (Shao 2014 Eq. 7) instead
    /// of along their normals (Eq. 23).
    pub akinci: bool,
    /// An evaluation that may end the loop also computes Eq. 25's asymmetry, so that the
    /// staggered creation and the surface marking reuse it.
    pub asymmetry: bool,
}

/// What a run of the density loop did.
pub(crate) struct DensityOutcome {
    /// Iterations that applied a pressure force.
    pub iterations: u32,
    /// Mean compression (fraction) at the last evaluation.
    pub compression: f64,
    /// Whether `rho`, `count` and `asym` in the scratch hold the final positions' values.
    pub fresh: bool,
}

/// A position correction run after every iteration's prediction (Shao's Eq. 12 inside the
/// PCISPH loop). With one, the final positions are predicted again from the final force: the
/// correction served the density prediction only.
pub(crate) type Correction<'a> = &'a dyn Fn(&mut FluidWorld, &Substep);

impl FluidWorld {
    /// Runs the density loop on the predicted positions and velocities.
    pub(crate) fn density_constraint(
        &mut self,
        s: &Substep,
        cfg: &DensityLoop,
        correction: Option<Correction>,
    ) -> DensityOutcome {
        let (n, dt) = (self.fluid.len(), s.dt);
        let sc = &mut self.scratch;
        sc.rho.resize(n, 0.0);
        sc.count.resize(n, 0);
        sc.accel.resize(n, Vector::ZERO);
        let rest = self.params.rest_density;
        let x0 = self.fluid.x.clone();
        let solid_x0 = self
            .rigids
            .iter()
            .any(|r| r.moving())
            .then(|| self.solid.x.clone());
        self.fluid.p_density.par_iter_mut().for_each(|p| *p = 0.0);
        let mut imp = Impulses::new();
        let (mut done, mut compression, mut fresh) = (0, 0.0, false);
        self.scratch.asym.resize(n, 0.0);
        for it in 0..cfg.max_iterations {
            let sc = &mut self.scratch;
            let last = it >= cfg.min_iterations;
            density::density_and_count(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &mut sc.rho,
                &mut sc.count,
                (last && cfg.asymmetry).then_some(&mut sc.asym[..]),
            );
            let rho = &sc.rho;
            compression = det_sum(n, |i| (rho[i] - rest).max(0.0) as f64) / n as f64 / rest as f64;
            if last && compression <= cfg.tolerance as f64 {
                fresh = cfg.asymmetry;
                break;
            }
            done += 1;
            // the last iteration's impulses are replaced: freed before the new ones are built
            drop(std::mem::take(&mut imp));
            let k = cfg.stiffness;
            self.fluid
                .p_density
                .par_iter_mut()
                .zip(sc.rho.par_iter())
                .for_each(|(p, &r)| *p = (*p + k * (r - rest)).max(0.0));
            imp = density::pressure_accel(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &self.fluid.p_density,
                &sc.rho,
                &mut sc.accel,
                dt,
                cfg.akinci,
            );
            predict_positions(&mut self.fluid.x, &x0, &self.scratch.accel, dt);
            if let Some(c) = correction {
                c(self, s);
            }
            if let Some(sx0) = &solid_x0 {
                self.shift_rigids(&imp, sx0, dt);
            }
        }
        if done > 0 && correction.is_some() {
            predict_positions(&mut self.fluid.x, &x0, &self.scratch.accel, dt);
        }
        if done > 0 {
            let sc = &self.scratch;
            self.fluid
                .v
                .par_iter_mut()
                .zip(sc.accel.par_iter())
                .for_each(|(v, &a)| *v += a * dt);
        }
        self.absorb(imp);
        DensityOutcome {
            iterations: done,
            compression,
            fresh,
        }
    }
}
