//! Staggered particles (He 2012 §4.1, Eqs. 7–9) and the solid-wall conditions imposed on them
//! (§5.2, Eqs. 26–27 and the no-stick inequality).
//!
//! Staggered particles are formed on the fly from per-carrier shares (`m_i/N_i`, `m_i/(N_i ρ_i)`)
//! rather than stored: both the assembly and the remap call [`pair`], so they always agree.

use crate::math::Vector;
use serde::{Deserialize, Serialize};

/// Slip condition of a solid (He 2012 §5.2 and §6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub enum Slip {
    /// Only the normal relative velocity is constrained (Eq. 27), no wall viscosity (μ^s = 0).
    #[default]
    FreeSlip,
    /// He 2012 Eq. 26: the whole relative velocity of every fluid–solid staggered particle is
    /// constrained, so the first layer of fluid moves with the wall at any viscosity (plus the
    /// wall viscosity μ^s = μ^f). Much stronger than water's real boundary layer at these
    /// spacings (a surge two or three spacings deep runs late; see [`Slip::BoundaryLayer`]).
    NoSlip,
    /// No slip as a boundary layer: the wall's friction is a shear stress on the fluid beside
    /// it, the generalized viscous force (Eq. 24) with μ^s = μ^f and the wall velocity taken
    /// on the wall's surface (the solid carriers' velocities mirrored, Morris et al. 1997),
    /// the normal part as free slip (Eq. 27). The fluid beside the wall slows by what its
    /// viscosity implies: water (10⁻⁶ m²/s) barely, a syrup a lot (a channel's start-up flow
    /// follows Navier–Stokes within 5 % of its centre speed). Not the default for tanks yet:
    /// over it, as over free-slip walls, a still tank keeps a slow circulation down its
    /// vertical edges (0.14 m/s after 2 s) that pinned walls hold back.
    BoundaryLayer,
    /// Normal part as free slip (Eq. 27) plus the generalized viscous force (Eq. 24) with the
    /// given wall kinematic viscosity in m²/s.
    Partial {
        /// Wall viscosity μ^s (kinematic, m²/s).
        viscosity: f32,
    },
}

impl Slip {
    /// Wall viscosity μ^s for a fluid of viscosity `fluid_viscosity`.
    pub fn wall_viscosity(&self, fluid_viscosity: f32) -> f32 {
        match *self {
            Slip::FreeSlip => 0.0,
            Slip::NoSlip | Slip::BoundaryLayer => fluid_viscosity,
            Slip::Partial { viscosity } => viscosity,
        }
    }
}

/// One carrier's contribution to its staggered particles: `m_i− = m_i/N_i`, `V_i− = m_i−/ρ_i`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Share {
    /// Mass share `m_i/N_i` (Eq. 7).
    pub mass: f32,
    /// Volume share `m_i/(N_i ρ_i)` (Eq. 9).
    pub volume: f32,
}

impl Share {
    /// Share of a carrier of mass `m`, density `rho` and `n` neighbours (n ≥ 1).
    #[inline]
    pub fn new(m: f32, rho: f32, n: u32) -> Self {
        let mass = m / n.max(1) as f32;
        Self {
            mass,
            volume: mass / rho,
        }
    }
}

/// A staggered particle `P_{i−j}` (Eqs. 7–9).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Staggered {
    /// Mass `m_{i−j} = m_i− + m_j−` (Eq. 7).
    pub mass: f32,
    /// Mixed volume `V_{i−j} = V_i− + V_j−` (Eq. 9).
    pub volume: f32,
    /// Momentum-weighted velocity ṽ_{i−j} (Eq. 8).
    pub velocity: Vector,
}

impl Staggered {
    /// Mixed density `ρ_{i−j} = m_{i−j}/V_{i−j}` (Eq. 9).
    #[inline]
    pub fn density(&self) -> f32 {
        self.mass / self.volume
    }
}

/// Creates the staggered particle between carriers with shares `a`, `b` and velocities `va`,
/// `vb`. Symmetric in its arguments bit for bit, so the assembled matrix is exactly symmetric.
#[inline]
pub fn pair(a: Share, va: Vector, b: Share, vb: Vector) -> Staggered {
    let mass = a.mass + b.mass;
    let volume = a.volume + b.volume;
    let velocity = (va * a.mass + vb * b.mass) / mass;
    Staggered {
        mass,
        volume,
        velocity,
    }
}

/// Velocity `v^new_{i−j}` a fluid–solid staggered particle must take under the wall condition
/// (Eqs. 26–27), or `None` when no condition applies (no-stick: fluid leaving the wall).
///
/// `v` is ṽ_{i−j}, `u` the solid velocity at the solid carrier, `n` the solid's outward normal.
#[inline]
pub fn wall_velocity(slip: Slip, stick: bool, v: Vector, u: Vector, n: Vector) -> Option<Vector> {
    let rel = v - u;
    let vn = rel.dot(n);
    // §5.2 no-stick inequality (u − v^new)·n ≥ 0: only pairs approaching the wall are constrained.
    if !stick && vn >= 0.0 {
        return match slip {
            // a separating no-slip pair keeps its normal motion but loses tangential slip
            Slip::NoSlip => Some(u + n * vn),
            _ => None,
        };
    }
    match slip {
        Slip::NoSlip => Some(u), // Eq. 26
        _ => Some(v - n * vn),   // Eq. 27
    }
}
