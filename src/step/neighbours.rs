//! Stage: neighbour search (He 2012 Table 3, t_neighbor). Fluid carriers that left the domain
//! are removed and counted, the rest sorted by cell, and the neighbour lists built over fluid
//! and active solid carriers.

use crate::error::{FluidError, Result};
use crate::metrics::StepReport;
use crate::neighbors::{build_lists, counting_sort_into};
use crate::world::FluidWorld;
use rayon::prelude::*;

impl FluidWorld {
    /// Culls the fluid to the domain, sorts it by cell and builds the neighbour lists.
    pub(crate) fn find_neighbours(&mut self, rep: &mut StepReport) -> Result<()> {
        let grid = self.grid.expect("grid initialised in step");
        let (lo, hi) = self.domain().expect("grid");
        let keep: Vec<bool> = self
            .fluid
            .x
            .par_iter()
            .map(|p| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]))
            .collect();
        let removed = keep.iter().filter(|k| !**k).count();
        if removed > 0 {
            self.fluid.retain(&keep);
            self.removed_total += removed as u64;
            rep.removed_outside += removed as u64;
            if self.fluid.is_empty() {
                return Err(FluidError::EmptyFluid);
            }
        }
        let grid = self.search_box(&grid);
        let sc = &mut self.scratch;
        sc.cells.clear();
        sc.cells
            .par_extend(self.fluid.x.par_iter().map(|p| grid.cell_of(*p)));
        let order =
            counting_sort_into(&sc.cells, grid.cell_count() as usize, &mut self.fluid_start);
        self.fluid.permute(&order);
        let radius = self.params.support_radius() * (1.0 + self.params.neighbor_skin);
        build_lists(
            &grid,
            radius,
            &self.fluid.x,
            &self.fluid_start,
            &self.solid.x,
            &self.solid_ids,
            &self.solid_start,
            &mut self.lists,
        );
        Ok(())
    }
}
