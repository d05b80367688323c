//! Stage: the end of a substep for the solids: dynamic bodies take the pose their final
//! velocity reaches, and fluid carriers found inside a solid at that pose are moved back to
//! its surface (exact parry geometry).

use super::Substep;
use crate::metrics::StepReport;
use crate::solver::contact;
use crate::world::FluidWorld;

impl FluidWorld {
    /// Moves the bodies to their end pose and corrects the carriers inside them; the
    /// correction's impulses change the bodies' velocities for the next substep, like rapier's
    /// velocity-level contacts.
    pub(crate) fn correct_penetration(&mut self, s: &Substep, rep: &mut StepReport) {
        self.finish_rigids(s.dt);
        let final_shapes = self.shapes();
        let (imp, corrected) = contact::correct_penetration(
            &ctx!(self, &s.bodies),
            &final_shapes,
            &mut self.fluid.x,
            &mut self.fluid.v,
        );
        self.absorb(imp);
        rep.penetrations_corrected += corrected as u64;
    }
}
