//! Stage: free surface (He 2012 Eq. 25) and isolated regions (Table 3 t_surface): surface
//! carriers get p^v = 0 in the velocity constraint.

use super::Substep;
use crate::math::Vector;
use crate::solver::surface;
use crate::world::FluidWorld;

impl FluidWorld {
    /// Marks the free-surface carriers from density and asymmetry, then the carriers of
    /// regions that touch no solid from below (drops, splashes).
    pub(crate) fn mark_surface(&mut self, s: &Substep) {
        let n = self.fluid.len();
        let sc = &mut self.scratch;
        sc.surface.resize(n, false);
        surface::detect(
            &ctx!(self, &s.bodies),
            &sc.rho,
            &sc.asym,
            self.params.surface_asymmetry,
            self.params.surface_density,
            &mut sc.surface,
        );
        let up = (-s.gravity).try_normalize().unwrap_or(Vector::Y);
        surface::mark_isolated(&ctx!(self, &s.bodies), &self.fluid.x, up, &mut sc.surface);
    }

    /// The density stage's buffers are refilled next step: freed once the surface is marked,
    /// so the solve's vectors take their place instead of adding to the peak (32 B per
    /// carrier).
    pub(crate) fn release_density_buffers(&mut self) {
        let sc = &mut self.scratch;
        sc.v_old = Vec::new();
        sc.accel = Vec::new();
        sc.asym = Vec::new();
        sc.cells = Vec::new();
        sc.wet = Vec::new();
    }
}
