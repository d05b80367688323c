//! A deformable body's data: its material, its IBPs (structure of arrays), how its SBPs
//! hang on them, and what a user reads (positions, momentum, bound points).

use super::lattice::{self, Rows};
use crate::error::{FluidError, Result};
use crate::math::{Rotation, Vector};
use crate::solver::staggered::Slip;
use rapier3d::math::Matrix;
use serde::{Deserialize, Serialize};

pub use super::lattice::MAX_HALF_WIDTH;

/// Handle of a deformable body added to a [`crate::FluidWorld`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct DeformableHandle(pub u32);

/// A deformable body's material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DeformableParams {
    /// Density, kg/m³.
    pub density: f32,
    /// α in (0, 1]: the share of the way to its goal position an IBP is moved each substep
    /// (Müller et al. 2005's blend). 1 keeps the shape as far as the regions allow; lower is
    /// softer. A cloth takes α at a reference substep, its first step split by
    /// [`crate::FluidParams::body_force_limit`] (the same under either solver), and keeps that
    /// stiffness `α m / Δt₁²` at whatever substeps follow.
    pub stiffness: f32,
    /// Region half-width w in lattice steps, 1 ..= [`MAX_HALF_WIDTH`]: wider regions resist
    /// bending more (Rivers & James 2007).
    pub half_width: u32,
    /// Slip condition of its surface.
    pub slip: Slip,
    /// ζ in [0, 1): the share of its deformation's velocity (relative to its rigid motion) it
    /// loses each substep — internal friction, so a jelly stops wobbling; 0 keeps it.
    #[serde(default)]
    pub damping: f32,
    /// How it melts (Shao §3.4.2), if it does: then every lattice point is a solid carrier the
    /// fluid can reach once the points outside it have melted.
    #[serde(default)]
    pub melting: Option<Melting>,
}

/// A melting material (Shao et al. 2014 §3.4.2): the body's lattice points take heat from the
/// water and each other (Eq. 20) and, once at their melting point and on the surface, turn into
/// water.
///
/// Conductivities are diffusivities, m²/s: every material and the fluid hold the same heat per
/// volume and degree (Shao's model has no heat capacity and no latent heat), so what Eq. 20
/// conserves is the sum of the temperatures over particles of one lattice cell each.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Melting {
    /// The body's temperature when it is added, °C.
    pub temperature: f32,
    /// Melting point T_melt, °C.
    pub melting_point: f32,
    /// Heat conductivity K, m²/s (≥ 0).
    pub conductivity: f32,
    /// Latent heat, as the degrees of warming the same heat would give (≥ 0; ice: 80 °C, its
    /// 334 kJ/kg over water's 4.18 kJ/(kg K)): a point at its melting point takes this much
    /// more heat before it melts. 0, Shao's model, melts a point as soon as it reaches its
    /// melting point.
    #[serde(default)]
    pub latent_heat: f32,
}

impl Default for Melting {
    /// Ice at −5 °C melting at 0 °C, K = 1e-4 m²/s (a game's ice: real ice, 1.2e-6 m²/s, takes
    /// hours to melt a 10 cm cube by conduction alone).
    fn default() -> Self {
        Melting {
            temperature: -5.0,
            melting_point: 0.0,
            conductivity: 1e-4,
            latent_heat: 0.0,
        }
    }
}

impl Melting {
    pub(crate) fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("Melting::temperature", self.temperature),
            ("Melting::melting_point", self.melting_point),
        ] {
            if !v.is_finite() {
                return Err(FluidError::NonFinite {
                    what: format!("{name} ({v})"),
                });
            }
        }
        if !(self.latent_heat.is_finite() && self.latent_heat >= 0.0) {
            return Err(FluidError::OutOfRange {
                name: "Melting::latent_heat",
                value: self.latent_heat as f64,
                range: ">= 0 °C",
            });
        }
        crate::heat::check_conductivity("Melting::conductivity", self.conductivity)
    }
}

impl Default for DeformableParams {
    /// Water's density, stiff (α = 1, w = 2), free slip, undamped.
    fn default() -> Self {
        DeformableParams {
            density: 1000.0,
            stiffness: 1.0,
            half_width: 2,
            slip: Slip::FreeSlip,
            damping: 0.0,
            melting: None,
        }
    }
}

impl DeformableParams {
    pub(crate) fn validate(&self) -> Result<()> {
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(FluidError::NonPositive {
                name: "DeformableParams::density",
                value: self.density as f64,
            });
        }
        if !(self.stiffness > 0.0 && self.stiffness <= 1.0) {
            return Err(FluidError::OutOfRange {
                name: "DeformableParams::stiffness",
                value: self.stiffness as f64,
                range: "(0, 1]",
            });
        }
        if !(self.damping >= 0.0 && self.damping < 1.0) {
            return Err(FluidError::OutOfRange {
                name: "DeformableParams::damping",
                value: self.damping as f64,
                range: "[0, 1)",
            });
        }
        if !(1..=MAX_HALF_WIDTH).contains(&self.half_width) {
            return Err(FluidError::OutOfRange {
                name: "DeformableParams::half_width",
                value: self.half_width as f64,
                range: "1 ..= 4",
            });
        }
        self.melting.as_ref().map_or(Ok(()), Melting::validate)
    }
}

/// A lattice shape matching body: its IBPs (structure of arrays) and how its SBPs, the solid
/// carriers of [`Deformable::solids`], hang on them.
#[derive(Clone, Serialize, Deserialize)]
pub struct Deformable {
    /// Name used in errors and reports.
    pub name: String,
    /// The solids holding its SBPs, one per chunk of the lattice ([`chunks`]), their carriers
    /// contiguous and in this order.
    pub(crate) solids: Vec<u32>,
    /// Each IBP's chunk: an index into `solids`, or `u32::MAX` for a chunk with no SBP.
    pub(crate) chunk: Vec<u32>,
    /// The IBPs of each chunk in `solids`.
    pub(crate) members: Rows<u32>,
    pub(crate) params: DeformableParams,
    /// Each IBP's mass, kg (the body's mass, density × the shape's volume, shared equally).
    pub(crate) mass: f32,
    /// IBP rest positions (the shape's frame).
    pub(crate) rest: Vec<Vector>,
    pub(crate) x: Vec<Vector>,
    pub(crate) v: Vec<Vector>,
    pub(crate) pinned: Vec<bool>,
    /// Each IBP's mean rotation (of the regions it belongs to).
    pub(crate) rotation: Vec<Rotation>,
    /// Each region's rotation (the warm start of the next fit).
    pub(crate) region_rotation: Vec<Rotation>,
    pub(crate) regions: Rows<u32>,
    /// Per SBP: its IBPs and weights (Eqs. 19 and 10).
    pub(crate) carriers: Rows<(u32, f32)>,
    /// Per SBP: its rest position and outward normal (the shape's frame).
    pub(crate) sbp_rest: Vec<(Vector, Vector)>,
    /// The SBPs' impulses so far this step when the current substep began.
    #[serde(skip)]
    pub(crate) seen: Vec<Vector>,
    /// Each SBP's mean rotation this substep (the penetration correction maps the rest shape
    /// with it).
    #[serde(skip)]
    pub(crate) sbp_rotation: Vec<Rotation>,
    /// The groups of IBPs that entered the current substep as rigid proxies.
    #[serde(skip)]
    pub(crate) groups: Vec<Group>,
    /// Each IBP's lattice coordinates (its one-ring: the 26 around it).
    #[serde(default)]
    pub(crate) cells: Vec<[i32; 3]>,
    /// Each IBP's one-ring neighbours present in the body, Shao §3.4.2
    /// ([`Self::update_rings`]).
    #[serde(skip)]
    pub(crate) rings: Vec<Vec<u32>>,
    /// Shape matching's elastic energy at the last substep, `Σ ½ k |g − x*|²` with the
    /// substep's stiffness `k = α m / Δt²`, J (for the energy guard).
    #[serde(skip)]
    pub(crate) elastic_energy: f64,
    /// Each IBP's temperature, °C (melting bodies only).
    #[serde(default)]
    pub(crate) temperature: Vec<f32>,
    /// Heat each IBP has taken at its melting point toward its latent heat, °C.
    #[serde(default)]
    pub(crate) absorbed: Vec<f32>,
    /// Melted mass not yet a fluid carrier ([`super::melt`]).
    #[serde(default)]
    pub(crate) pool: Pool,
    /// A cloth's reference substep `Δt₁`, s: its stiffness is `α m / Δt₁²` (the first step
    /// split by the shared body-force limit; 0 until set).
    #[serde(default, alias = "first_substep")]
    pub(crate) reference_substep: f32,
    /// A cloth ([`crate::FluidWorld::add_cloth`]): one layer of points, each its own SBP.
    #[serde(default)]
    pub(crate) cloth: bool,
}

/// Melted mass and momentum not yet a fluid carrier ([`super::melt`]).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub(crate) struct Pool {
    /// kg.
    pub mass: f64,
    /// kg·m/s.
    pub momentum: [f64; 3],
}

/// Points of a deformable body's rest shape that follow it (Eq. 19): a render mesh's
/// vertices, probes. Made by [`Deformable::bind`].
#[derive(Debug, Clone)]
pub struct PointBinding {
    rest: Vec<Vector>,
    weights: Rows<(u32, f32)>,
}

impl PointBinding {
    /// The points' current positions: each the weighted mean of where its IBPs carry it,
    /// `Σ_d w_d (R_d (x⁰ − x⁰_d) + x_d)` (Shao Eq. 19, with the IBPs' positions for their
    /// goals, so that the points are where the mass is).
    pub fn positions(&self, body: &Deformable) -> Vec<Vector> {
        (0..self.rest.len())
            .map(|k| body.carry(self.rest[k], self.weights.row(k)))
            .collect()
    }
}

impl Deformable {
    /// Brings [`Self::rings`] up to date, computing the one-rings once per lattice: a body
    /// only loses points (melting), so a changed count is a changed lattice.
    pub(crate) fn update_rings(&mut self) {
        if self.rings.len() != self.cells.len() {
            self.rings = lattice::one_rings(&self.cells);
        }
    }

    /// The IBPs' positions, m.
    pub fn positions(&self) -> &[Vector] {
        &self.x
    }

    /// The IBPs' velocities, m/s.
    pub fn velocities(&self) -> &[Vector] {
        &self.v
    }

    /// Each IBP's rotation (the mean of its regions' fits).
    pub fn rotations(&self) -> &[Rotation] {
        &self.rotation
    }

    /// The IBPs' rest positions in the shape's frame, m.
    pub fn rest_positions(&self) -> &[Vector] {
        &self.rest
    }

    /// Whether each IBP is pinned ([`crate::FluidWorld::pin_deformable`]).
    pub fn pinned(&self) -> &[bool] {
        &self.pinned
    }

    /// Whether it is a cloth.
    pub fn is_cloth(&self) -> bool {
        self.cloth
    }

    /// The body's material.
    pub fn params(&self) -> &DeformableParams {
        &self.params
    }

    /// The IBPs' temperatures, °C (empty unless the body melts).
    pub fn temperatures(&self) -> &[f32] {
        &self.temperature
    }

    /// Heat each IBP has taken at its melting point toward [`Melting::latent_heat`], °C.
    pub fn absorbed_heat(&self) -> &[f32] {
        &self.absorbed
    }

    /// Mass that has melted off the body but is not yet a fluid carrier, kg (a carrier is made
    /// once a fluid carrier's mass has melted).
    pub fn melt_pending(&self) -> f64 {
        self.pool.mass
    }

    /// Momentum of [`Self::melt_pending`], kg·m/s.
    pub fn melt_pending_momentum(&self) -> Vector {
        Vector::from_array(self.pool.momentum.map(|p| p as f32))
    }

    /// The body's mass, kg.
    pub fn mass(&self) -> f64 {
        self.mass as f64 * self.x.len() as f64
    }

    /// The centre of mass, m (the origin once nothing is left of a melted body).
    pub fn center_of_mass(&self) -> Vector {
        if self.x.is_empty() {
            return Vector::ZERO;
        }
        let mut c = [0.0f64; 3];
        for p in &self.x {
            for k in 0..3 {
                c[k] += p[k] as f64;
            }
        }
        Vector::from_array(c.map(|v| (v / self.x.len() as f64) as f32))
    }

    /// Linear momentum Σ m v, kg·m/s (summed in f64).
    pub fn linear_momentum(&self) -> Vector {
        let mut p = [0.0f64; 3];
        for v in &self.v {
            for k in 0..3 {
                p[k] += v[k] as f64;
            }
        }
        Vector::from_array(p.map(|s| (s * self.mass as f64) as f32))
    }

    /// Ties points of the rest shape (the shape's frame) to the IBPs around them (within one
    /// support radius `h`; the nearest IBP where none is). A melting body renumbers its IBPs
    /// as they melt: bind again after a step that melted ([`crate::StepReport::melted`]).
    pub fn bind(&self, points: &[Vector], h: f32) -> PointBinding {
        PointBinding {
            rest: points.to_vec(),
            weights: lattice::bind(points, &self.rest, &crate::kernel::CubicSpline::new(h)),
        }
    }

    /// How many of `points` lie in the body as it is now, and the first of them: inside its
    /// rest `shape` mapped by the nearest lattice point (`x = x_d + R_d (X − X_d)`), or, for a
    /// melting body or a cloth (`shape` `None`: what is left of its lattice), in that point's
    /// cell (a cube of side `dx` turned with it).
    pub(crate) fn covered(
        &self,
        points: &[Vector],
        dx: f32,
        shape: Option<&dyn rapier3d::parry::shape::Shape>,
    ) -> (usize, Option<Vector>) {
        let key = |p: Vector| (p / dx).floor().as_ivec3().to_array();
        let mut cells: std::collections::HashMap<[i32; 3], Vec<u32>> = Default::default();
        for (i, x) in self.x.iter().enumerate() {
            cells.entry(key(*x)).or_default().push(i as u32);
        }
        let inside = |p: Vector| {
            let c = key(p);
            let nearest = lattice::cube_offsets()
                .filter_map(|o| cells.get(&lattice::shifted(c, o)))
                .flatten()
                .map(|&i| i as usize)
                .min_by(|&a, &b| {
                    (self.x[a] - p)
                        .length_squared()
                        .total_cmp(&(self.x[b] - p).length_squared())
                });
            nearest.is_some_and(|d| {
                let local = self.rotation[d].inverse() * (p - self.x[d]);
                match shape {
                    Some(s) => s.contains_local_point(local + self.rest[d]),
                    None => local.abs().max_element() < 0.5 * dx,
                }
            })
        };
        let mut hits = points.iter().filter(|p| inside(**p));
        let first = hits.next().copied();
        (first.map_or(0, |_| 1 + hits.count()), first)
    }

    /// Whether the body is its lattice's cells (a melting body, a cloth) rather than its rest
    /// shape.
    pub(crate) fn is_cells(&self) -> bool {
        self.cloth || self.params.melting.is_some()
    }

    /// Where the IBPs `weights` carry the rest point `p` (Eq. 19).
    pub(crate) fn carry(&self, p: Vector, weights: &[(u32, f32)]) -> Vector {
        // (a melting body's bindings name points that may have melted since: they are skipped)
        weights
            .iter()
            .filter(|e| (e.0 as usize) < self.x.len())
            .fold(Vector::ZERO, |acc, &(d, w)| {
                let d = d as usize;
                acc + w * (self.rotation[d] * (p - self.rest[d]) + self.x[d])
            })
    }
}

/// IBPs of a deformable body seen as one rigid body for a substep.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RigidState {
    /// Each IBP's mass.
    pub(crate) mass: f32,
    pub(crate) com: Vector,
    pub(crate) linvel: Vector,
    pub(crate) angvel: Vector,
    pub(crate) inertia: Matrix,
    pub(crate) inv_inertia: Matrix,
    /// The proxy's index in [`FluidWorld::rigids`].
    pub(crate) proxy: usize,
}

impl RigidState {
    /// The rigid part `(ΔU, Δω)` of velocity changes `dv` of the IBPs `ids` at `x` (the
    /// momentum and angular momentum about the centre they carry, over mass and inertia).
    pub(crate) fn rigid_part(&self, ids: &[u32], x: &[Vector], dv: &[Vector]) -> (Vector, Vector) {
        let (mut p, mut l) = (Vector::ZERO, Vector::ZERO);
        for &i in ids {
            let i = i as usize;
            p += dv[i];
            l += (x[i] - self.com).cross(dv[i]);
        }
        (p / ids.len() as f32, self.inv_inertia * (l * self.mass))
    }
}

/// IBPs that enter a substep as one rigid proxy.
#[derive(Debug, Clone)]
pub(crate) struct Group {
    pub(crate) ids: Vec<u32>,
    pub(crate) st: RigidState,
}
