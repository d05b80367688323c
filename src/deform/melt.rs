//! Melting (Shao et al. 2014 §3.4.2): the lattice points of a melting body that reached their
//! melting point on its surface — fewer than the 26 lattice neighbours of a full one-ring —
//! turn into fluid carriers with their mass and momentum — once they have also taken their
//! latent heat ([`super::Melting::latent_heat`], an enthalpy store: heat past the melting
//! point goes into it, the temperature stays at the melting point). Only the surface at the start of a
//! step melts in it, so the body melts from the outside in whatever the heat did inside.
//!
//! A lattice point's mass (the body's density times its cell) is rarely a fluid carrier's
//! (the fluid's rest density times `Δx³`): melted mass and momentum gather in the body's pool,
//! and a carrier is made, at the lattice point that completes its mass, whenever the pool holds
//! one. The pool keeps the rest, so mass and momentum are conserved exactly
//! ([`super::Deformable::melt_pending`]). A body denser than the fluid makes several carriers
//! of one point, set a quarter spacing apart in its cell: it melts into more volume.

use super::lattice::{self, Rows};
use crate::math::Vector;
use crate::metrics::StepReport;
use crate::world::{retain_where, FluidWorld};
use std::collections::HashSet;

/// Where the `k`-th carrier made of one lattice point sits in its cell (body frame).
fn spot(k: usize, dx: f32) -> Vector {
    if k == 0 {
        return Vector::ZERO;
    }
    let c = (k - 1) % 8;
    let s = |bit: usize| if c & bit == 0 { -0.25 } else { 0.25 };
    Vector::new(s(1), s(2), s(4)) * dx
}

impl FluidWorld {
    /// The phase change of a step: each melting body's surface points at their melting point
    /// become fluid carriers ([`self`]).
    pub(crate) fn melt(&mut self, rep: &mut StepReport) {
        for bi in 0..self.deformables.len() {
            let b = &self.deformables[bi];
            let Some(m) = b.params.melting.filter(|_| !b.x.is_empty()) else {
                continue;
            };
            let b = &mut self.deformables[bi];
            if m.latent_heat > 0.0 {
                // heat past the melting point goes into melting
                for (t, h) in b.temperature.iter_mut().zip(b.absorbed.iter_mut()) {
                    if *t > m.melting_point {
                        *h += *t - m.melting_point;
                        *t = m.melting_point;
                    }
                }
            }
            b.update_rings();
            let melting: Vec<bool> = (0..b.x.len())
                .map(|i| {
                    b.temperature[i] >= m.melting_point
                        && b.absorbed[i] >= m.latent_heat
                        && b.rings[i].len() < 26
                })
                .collect();
            if melting.iter().any(|&m| m) {
                self.liquefy(bi, &melting, rep);
            }
        }
    }

    /// Turns the points `melting` of body `bi` into fluid (through its pool) and drops them.
    fn liquefy(&mut self, bi: usize, melting: &[bool], rep: &mut StepReport) {
        let (mf, dx, g) = (self.mass as f64, self.params.spacing, self.step_gravity);
        let b = &mut self.deformables[bi];
        let mb = b.mass as f64;
        let mut made: Vec<(Vector, Vector, f32)> = Vec::new();
        for i in (0..b.x.len()).filter(|&i| melting[i]) {
            b.pool.mass += mb;
            for k in 0..3 {
                b.pool.momentum[k] += mb * b.v[i][k] as f64;
            }
            let mut k = 0;
            while b.pool.mass >= mf {
                let v = Vector::from_array(b.pool.momentum.map(|p| (p / b.pool.mass) as f32));
                made.push((b.x[i] + b.rotation[i] * spot(k, dx), v, b.temperature[i]));
                b.pool.mass -= mf;
                for k in 0..3 {
                    b.pool.momentum[k] -= mf * v[k] as f64;
                }
                k += 1;
            }
            rep.melted += 1;
        }
        for (x, v, t) in made {
            self.fluid.push(x, v, self.next_id);
            self.next_id += 1;
            if let Some(last) = self.fluid.temperature.last_mut() {
                *last = t;
            }
            self.added_energy += mf * crate::step::carrier_energy(x, v, g);
            rep.melt_carriers += 1;
        }
        let keep: Vec<bool> = melting.iter().map(|m| !m).collect();
        self.drop_points(bi, &keep);
    }

    /// Removes body `bi`'s lattice points not in `keep`, with their carriers: the regions are
    /// rebuilt on what is left, the points that lost a neighbour face the gap (their normal the
    /// mean direction of their missing neighbours), and chunks left without a carrier are
    /// removed.
    fn drop_points(&mut self, bi: usize, keep: &[bool]) {
        let dx = self.params.spacing;
        let b = &mut self.deformables[bi];
        let gone: HashSet<[i32; 3]> = (0..keep.len())
            .filter(|&i| !keep[i])
            .map(|i| b.cells[i])
            .collect();
        let mut index = vec![u32::MAX; keep.len()];
        for (n, (i, _)) in keep.iter().enumerate().filter(|e| *e.1).enumerate() {
            index[i] = n as u32;
        }
        retain_where(&mut b.rest, keep);
        retain_where(&mut b.x, keep);
        retain_where(&mut b.v, keep);
        retain_where(&mut b.pinned, keep);
        retain_where(&mut b.rotation, keep);
        retain_where(&mut b.region_rotation, keep);
        retain_where(&mut b.cells, keep);
        retain_where(&mut b.temperature, keep);
        retain_where(&mut b.absorbed, keep);
        retain_where(&mut b.chunk, keep);
        b.regions = lattice::regions(&b.cells, b.params.half_width);
        // SBPs: each its own lattice point
        let first = self.solids[b.solids[0] as usize].range.start;
        let own: Vec<usize> = (0..b.sbp_rest.len())
            .map(|k| b.carriers.row(k)[0].0 as usize)
            .collect();
        let keep_sbp: Vec<bool> = own.iter().map(|&d| keep[d]).collect();
        b.carriers = Rows::from_rows(
            own.iter()
                .filter(|&&d| keep[d])
                .map(|&d| vec![(index[d], 1.0)]),
        );
        if b.sbp_rotation.len() != b.sbp_rest.len() {
            b.sbp_rotation.clear();
        } else {
            retain_where(&mut b.sbp_rotation, &keep_sbp);
        }
        retain_where(&mut b.sbp_rest, &keep_sbp);
        b.seen.clear();
        let mut all = vec![true; self.solid.len()];
        for (k, kept) in keep_sbp.iter().enumerate() {
            all[first + k] = *kept;
        }
        self.retain_solid_carriers(&all);
        // the points beside the gap face it
        let b = &mut self.deformables[bi];
        let at: HashSet<[i32; 3]> = b.cells.iter().copied().collect();
        for k in 0..b.sbp_rest.len() {
            let d = b.carriers.row(k)[0].0 as usize;
            let c = b.cells[d];
            if !lattice::neighbour_offsets().any(|o| gone.contains(&lattice::shifted(c, o))) {
                continue;
            }
            let n: Vector = lattice::neighbour_offsets()
                .filter(|o| !at.contains(&lattice::shifted(c, *o)))
                .map(|o| Vector::new(o[0] as f32, o[1] as f32, o[2] as f32))
                .sum();
            if let Some(n) = n.try_normalize() {
                b.sbp_rest[k].1 = n;
                self.solid.n[first + k] = b.rotation[d] * n;
                self.solid.depth[first + k] = 0.5 * dx;
            }
        }
        // chunks left without carriers go
        let empty: Vec<bool> = b
            .solids
            .iter()
            .map(|&s| self.solids[s as usize].range.is_empty())
            .collect();
        let mut slot = vec![u32::MAX; b.solids.len()];
        let mut c = 0;
        for (k, e) in empty.iter().enumerate() {
            if *e {
                let s = &mut self.solids[b.solids[k] as usize];
                (s.removed, s.active, s.rigid) = (true, false, None);
            } else {
                slot[k] = c;
                c += 1;
            }
        }
        let mut k = empty.iter();
        b.solids.retain(|_| !*k.next().unwrap_or(&false));
        for ch in b.chunk.iter_mut().filter(|c| **c != u32::MAX) {
            *ch = slot[*ch as usize];
        }
        let mut groups = vec![Vec::new(); b.solids.len()];
        for (i, &ch) in b.chunk.iter().enumerate() {
            if ch != u32::MAX {
                groups[ch as usize].push(i as u32);
            }
        }
        b.members = Rows::from_rows(groups);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deform::{DeformableParams, Melting};
    use crate::math::Pose;
    use crate::params::FluidParams;
    use crate::solver::staggered::Slip;
    use rapier3d::parry::shape::SharedShape;

    /// Mass and momentum of fluid, body and pool, in f64.
    fn totals(w: &FluidWorld) -> (f64, [f64; 3]) {
        let b = &w.deformables[0];
        let (mf, mb) = (w.mass as f64, b.mass as f64);
        let mut p = b.pool.momentum;
        for v in &w.fluid.v {
            (0..3).for_each(|k| p[k] += mf * v[k] as f64);
        }
        for v in &b.v {
            (0..3).for_each(|k| p[k] += mb * v[k] as f64);
        }
        let m = w.fluid.len() as f64 * mf + b.x.len() as f64 * mb + b.pool.mass;
        (m, p)
    }

    /// Liquefaction keeps mass and momentum to round-off, melts only the surface (a 4³ block
    /// all above its melting point loses its 56 surface points, keeps its 2³ core), and the
    /// rest of the body stays consistent: carriers, chunks, normals facing the gap.
    #[test]
    fn liquefaction_conserves_mass_and_momentum_and_starts_at_the_surface() {
        for density in [700.0, 1000.0, 2600.0] {
            let dx = 0.02;
            let mut w = FluidWorld::new(FluidParams {
                spacing: dx,
                domain: Some(([-1.0; 3], [1.0; 3])),
                ..Default::default()
            })
            .unwrap();
            w.add_open_tank(Vector::ZERO, Vector::splat(0.3), Slip::FreeSlip)
                .unwrap();
            w.add_block(Vector::ZERO, Vector::new(0.3, 0.06, 0.3), Vector::ZERO)
                .unwrap();
            let melting = Melting {
                temperature: 5.0,
                melting_point: 0.0,
                conductivity: 1e-3,
                latent_heat: 0.0,
            };
            w.add_deformable(
                "ice",
                SharedShape::cuboid(0.04, 0.04, 0.04),
                Pose::from_translation(Vector::new(0.15, 0.2, 0.15)),
                DeformableParams {
                    density,
                    melting: Some(melting),
                    ..Default::default()
                },
            )
            .unwrap();
            let b = &mut w.deformables[0];
            assert_eq!(b.x.len(), 64);
            for (i, v) in b.v.iter_mut().enumerate() {
                *v = Vector::new(0.3 + 0.01 * i as f32, -0.2, (i % 7) as f32 * 0.05);
            }
            let n_solid = w.solid.len();
            let (m0, p0) = totals(&w);
            let mut rep = StepReport::default();
            w.melt(&mut rep);
            let (m1, p1) = totals(&w);
            assert!((m1 - m0).abs() <= 1e-12 * m0, "mass {m0} → {m1}");
            for k in 0..3 {
                assert!(
                    (p1[k] - p0[k]).abs() <= 1e-6 * m0,
                    "momentum {p0:?} → {p1:?}"
                );
            }
            let b = &w.deformables[0];
            assert_eq!((rep.melted, b.x.len()), (56, 8));
            assert_eq!(w.solid.len(), n_solid - 56);
            // the carriers made: the melted mass over a carrier's, the rest pooled
            let made = (56.0 * b.mass as f64 / w.mass as f64).floor() as u64;
            assert_eq!(rep.melt_carriers, made, "density {density}");
            assert!(b.pool.mass < w.mass as f64);
            // each remaining carrier is its own point, and every one faces out of the core
            let first = w.solids[b.solids[0] as usize].range.start;
            let c = b.center_of_mass();
            for k in 0..b.sbp_rest.len() {
                let d = b.carriers.row(k)[0].0 as usize;
                assert_eq!(w.solid.x[first + k], b.x[d]);
                assert!(w.solid.n[first + k].dot(b.x[d] - c) > 0.5 * dx);
            }
            let members: usize = (0..b.members.len()).map(|c| b.members.row(c).len()).sum();
            assert_eq!(members, 8);
        }
    }
}
