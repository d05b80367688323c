//! Stage: fluid carriers found inside a solid at its end-of-substep pose are moved back to its
//! surface (exact parry geometry).

use super::Substep;
use crate::metrics::StepReport;
use crate::solver::contact;
use crate::world::FluidWorld;

impl FluidWorld {
    /// Corrects the carriers inside solids at their current pose (dynamic bodies at their end
    /// pose, [`FluidWorld::finish_rigids`]); the correction's impulses change the bodies'
    /// velocities for the next substep, like rapier's velocity-level contacts.
    pub(crate) fn correct_penetration(&mut self, s: &Substep, rep: &mut StepReport) {
        let final_shapes = self.shapes();
        let deformed = self.deformed_frames();
        let (imp, corrected) = contact::correct_penetration(
            &ctx!(self, &s.bodies),
            &final_shapes,
            &deformed,
            &mut self.fluid.x,
            &mut self.fluid.v,
        );
        self.absorb_at_points(&imp);
        rep.penetrations_corrected += corrected as u64;
    }
}
