//! Filling the world with fluid: carriers at given positions, lattice blocks, removal.

use super::solids::check_overlap;
use super::FluidWorld;
use crate::error::{FluidError, Result};
use crate::math::{arr, finite, Vector};
use crate::params::{check_count, MAX_PARTICLES};
use crate::sampling::fill_box;
use rayon::prelude::*;

impl FluidWorld {
    /// Checks that fluid placed at `positions` would lie inside no solid (what
    /// [`Self::add_particles`] checks before adding), without adding it.
    pub fn check_free(&self, positions: &[Vector]) -> Result<()> {
        // (a deformable body is where its lattice points are, not where its rest shape was)
        let rigid = |s: &&super::Solid| !s.removed && s.kind != super::SolidKind::Deformable;
        for s in self.solids.iter().filter(rigid) {
            check_overlap(s, positions)?;
        }
        for b in self.deformables.iter().filter(|b| !b.solids.is_empty()) {
            let shape = (!b.is_cells()).then(|| self.solids[b.solids[0] as usize].shape.as_ref());
            if let (count, Some(first)) = b.covered(positions, self.params.spacing, shape) {
                return Err(crate::error::FluidError::FluidOverlapsSolid {
                    solid: b.name.clone(),
                    count,
                    first: crate::math::arr(first),
                });
            }
        }
        Ok(())
    }

    /// Makes the automatic domain (fixed at the first step, see [`crate::FluidParams::domain`])
    /// include the box `[lo, hi]`, where fluid will appear later (an emitter's outlet).
    /// No effect once the world has stepped or with an explicit domain.
    pub fn include_in_domain(&mut self, lo: Vector, hi: Vector) {
        self.domain_hint = Some(match self.domain_hint {
            Some((a, b)) => (a.min(lo), b.max(hi)),
            None => (lo, hi),
        });
    }

    /// Removes the fluid carriers whose position satisfies `inside` (an outflow sink, see
    /// [`crate::emitter::Sink`]); returns how many. The caller counts them: this is not a
    /// silent loss.
    pub fn remove_fluid_where(&mut self, inside: impl Fn(Vector) -> bool + Sync) -> u64 {
        let keep: Vec<bool> = self.fluid.x.par_iter().map(|p| !inside(*p)).collect();
        let removed = keep.iter().filter(|k| !**k).count() as u64;
        if removed > 0 {
            self.fluid.retain(&keep);
        }
        removed
    }

    /// Adds fluid carriers at `positions`, all with velocity `velocity`.
    pub fn add_particles(&mut self, positions: &[Vector], velocity: Vector) -> Result<()> {
        if positions.is_empty() {
            return Err(FluidError::EmptyFluid);
        }
        if !finite(velocity) {
            return Err(FluidError::NonFinite {
                what: "fluid velocity".into(),
            });
        }
        let total = (self.fluid.len() + self.solid.len() + positions.len()) as u64;
        if total > MAX_PARTICLES {
            return Err(FluidError::TooMany {
                what: "particles",
                count: total,
                limit: MAX_PARTICLES,
            });
        }
        if let Some(k) = positions.iter().position(|p| !finite(*p)) {
            return Err(FluidError::NonFinite {
                what: format!("fluid particle {k} position"),
            });
        }
        if let Some((lo, hi)) = self
            .domain()
            .or(self.params.domain.map(|(a, b)| (a.into(), b.into())))
        {
            if let Some(p) = positions
                .iter()
                .find(|p| (0..3).any(|k| p[k] < lo[k] || p[k] > hi[k]))
            {
                return Err(FluidError::OutsideDomain {
                    what: format!("fluid particle at {:?}", arr(*p)),
                    mins: arr(lo),
                    maxs: arr(hi),
                });
            }
        }
        self.check_free(positions)?;
        if velocity == Vector::ZERO {
            // water placed at rest may start hydrostatic (step/rest_pressure.rs)
            let first = self.next_id;
            self.rest_pending
                .push((first, first.saturating_add(positions.len() as u32)));
        }
        for &p in positions {
            self.fluid.push(p, velocity, self.next_id);
            self.next_id += 1;
        }
        // water placed at rest: its packing against solids was never a velocity (a stream
        // an emitter adds moves, and is left to the loop as it is)
        self.placed |= velocity == Vector::ZERO && !positions.is_empty();
        Ok(())
    }

    /// Fills the box `[mins, maxs]` with fluid at rest spacing; returns the number added.
    pub fn add_block(&mut self, mins: Vector, maxs: Vector, velocity: Vector) -> Result<usize> {
        if !finite(mins) || !finite(maxs) {
            return Err(FluidError::NonFinite {
                what: "fluid block corners".into(),
            });
        }
        let dx = self.params.spacing as f64;
        // in f64: a block of 1e30 m needs 1e90 carriers, which no integer type holds
        let count: f64 = (0..3)
            .map(|k| {
                (((maxs[k] as f64 - mins[k] as f64) / dx) + 1e-4)
                    .floor()
                    .max(0.0)
            })
            .product();
        if count == 0.0 {
            return Err(FluidError::EmptyBlock {
                mins: arr(mins),
                maxs: arr(maxs),
                spacing: self.params.spacing,
            });
        }
        check_count("fluid block particles", count, MAX_PARTICLES)?;
        let pts = fill_box(mins, maxs, self.params.spacing);
        self.add_particles(&pts, velocity)?;
        Ok(pts.len())
    }
}
