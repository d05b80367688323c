//! Stage: the remap (He 2012 Eq. 19 and its consistent form): the solved p^v applied to the
//! carriers, then the wall conditions of no-slip walls (Eq. 26) and of free-surface carriers
//! beside walls (Eq. 27).

use super::Substep;
use crate::math::Vector;
use crate::params::Remap;
use crate::solver::staggered::Slip;
use crate::solver::ROWS;
use crate::solver::{density, projection, velocity};
use crate::world::FluidWorld;
use rayon::prelude::*;

impl FluidWorld {
    /// Carrier velocities from the pressure in the scratch's `p`; every impulse on a solid
    /// carrier goes to its body.
    pub(crate) fn remap(&mut self, s: &Substep) {
        let (n, dt) = (self.fluid.len(), s.dt);
        if self.params.remap == Remap::Consistent {
            let imp = velocity::apply_pressure(
                &ctx!(self, &s.bodies),
                &self.system,
                &self.scratch.p,
                dt,
                &mut self.fluid.v,
            );
            // the rigid rows' reaction moves a body with the water beside it, as the explicit
            // stages' do (`world/lumps.rs`): taken alone, it spun a 10 kg/m³ cube up 15–25 %
            // a substep
            self.absorb_shared(imp);
            let kappa = self.exchange_weights(s);
            let sc = &self.scratch;
            let imp = velocity::no_slip(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &sc.shares,
                &sc.count,
                &mut self.fluid.v,
                &kappa,
            );
            self.absorb(imp);
            let sc = &self.scratch;
            let imp = velocity::surface_walls(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &sc.shares,
                &sc.count,
                &self.system.unknown,
                &mut self.fluid.v,
            );
            self.absorb_shared(imp);
            return;
        }
        let sc = &mut self.scratch;
        sc.v_old.clone_from(&self.fluid.v);
        let imp = projection::remap(
            &ctx!(self, &s.bodies),
            &self.fluid.x,
            &sc.v_old,
            &sc.shares,
            &sc.count,
            &sc.p,
            dt,
            self.params.remap,
            &mut self.fluid.v,
        );
        self.absorb(imp);
        if self.params.remap == Remap::Conservative {
            let sc = &mut self.scratch;
            sc.accel.resize(n, Vector::ZERO);
            let imp = density::pressure_accel(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &sc.p,
                &sc.rho,
                &mut sc.accel,
                dt,
                // (a velocity pressure: no hydrostatic part)
                density::WallPush::Normal(Vector::ZERO),
                None,
                &[],
                None,
            );
            self.absorb(imp);
            let fl = &mut self.fluid;
            fl.v.par_iter_mut()
                .zip(self.scratch.accel.par_iter())
                .for_each(|(v, &a)| *v += a * dt);
        }
    }
}

impl FluidWorld {
    /// Per solid, the share of Eq. 26's exchange that is applied: `κ = M / (M + m_c)` for a
    /// moving dynamic body of mass `M` whose no-slip neighbours would move `m_c` of fluid
    /// (each carrier's mass times the fraction of its neighbours in the body), 1 for the
    /// rest. The exchange as printed gives the body `Σ m (v − u)`, which for a body much
    /// lighter than the water beside it overshoots many times over (a 30 kg/m³ ball erupted
    /// in its second frame); with `κ` the fluid and the body meet at their mass-weighted
    /// velocity, as an inelastic collision does, and a heavy body (`M ≫ m_c`) is Eq. 26.
    fn exchange_weights(&self, s: &Substep) -> Vec<f32> {
        let mut kappa = vec![1.0f32; s.bodies.len()];
        let moving: Vec<bool> = s
            .bodies
            .iter()
            .map(|b| b.rigid != u32::MAX && b.slip == Slip::NoSlip)
            .collect();
        if !moving.iter().any(|&m| m) {
            return kappa;
        }
        let (nf, h) = (self.fluid.len(), self.params.support_radius());
        // per fixed block of rows, then summed in block order: independent of the threads
        let parts: Vec<Vec<f64>> = (0..nf.div_ceil(ROWS))
            .into_par_iter()
            .map(|c| {
                let mut m_c = vec![0.0f64; s.bodies.len()];
                for i in c * ROWS..((c + 1) * ROWS).min(nf) {
                    let inv_n = 1.0 / self.scratch.count[i].max(1) as f64;
                    for &j in &self.lists.indices[self.lists.solid_range(i)] {
                        let sj = j as usize - nf;
                        let b = self.solid.body[sj] as usize;
                        if moving[b] && (self.solid.x[sj] - self.fluid.x[i]).length() < h {
                            m_c[b] += self.mass as f64 * inv_n;
                        }
                    }
                }
                m_c
            })
            .collect();
        for (b, v) in s.bodies.iter().enumerate() {
            if moving[b] {
                let m_c: f64 = parts.iter().map(|p| p[b]).sum();
                let m = self.rigids[v.rigid as usize].mprops.mass() as f64;
                kappa[b] = (m / (m + m_c)) as f32;
            }
        }
        kappa
    }
}
