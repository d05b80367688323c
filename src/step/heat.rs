//! Stage: heat exchange (Shao et al. 2014 Eq. 20), once a step when heat is modelled: between
//! fluid carriers, between fluid carriers and the lattice points of melting bodies (through the
//! body's carriers, each its own lattice point), between a body's lattice neighbours (its
//! one-ring), and from heat sources into the fluid.

use crate::deform::lattice::Rows;
use crate::error::{FluidError, Result};
use crate::heat::{Exchange, FluidHeat, HeatSource, Laplacian};
use crate::metrics::StepReport;
use crate::world::{FluidWorld, SolidHandle};
use rayon::prelude::*;

/// One fluid carrier's row: its pairs `(j, a_ij)` and its heat sources `(Σ a, Σ a T)`.
type Row = (Vec<(u32, f32)>, (f32, f32));

impl FluidWorld {
    /// Models heat in the fluid: every carrier takes `heat.temperature` (so do carriers made
    /// later), and the water conducts with `heat.conductivity`. A world with a melting body
    /// or a heat source models heat anyway, with [`FluidHeat::default`] unless this is called.
    ///
    /// ```
    /// use staggered_fluid::prelude::*;
    /// use staggered_fluid::{FluidHeat, HeatSource};
    ///
    /// let mut world = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
    /// let size = Vector::new(0.5, 0.5, 0.5);
    /// world.add_open_tank(Vector::ZERO, size, Slip::FreeSlip)?;
    /// // a hot plate over the floor, water 0.2 m deep over it
    /// let plate = world.add_static_box("plate", Vector::ZERO, Vector::new(0.5, 0.05, 0.5), Slip::FreeSlip)?;
    /// world.add_block(Vector::new(0.0, 0.05, 0.0), Vector::new(0.5, 0.25, 0.5), Vector::ZERO)?;
    /// world.set_fluid_heat(FluidHeat { temperature: 20.0, conductivity: 1e-3 })?;
    /// world.set_heat_source(plate, Some(HeatSource { temperature: 90.0, conductivity: 1e-3 }))?;
    /// for _ in 0..5 {
    ///     world.step(Vector::new(0.0, -9.81, 0.0), 0.01)?;
    /// }
    /// let warmest = world.fluid().temperature.iter().copied().fold(0.0f32, f32::max);
    /// assert!(warmest > 20.5 && warmest < 90.0);
    /// # Ok::<(), FluidError>(())
    /// ```
    pub fn set_fluid_heat(&mut self, heat: FluidHeat) -> Result<()> {
        heat.validate()?;
        self.start_heat(heat);
        Ok(())
    }

    /// Models heat from now on: every fluid carrier, and every one made later, at
    /// `heat.temperature`.
    fn start_heat(&mut self, heat: FluidHeat) {
        self.heat = Some(heat);
        self.fluid.ambient = Some(heat.temperature);
        self.fluid.temperature = vec![heat.temperature; self.fluid.len()];
    }

    /// The fluid's heat settings, if heat is modelled.
    pub fn fluid_heat(&self) -> Option<FluidHeat> {
        self.heat
    }

    /// Holds solid `h` at a fixed temperature (a hot plate), or (`None`) stops it exchanging
    /// heat.
    pub fn set_heat_source(&mut self, h: SolidHandle, source: Option<HeatSource>) -> Result<()> {
        if let Some(s) = &source {
            s.validate()?;
        }
        let solid = self
            .solids
            .get_mut(h.0 as usize)
            .ok_or_else(|| FluidError::Coupling(format!("no solid with handle {}", h.0)))?;
        solid.heat = source;
        if source.is_some() {
            self.ensure_heat();
        }
        Ok(())
    }

    /// Switches the fluid's temperatures on (at the default heat) if they are not yet.
    pub(crate) fn ensure_heat(&mut self) {
        if self.heat.is_none() {
            self.start_heat(FluidHeat::default());
        }
    }

    /// Whether a step exchanges heat: a melting body or a heat source is in the world.
    pub(crate) fn heat_on(&self) -> bool {
        self.deformables
            .iter()
            .any(|b| b.params.melting.is_some() && !b.x.is_empty())
            || self.solids.iter().any(|s| s.heat.is_some() && !s.removed)
    }

    /// One step's heat exchange over `dt` (implicit, [`Exchange::apply`]).
    pub(crate) fn exchange_heat(&mut self, dt: f32, rep: &mut StepReport) {
        let Some(heat) = self.heat else { return };
        let nf = self.fluid.len();
        if self.fluid.temperature.len() != nf || self.lists.offsets.len() != nf + 1 {
            return;
        }
        let lap = Laplacian::new(self.kernel, self.params.spacing);
        for b in self
            .deformables
            .iter_mut()
            .filter(|b| b.params.melting.is_some())
        {
            b.update_rings();
        }
        // each melting body's lattice points follow the fluid in the temperature vector; each
        // of their carriers names its point there
        let mut owner = vec![(u32::MAX, 0.0f32); self.solid.len()];
        let mut offsets = Vec::new();
        let mut next = nf as u32;
        for b in &self.deformables {
            let Some(m) = b.params.melting.filter(|_| !b.x.is_empty()) else {
                offsets.push(None);
                continue;
            };
            let first = self.solids[b.solids[0] as usize].range.start;
            for k in 0..b.sbp_rest.len() {
                owner[first + k] = (next + b.carriers.row(k)[0].0, m.conductivity);
            }
            offsets.push(Some(next));
            next += b.x.len() as u32;
        }
        let sources: Vec<Option<HeatSource>> = self.solids.iter().map(|s| s.heat).collect();
        let (x, sx, sb, lists) = (&self.fluid.x, &self.solid.x, &self.solid.body, &self.lists);
        let kf = heat.conductivity;
        // fluid rows: fluid and body neighbours, heat sources
        let rows: Vec<Row> = (0..nf)
            .into_par_iter()
            .map(|i| {
                let (mut row, mut fixed) = (Vec::new(), (0.0f32, 0.0f32));
                for &j in lists.row(i) {
                    let j = j as usize;
                    if j < nf {
                        if kf > 0.0 {
                            let a = dt * kf * lap.weight((x[i] - x[j]).length());
                            row.push((j as u32, a));
                        }
                        continue;
                    }
                    let s = j - nf;
                    let r = (x[i] - sx[s]).length();
                    if let Some(src) = sources[sb[s] as usize] {
                        let a = dt * 0.5 * (kf + src.conductivity) * lap.weight(r);
                        fixed.0 += a;
                        fixed.1 += a * src.temperature;
                    } else if owner[s].0 != u32::MAX {
                        let a = dt * 0.5 * (kf + owner[s].1) * lap.weight(r);
                        row.push((owner[s].0, a));
                    }
                }
                row.retain(|e| e.1 > 0.0);
                (row, fixed)
            })
            .collect();
        let total = next as usize;
        let mut body_rows: Vec<Vec<(u32, f32)>> = vec![Vec::new(); total - nf];
        for (i, (row, _)) in rows.iter().enumerate() {
            for &(j, a) in row.iter().filter(|e| e.0 as usize >= nf) {
                body_rows[j as usize - nf].push((i as u32, a));
            }
        }
        let mut t = std::mem::take(&mut self.fluid.temperature);
        for (b, off) in self.deformables.iter().zip(&offsets) {
            let (Some(off), Some(m)) = (off, b.params.melting) else {
                continue;
            };
            let a_of = |r: f32| dt * m.conductivity * lap.weight(r);
            for (d, ring) in b.rings.iter().enumerate() {
                let row = &mut body_rows[(*off as usize - nf) + d];
                for &e in ring {
                    let a = a_of((b.rest[d] - b.rest[e as usize]).length());
                    row.push((off + e, a));
                }
            }
            t.extend_from_slice(&b.temperature);
        }
        let (fluid_rows, mut fixed): (Vec<_>, Vec<_>) = rows.into_iter().unzip();
        fixed.resize(total, (0.0, 0.0));
        let ex = Exchange {
            pairs: Rows::from_rows(fluid_rows.into_iter().chain(body_rows)),
            fixed,
        };
        rep.heat_sweeps = ex.apply(&mut t);
        for (b, off) in self.deformables.iter_mut().zip(&offsets) {
            if let Some(off) = off {
                let o = *off as usize;
                b.temperature.copy_from_slice(&t[o..o + b.x.len()]);
            }
        }
        t.truncate(nf);
        self.fluid.temperature = t;
    }
}
