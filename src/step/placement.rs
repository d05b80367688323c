//! Water placed at rest (`FluidWorld::placed`): its compression was never a velocity. The
//! first substep after a placement runs the position-only drift pass until it stalls
//! (`step/he2012.rs`), and what that leaves, each carrier's density then, is kept out of the
//! density loop's reach with a share that falls to zero over the body-force limit's substep
//! (`FluidWorld::placement`): its relief adds about `δx/T`, not `δx/Δt` (a world's first step
//! of 1 µs threw water placed around a body at 2.98 m/s; docs/experiments.md, thirty-fifth
//! session).

use super::Substep;
use crate::math::Vector;
use crate::solver::density;
use crate::world::FluidWorld;
use rayon::prelude::*;

impl FluidWorld {
    /// Opens the window over which a placement's compression is relieved
    /// ([`FluidWorld::placement`]) before the first substep after water was placed at rest:
    /// the body-force limit's substep under `gravity` (none without gravity).
    pub(crate) fn open_placement_window(&mut self, gravity: Vector, dt: f32) {
        if !self.placed {
            return;
        }
        self.placement = self
            .body_force_step(self.body_force_limit(), gravity)
            .filter(|&t| t > dt)
            .map(|t| (t, t));
        if self.placement.is_none() {
            self.fluid.placed_rho.clear();
        }
    }

    /// After a substep of `dt`: the placement handled, its window shorter by `dt`.
    pub(crate) fn close_placement_window(&mut self, dt: f32) {
        self.placed = false;
        self.placement = self
            .placement
            .map(|(left, span)| (left - dt, span))
            .filter(|&(left, _)| left > 0.0);
        if self.placement.is_none() {
            self.fluid.placed_rho.clear();
        }
    }

    /// At the first substep after water was placed, each carrier's density at its
    /// (drift-corrected) start, as the density loop will evaluate it (the same walls), kept as
    /// the placement's ([`FluidCarriers::placed_rho`](crate::FluidCarriers)).
    pub(crate) fn keep_placement_compression(&mut self, s: &Substep) {
        if !self.placed || self.placement.is_none() {
            return;
        }
        let n = self.fluid.len();
        let wet = self.wet_walls(s, self.params.hydrostatic_walls);
        let mut rho = std::mem::take(&mut self.fluid.placed_rho);
        rho.resize(n, 0.0);
        let sc = &mut self.scratch;
        sc.count.resize(n, 0);
        density::density_and_count(
            &ctx!(self, &s.bodies),
            &self.fluid.x,
            &mut rho,
            &mut sc.count,
            None,
            None,
            density::WallHead::new(s.gravity, &self.fluid.accel, self.params.rest_density, &wet)
                .as_ref(),
        );
        self.fluid.placed_rho = rho;
    }

    /// Each carrier's EOS rest density `rest_of` (empty: ρ̄ for all) raised by the share of
    /// its placement's compression the density loop leaves in this substep of `dt`: what is
    /// left of the window at the substep's end over the window (linear: the velocity its
    /// relief adds is about `δx/T`, not `δx/Δt`). Compression the substeps' own motion makes
    /// is corrected at once, as before.
    pub(super) fn raise_by_kept(&self, rest_of: &mut Vec<f32>, dt: f32) {
        let Some((left, span)) = self.placement else {
            return;
        };
        let share = ((left - dt) / span).max(0.0);
        let placed = &self.fluid.placed_rho;
        let n = self.fluid.len();
        if placed.len() != n || share <= 0.0 {
            return;
        }
        rest_of.resize(n, self.params.rest_density);
        rest_of
            .par_iter_mut()
            .zip(placed.par_iter())
            .for_each(|(r, &start)| *r += share * (start - *r).max(0.0));
    }
}
