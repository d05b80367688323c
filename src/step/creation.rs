//! Stage: staggered-particle creation (He 2012 Eqs. 7–9, 22; Table 3 t_creating): each fluid
//! carrier's density ρ_i and neighbour count N_i at its final predicted position, and its share
//! `(m_i/N_i, ρ_i)` in the staggered particles between it and its neighbours.

use super::Substep;
use crate::solver::density;
use crate::solver::staggered::Share;
use crate::world::FluidWorld;
use rayon::prelude::*;

impl FluidWorld {
    /// Densities, counts and Eq. 25's asymmetry (unless the density loop left them `fresh`),
    /// then the shares.
    pub(crate) fn create_staggered(&mut self, s: &Substep, fresh: bool) {
        let sc = &mut self.scratch;
        if !fresh {
            density::density_and_count(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &mut sc.rho,
                &mut sc.count,
                Some(&mut sc.asym),
                None,
                density::WallHead::new(
                    s.gravity,
                    &self.fluid.accel,
                    self.params.rest_density,
                    &sc.wet,
                )
                .as_ref(),
            );
        }
        sc.shares.clear();
        let mass = self.mass;
        sc.shares.par_extend(
            sc.rho
                .par_iter()
                .zip(sc.count.par_iter())
                .map(|(&r, &c)| Share::new(mass, r, c)),
        );
    }
}
