//! Stage: free surface (He 2012 Eq. 25) and isolated regions (Table 3 t_surface): surface
//! carriers get p^v = 0 in the velocity constraint. Also the density loop's surface pressure
//! ([`extrapolate_surface`]).

use super::Substep;
use crate::math::Vector;
use crate::solver::surface;
use crate::world::FluidWorld;
use rayon::prelude::*;

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

/// Free-surface carriers' p^d from their inner neighbours' pressure and pressure gradient,
/// `p_i = Σ_j W_ij (p_j + ∇p_j·(x_i − x_j)) / Σ_j W_ij` with `∇p_j = −ρ̄ a_j` (a_j the last
/// iteration's pressure acceleration), limited to the lowest of those neighbours' pressures
/// (no new maximum in a transient) and kept where it is above the EOS value: the pressure field
/// continued linearly to the surface layer (Adami et al. 2012's wall extrapolation applied at
/// the free surface, with the fluid's own pressure gradient in place of ρ(g − a), so a free
/// jet, whose gradient is zero, gets no pressure). Only carriers of a surface layer (with a
/// surface neighbour) are continued: a sealed region's pinned carrier, alone among inner ones,
/// keeps its p = 0 convention. A flat layer's weight is then carried as in
/// the bulk, p = ρ̄g(Δx/2) at the top carriers; with p = 0 there the layer below carried 2ρ̄gΔx.
pub(super) fn extrapolate_surface(
    p: &mut [f32],
    surface: &[bool],
    x: &[Vector],
    accel: &[Vector],
    lists: &crate::neighbors::NeighborLists,
    kernel: &crate::kernel::CubicSpline,
    rest: f32,
) {
    let n = p.len();
    if surface.len() != n || accel.len() != n || lists.offsets.len() != n + 1 {
        return;
    }
    let new: Vec<(u32, f32)> = (0..n)
        .into_par_iter()
        .filter(|&i| surface[i])
        .filter_map(|i| {
            let (mut s, mut ws, mut layer, mut low) = (0.0f32, 0.0f32, false, f32::INFINITY);
            for &j in &lists.indices[lists.fluid_range(i)] {
                let j = j as usize;
                if surface[j] {
                    layer = true;
                    continue;
                }
                let d = x[i] - x[j];
                let w = kernel.w(d.length());
                s += w * (p[j] - rest * accel[j].dot(d));
                ws += w;
                if w > 0.0 {
                    low = low.min(p[j]);
                }
            }
            let v = (s / ws).min(low);
            (layer && ws > 0.0 && v > p[i]).then_some((i as u32, v))
        })
        .collect();
    for (i, v) in new {
        p[i as usize] = v;
    }
}
