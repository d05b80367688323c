//! Stage: body and generalized viscous forces (He 2012 Eq. 24) and the predicted positions
//! (Algorithm 1, lines 2–3).

use super::Substep;
use crate::solver::forces;
use crate::world::FluidWorld;
use rayon::prelude::*;

impl FluidWorld {
    /// `ṽ = v + Δt (g + viscous force / m)`, then `x += ṽ Δt`; the viscous impulse on solid
    /// carriers goes to their bodies.
    pub(crate) fn predict(&mut self, s: &Substep) {
        self.build_lumps(&s.bodies, s.dt);
        self.share_weight(s.gravity, s.dt);
        self.scratch.v_old.clone_from(&self.fluid.v);
        let imp = forces::viscous_prediction(
            &ctx!(self, &s.bodies),
            &self.fluid.x,
            &self.scratch.v_old,
            &mut self.fluid.v,
            s.gravity,
            s.dt,
        );
        self.absorb_shared(imp);
        let dt = s.dt;
        let fl = &mut self.fluid;
        fl.x.par_iter_mut()
            .zip(fl.v.par_iter())
            .for_each(|(x, v)| *x += *v * dt);
    }
}
