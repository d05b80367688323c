//! Stage: the remap (He 2012 Eq. 19 and its consistent form): the solved p^v applied to the
//! carriers, then the wall conditions of no-slip walls (Eq. 26) and of free-surface carriers
//! beside walls (Eq. 27).

use super::Substep;
use crate::math::Vector;
use crate::params::Remap;
use crate::solver::{density, projection, velocity};
use crate::world::FluidWorld;
use rayon::prelude::*;

impl FluidWorld {
    /// Carrier velocities from the pressure in the scratch's `p`; every impulse on a solid
    /// carrier goes to its body.
    pub(crate) fn remap(&mut self, s: &Substep) {
        let (n, dt) = (self.fluid.len(), s.dt);
        if self.params.remap == Remap::Consistent {
            let imp = velocity::apply_pressure(
                &ctx!(self, &s.bodies),
                &self.system,
                &self.scratch.p,
                dt,
                &mut self.fluid.v,
            );
            self.absorb(imp);
            let sc = &self.scratch;
            let imp = velocity::no_slip(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &sc.shares,
                &sc.count,
                &mut self.fluid.v,
            );
            self.absorb(imp);
            let sc = &self.scratch;
            let imp = velocity::surface_walls(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &sc.shares,
                &sc.count,
                &self.system.unknown,
                &mut self.fluid.v,
            );
            self.absorb(imp);
            return;
        }
        let sc = &mut self.scratch;
        sc.v_old.clone_from(&self.fluid.v);
        let imp = projection::remap(
            &ctx!(self, &s.bodies),
            &self.fluid.x,
            &sc.v_old,
            &sc.shares,
            &sc.count,
            &sc.p,
            dt,
            self.params.remap,
            &mut self.fluid.v,
        );
        self.absorb(imp);
        if self.params.remap == Remap::Conservative {
            let sc = &mut self.scratch;
            sc.accel.resize(n, Vector::ZERO);
            let imp = density::pressure_accel(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &sc.p,
                &sc.rho,
                &mut sc.accel,
                dt,
                density::WallPush::Normal,
            );
            self.absorb(imp);
            let fl = &mut self.fluid;
            fl.v.par_iter_mut()
                .zip(self.scratch.accel.par_iter())
                .for_each(|(v, &a)| *v += a * dt);
        }
    }
}
