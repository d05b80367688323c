//! Structure-of-arrays carrier storage (He 2012 §4): fluid carriers and solid carriers.

use crate::math::Vector;
use serde::{Deserialize, Serialize};

/// Fluid carrier particles, one entry per particle in each array.
///
/// The arrays are re-ordered by grid cell every step (for memory locality); [`FluidCarriers::id`]
/// keeps each particle's stable identity.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct FluidCarriers {
    /// Positions.
    pub x: Vec<Vector>,
    /// Velocities.
    pub v: Vec<Vector>,
    /// Stable particle identifiers (creation order).
    pub id: Vec<u32>,
    /// Density (Eq. 22) at the end of the last step, kg/m³.
    pub density: Vec<f32>,
    /// Density-constraint pressure p^d of the last density iteration, Pa.
    pub p_density: Vec<f32>,
    /// Velocity-constraint pressure p^v of the last step, Pa.
    pub p_velocity: Vec<f32>,
    /// The density constraint's pressure memory, Pa: a running mean of p^d that each step's
    /// density constraint starts from ([`crate::FluidParams::density_memory`]).
    #[serde(default)]
    pub p_memory: Vec<f32>,
    /// Acceleration over the last substep, m/s² (what the hydrostatic wall pressure carries
    /// the fluid's pressure to the walls with: `g − a`, [`crate::FluidParams::hydrostatic_walls`]).
    #[serde(default)]
    pub accel: Vec<Vector>,
    /// Free-surface flag of the last step (Eq. 25).
    pub surface: Vec<bool>,
    /// Number of carrier neighbours `N_i` of the last step (Eq. 7).
    pub neighbors: Vec<u32>,
    /// Temperatures, °C — empty until heat is modelled (a melting body or a heat source in the
    /// world, [`crate::FluidWorld::set_fluid_heat`]); then one per carrier.
    #[serde(default)]
    pub temperature: Vec<f32>,
    /// The temperature new carriers take, °C, once [`Self::temperature`] is kept.
    #[serde(default)]
    pub(crate) ambient: Option<f32>,
    /// Each carrier's density when water was last placed at rest, kg/m³, while the placement's
    /// compression is still being relieved (`FluidWorld::placement`); empty otherwise.
    #[serde(default)]
    pub(crate) placed_rho: Vec<f32>,
}

impl FluidCarriers {
    /// Number of fluid carriers.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there is no fluid carrier.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    pub(crate) fn push(&mut self, x: Vector, v: Vector, id: u32) {
        self.x.push(x);
        self.v.push(v);
        self.id.push(id);
        self.density.push(0.0);
        self.p_density.push(0.0);
        self.p_velocity.push(0.0);
        self.p_memory.push(0.0);
        self.accel.push(Vector::ZERO);
        self.surface.push(false);
        self.neighbors.push(0);
        if let Some(t) = self.ambient {
            self.temperature.push(t);
        }
        if !self.placed_rho.is_empty() {
            self.placed_rho.push(0.0);
        }
    }

    /// Applies the permutation `order` (new index → old index) to every array.
    pub(crate) fn permute(&mut self, order: &[u32]) {
        fn apply<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            let out: Vec<T> = order.iter().map(|&o| v[o as usize]).collect();
            *v = out;
        }
        if self.p_memory.len() != self.x.len() {
            // a snapshot from before the memory existed
            self.p_memory = vec![0.0; self.x.len()];
        }
        if self.accel.len() != self.x.len() {
            self.accel = vec![Vector::ZERO; self.x.len()];
        }
        if let Some(t) = self.ambient {
            self.temperature.resize(self.x.len(), t);
        }
        if self.placed_rho.len() != self.x.len() {
            self.placed_rho.clear();
        }
        apply(&mut self.x, order);
        apply(&mut self.v, order);
        apply(&mut self.id, order);
        apply(&mut self.density, order);
        apply(&mut self.p_density, order);
        apply(&mut self.p_velocity, order);
        apply(&mut self.p_memory, order);
        apply(&mut self.accel, order);
        apply(&mut self.surface, order);
        apply(&mut self.neighbors, order);
        if self.ambient.is_some() {
            apply(&mut self.temperature, order);
        }
        if !self.placed_rho.is_empty() {
            apply(&mut self.placed_rho, order);
        }
    }

    /// Keeps only the particles for which `keep[i]` is true.
    pub(crate) fn retain(&mut self, keep: &[bool]) {
        let order: Vec<u32> = (0..self.len() as u32)
            .filter(|&i| keep[i as usize])
            .collect();
        self.permute(&order);
    }
}

/// Solid carrier particles sampled from the shells of coupled solids (He 2012 §5).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct SolidCarriers {
    /// Index of the owning solid in [`crate::FluidWorld::solids`].
    pub body: Vec<u32>,
    /// World position (updated from the solid's pose).
    pub x: Vec<Vector>,
    /// World outward unit normal.
    pub n: Vec<Vector>,
    /// World velocity `U + ω × (x − X)`.
    pub u: Vec<Vector>,
    /// Relative volume of each carrier (Akinci et al. 2012 boundary volume over that of a
    /// carrier in a flat wall aligned with the fluid lattice): 1 on flat walls, below 1 where
    /// the shell is packed more densely (the outer layer of a convex body), above 1 where it is
    /// sparser. Scales the carrier's share of fluid density and of the wall pressure force.
    pub volume: Vec<f32>,
    /// Depth of each carrier below its solid's surface, m (`−φ` where it was sampled): puts a
    /// no-slip wall's velocity on the surface itself in the wall shear (Morris et al. 1997).
    #[serde(default)]
    pub depth: Vec<f32>,
    /// Force of the fluid on each carrier over the last step, N (the `F_i^s` of Eq. 21). A
    /// fixed solid's force and torque are their sum and moment; a dynamic body passes part of
    /// the explicit stages' pushes on to the water beside it (so a light body cannot
    /// overshoot), and [`crate::Solid::force`] is what it kept.
    pub f: Vec<Vector>,
}

impl SolidCarriers {
    /// Number of solid carriers.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// Whether there is no solid carrier.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Deletes the carriers in `r` from every array.
    pub(crate) fn remove_range(&mut self, r: std::ops::Range<usize>) {
        self.body.drain(r.clone());
        self.x.drain(r.clone());
        self.n.drain(r.clone());
        self.u.drain(r.clone());
        self.f.drain(r.clone());
        self.volume.drain(r.clone());
        if self.depth.len() >= r.end {
            self.depth.drain(r);
        }
    }
}
