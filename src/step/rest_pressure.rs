//! Water placed at rest starts with its hydrostatic pressure
//! ([`crate::FluidParams::hydrostatic_start`], on by default): the density constraint's
//! pressure memory of carriers added at rest ([`crate::FluidWorld::add_block`] and the like) is
//! `ρ̄ |g| (top − height)` over the column of water above each one, so the first substeps do
//! not have to build a deep tank's pressure from zero. From zero, a 0.3 m deep still tank at
//! rapier's 1/60 s hits its floor with 1.49× its weight in the first frame and the step
//! controller takes 17–26 substeps a frame for the next few; the five balls at 1/60 s spend
//! 361 of 643 substeps in their first 0.43 s (docs/experiments.md, twenty-sixth session;
//! the default since the thirtieth).

use crate::math::Vector;
use crate::world::{FluidWorld, SolidKind};

impl FluidWorld {
    /// Sets the pressure memory of the carriers still waiting for it (ids in
    /// [`FluidWorld::rest_pending`]) to the hydrostatic pressure of the water column above
    /// them: carriers are binned into vertical columns a spacing wide; in each column a run of
    /// carriers no more than 1.5Δx apart is one body of water, topped at its highest carrier
    /// plus Δx/2 (where the surface layer's pressure `ρ̄ |g| Δx/2` puts it). A run whose lowest
    /// carrier has no solid carrier below it (a block in mid-air or a column between two
    /// plates, in free fall) keeps 0.
    /// Needs the neighbour lists of the current positions; without gravity nothing is set.
    pub(crate) fn start_at_rest(&mut self, gravity: Vector) {
        if self.rest_pending.is_empty() {
            return;
        }
        let pending = std::mem::take(&mut self.rest_pending);
        if !self.params.hydrostatic_start {
            return;
        }
        let n = self.fluid.len();
        let g = gravity.length();
        if g <= 0.0 || !g.is_finite() || self.lists.offsets.len() != n + 1 {
            return;
        }
        let up = -gravity / g;
        let (e1, e2) = up.any_orthonormal_pair();
        let dx = self.params.spacing;
        let x = &self.fluid.x;
        let column = |p: Vector| {
            (
                (p.dot(e1) / dx).floor() as i64,
                (p.dot(e2) / dx).floor() as i64,
            )
        };
        // by column, highest first (ties by index: deterministic)
        let mut order: Vec<u32> = (0..n as u32).collect();
        order.sort_unstable_by(|&a, &b| {
            let (pa, pb) = (x[a as usize], x[b as usize]);
            column(pa)
                .cmp(&column(pb))
                .then(pb.dot(up).total_cmp(&pa.dot(up)))
                .then(a.cmp(&b))
        });
        // a solid carrier below within 25° of the vertical (not a wall beside the column)
        let supported = |i: usize| {
            self.lists.indices[self.lists.solid_range(i)]
                .iter()
                .any(|&j| {
                    let d = x[i] - self.solid.x[j as usize - n];
                    d.dot(up) > 0.25 * dx && d.dot(up) > 0.9 * d.length()
                })
        };
        // a deformable container has not yet taken the load it would bear at rest: water
        // beside one starts from zero (held at once, an elastic box's walls, undeflected,
        // were thrown out by the full hydrostatic push within four 1/60 s frames)
        let beside_soft = |i: usize| {
            self.lists.indices[self.lists.solid_range(i)]
                .iter()
                .any(|&j| {
                    let body = self.solid.body[j as usize - n] as usize;
                    self.solids[body].kind == SolidKind::Deformable
                })
        };
        let rho_g = self.params.rest_density * g;
        let mut p = vec![0.0f32; n];
        let mut k = 0;
        while k < n {
            let first = order[k] as usize;
            let (col, top) = (column(x[first]), x[first].dot(up) + 0.5 * dx);
            let mut end = k + 1;
            while end < n {
                let (above, here) = (x[order[end - 1] as usize], x[order[end] as usize]);
                if column(here) != col || above.dot(up) - here.dot(up) > 1.5 * dx {
                    break;
                }
                end += 1;
            }
            let soft = order[k..end].iter().any(|&i| beside_soft(i as usize));
            if supported(order[end - 1] as usize) && !soft {
                for &i in &order[k..end] {
                    p[i as usize] = rho_g * (top - x[i as usize].dot(up));
                }
            }
            k = end;
        }
        let fl = &mut self.fluid;
        fl.p_memory.resize(n, 0.0);
        for ((m, &id), &p) in fl.p_memory.iter_mut().zip(&fl.id).zip(&p) {
            if pending.iter().any(|&(a, b)| id >= a && id < b) {
                *m = p;
            }
        }
    }
}
