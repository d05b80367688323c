//! The water beside a deformable body moves with its deformation (the lumps of
//! `world/lumps.rs`, per IBP).
//!
//! The fluid's stages see a deformable body's surface as a wall with a given velocity; the
//! impulses they give it then change its IBPs' velocities after the substep — explicit
//! coupling. An IBP of a wall with water behind it weighs a fraction of that water (a 2Δx
//! wall of 1 000 kg/m³ against a 0.12 m column), so each substep's push overshot and the
//! next pushed back harder: an elastic box holding water erupted in three frames. Here the
//! velocity change `Δv_d` an IBP takes from the water moves it together with the fluid
//! carriers beside its SBPs: with `μ_d` their mass attached to it (each carrier shares itself
//! by the fraction of its neighbours that are this body's SBPs, split among those SBPs and on
//! through their weights to the IBPs), the lump's velocity change is `m Δv_d / (m + μ_d)`
//! for the IBP and, weighted, for those carriers. Momentum is exact; a heavy IBP keeps its
//! whole kick.

use crate::math::Vector;
use crate::world::FluidWorld;
use rayon::prelude::*;

/// Rows of fluid carriers gathered per parallel task.
const ROWS: usize = 1024;

impl FluidWorld {
    /// Shares the velocity changes `dv` of deformable body `b`'s IBPs with the fluid carriers
    /// beside it; `dv` becomes what the IBPs keep.
    pub(crate) fn share_with_water(&mut self, b: usize, dv: &mut [Vector]) {
        let nf = self.fluid.len();
        if self.lists.offsets.len() != nf + 1 || dv.iter().all(|d| *d == Vector::ZERO) {
            return;
        }
        let body = &self.deformables[b];
        let range = self.solids[body.solids[0] as usize].range.start
            ..self.solids[*body.solids.last().expect("a body has a solid") as usize]
                .range
                .end;
        let h = self.params.support_radius();
        let (x, sx, lists) = (&self.fluid.x, &self.solid.x, &self.lists);
        // (fluid carrier, IBP, the carrier's share attached to the IBP, the SBP through which)
        let links: Vec<(u32, u32, f32, u32)> = (0..nf.div_ceil(ROWS))
            .into_par_iter()
            .map(|c| {
                let mut out = Vec::new();
                for i in c * ROWS..((c + 1) * ROWS).min(nf) {
                    let near = |p: Vector| (p - x[i]).length() < h;
                    let mine: Vec<usize> = lists.indices[lists.solid_range(i)]
                        .iter()
                        .map(|&j| j as usize - nf)
                        .filter(|&s| range.contains(&s) && near(sx[s]))
                        .collect();
                    if mine.is_empty() {
                        continue;
                    }
                    let solids = lists.indices[lists.solid_range(i)]
                        .iter()
                        .filter(|&&j| near(sx[j as usize - nf]))
                        .count();
                    let fluid = lists.indices[lists.fluid_range(i)]
                        .iter()
                        .filter(|&&j| j as usize != i && near(x[j as usize]))
                        .count();
                    let share = 1.0 / (fluid + solids).max(1) as f32;
                    for s in mine {
                        for &(d, w) in body.carriers.row(s - range.start) {
                            out.push((i as u32, d, share * w, s as u32));
                        }
                    }
                }
                out
            })
            .collect::<Vec<_>>()
            .into_iter()
            .flatten()
            .collect();
        let m = body.mass;
        let mf = self.mass;
        let mut mu = vec![0.0f32; dv.len()];
        for &(_, d, a, _) in &links {
            mu[d as usize] += mf * a;
        }
        for (d, mu) in dv.iter_mut().zip(&mu) {
            *d *= m / (m + mu);
        }
        for &(i, d, a, s) in &links {
            let du = dv[d as usize] * a;
            self.fluid.v[i as usize] += du;
            // what the water got back is no longer the body's: its solid's force is the net
            // exchange with the water
            self.book_on_solid(s as usize, -mf * du);
        }
    }
}
