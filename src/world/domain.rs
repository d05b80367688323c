//! The simulation domain and its neighbour grid, the search box around the fluid, and which
//! moving solids take part in a step.

use super::{FluidWorld, SolidKind};
use crate::error::{FluidError, Result};
use crate::math::{bounding_box, Vector};
use crate::neighbors::{counting_sort_into, Grid};
use crate::params::MAX_CELLS;

impl FluidWorld {
    pub(crate) fn ensure_grid(&mut self) -> Result<()> {
        if self.grid.is_some() {
            return Ok(());
        }
        let (lo, hi) = match self.params.domain {
            Some((a, b)) => (Vector::from(a), Vector::from(b)),
            None => {
                let (mut flo, mut fhi) = bounding_box(&self.fluid.x);
                if let Some((a, b)) = self.domain_hint {
                    (flo, fhi) = (flo.min(a), fhi.max(b));
                }
                let (slo, shi) = bounding_box(&self.solid.x);
                let (lo, hi) = (flo.min(slo), fhi.max(shi));
                // Along an axis where solids bound the fluid on both sides (a slab between two
                // walls) fluid leaves only over a wall top, so the margin there need not exceed
                // half the extent: a 0.1 m margin around a 7.5 mm slab made the dense cell grid
                // 30× the particles (at 614k fluid: neighbour stage 0.55 → 0.28 s, peak memory
                // 1.73 → 1.39 GiB with the smaller margin)
                let h = self.params.support_radius();
                let m = Vector::from(std::array::from_fn::<f32, 3, _>(|k| {
                    let enclosed = slo[k] < flo[k] && shi[k] > fhi[k];
                    let margin = self.params.domain_margin;
                    if enclosed {
                        margin.min(0.5 * (hi[k] - lo[k]))
                    } else {
                        margin
                    }
                })) + Vector::splat(h);
                (lo - m, hi + m)
            }
        };
        let cell = self.params.support_radius() * (1.0 + self.params.neighbor_skin);
        let grid = Grid::new(lo, hi, cell);
        if grid.cell_count() <= MAX_CELLS {
            // grounds are sampled within the domain, now that it is fixed
            self.sample_deferred(lo, hi)?;
        }
        if grid.cell_count() > MAX_CELLS {
            return Err(FluidError::TooMany {
                what: "neighbour-grid cells (shrink the domain or grow the spacing)",
                count: grid.cell_count(),
                limit: MAX_CELLS,
            });
        }
        self.grid = Some(grid);
        Ok(())
    }

    /// The box of `domain`'s cells the neighbour search runs on this step: the fluid's bounding
    /// box with a margin of 8 cells, kept while the fluid stays 2 cells inside it (so the solids
    /// are sorted into it again only when the fluid has moved on, or when solids moved).
    pub(crate) fn search_box(&mut self, domain: &Grid) -> Grid {
        let (a, b) = bounding_box(&self.fluid.x);
        let (a, b) = (domain.coords(a), domain.coords(b));
        let inside = |s: &Grid| {
            (0..3).all(|k| {
                let (lo, hi) = (s.origin[k], s.origin[k] + s.dims[k] - 1);
                (a[k] >= lo + 2 || lo == 0) && (b[k] + 2 <= hi || hi == domain.dims[k] - 1)
            })
        };
        match self.search {
            Some(s) if !self.solids_dirty && inside(&s) => s,
            _ => {
                let s = domain.crop(a.map(|c| c.saturating_sub(8)), b.map(|c| c + 8));
                self.search = Some(s);
                self.sort_solids(&s);
                s
            }
        }
    }

    fn sort_solids(&mut self, grid: &Grid) {
        // only active solids' carriers inside the domain take part (bodies no fluid is near
        // cost nothing)
        let (lo, hi) = (grid.min(), grid.hi());
        let idx: Vec<u32> = (0..self.solid.len() as u32)
            .filter(|&i| {
                let p = self.solid.x[i as usize];
                self.solids[self.solid.body[i as usize] as usize].active
                    && (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k])
            })
            .collect();
        let cells: Vec<u32> = idx
            .iter()
            .map(|&i| grid.cell_of(self.solid.x[i as usize]))
            .collect();
        let order = counting_sort_into(&cells, grid.cell_count() as usize, &mut self.solid_start);
        self.solid_ids = order.iter().map(|&o| idx[o as usize]).collect();
        self.solids_dirty = false;
    }

    /// Marks moving solids (and their rapier bodies) active when some fluid carrier lies within
    /// two support radii of their bounding box, widened by how far the solid and the fastest
    /// fluid carrier (`fluid_speed`) can travel toward each other in the coming step of
    /// length `dt`.
    pub(crate) fn update_activity(&mut self, dt: f32, fluid_speed: f32) {
        let Some(grid) = self.grid else { return };
        if self.solids.iter().all(|s| s.kind == SolidKind::Static) {
            return;
        }
        let mut occupied = vec![false; grid.cell_count() as usize];
        for p in &self.fluid.x {
            occupied[grid.cell_of(*p) as usize] = true;
        }
        let near = 2.0 * self.params.support_radius();
        let (glo, ghi) = (grid.lo, grid.hi());
        for s in self.solids.iter_mut() {
            if s.kind == SolidKind::Static || s.removed {
                continue;
            }
            let (lo, hi) = if s.kind == SolidKind::Deformable {
                crate::math::bounding_box(&self.solid.x[s.range.clone()])
            } else {
                let aabb = s.shape.compute_aabb(&s.pose);
                (aabb.mins, aabb.maxs)
            };
            // a body thrown at the water from beyond the margin reached it within the step
            // unseen (its carriers out of the search) and ended the step deep in the water: a
            // ball at 6 m/s, 0.14 m over a pool at 1/30 s, erupted (+147 J) in its next step
            // (deformable bodies keep the plain margin: woken earlier by the water's travel,
            // a cloth under PCISPH gained energy and a membrane let a thrown carrier through,
            // docs/experiments.md, thirty-first session)
            let reach = if s.kind == SolidKind::Deformable {
                0.0
            } else {
                s.linvel.length() + s.angvel.length() * 0.5 * (hi - lo).length() + fluid_speed
            };
            let margin = Vector::splat(near + reach * dt);
            let (lo, hi) = (lo - margin, hi + margin);
            let was = s.active;
            s.active = if (0..3).any(|k| hi[k] < glo[k] || lo[k] > ghi[k]) {
                false
            } else {
                let (a, b) = (grid.coords(lo), grid.coords(hi));
                (a[2]..=b[2]).any(|z| {
                    (a[1]..=b[1])
                        .any(|y| (a[0]..=b[0]).any(|x| occupied[grid.index([x, y, z]) as usize]))
                })
            };
            self.solids_dirty |= was != s.active;
        }
        for (k, r) in self.rigids.iter_mut().enumerate() {
            r.active = self.solids.iter().any(|s| s.rigid == Some(k) && s.active);
        }
    }
}
