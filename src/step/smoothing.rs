//! Stage: XSPH velocity smoothing (Monaghan 1989) after the velocity constraint, walls included
//! (see [`crate::FluidParams::xsph`]).

use super::Substep;
use crate::solver::forces;
use crate::world::FluidWorld;

impl FluidWorld {
    /// Averages each carrier's velocity with its neighbours' (ε = `xsph`); the momentum taken
    /// from walls goes to their bodies. Nothing when `xsph` is 0.
    pub(crate) fn smooth(&mut self, s: &Substep) {
        if self.params.xsph <= 0.0 {
            return;
        }
        let sc = &mut self.scratch;
        sc.v_old.clone_from(&self.fluid.v);
        let imp = forces::xsph(
            &ctx!(self, &s.bodies),
            &self.fluid.x,
            &sc.v_old,
            &sc.rho,
            self.params.xsph,
            self.params.xsph_walls,
            &mut self.fluid.v,
        );
        self.absorb_shared(imp);
    }
}
