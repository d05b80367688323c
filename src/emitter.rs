//! Inflow emitters (a tap: a disc or rectangle that adds fluid at a velocity) and outflow sinks
//! (a box that removes the fluid entering it). Both count what they add and remove, so a run's
//! fluid mass balances: `initial + emitted − sunk − removed outside the domain`.
//!
//! ```
//! use staggered_fluid::emitter::{Emitter, EmitterSpec, OutletSpec};
//! use staggered_fluid::prelude::*;
//! let mut world = FluidWorld::new(FluidParams { spacing: 0.02, ..Default::default() }).unwrap();
//! world.add_open_tank(Vector::ZERO, Vector::new(0.4, 0.4, 0.4), Slip::FreeSlip).unwrap();
//! let spec = EmitterSpec {
//!     center: [0.2, 0.3, 0.2],
//!     velocity: [0.0, -1.0, 0.0],
//!     outlet: OutletSpec::Disc { radius: 0.05 },
//!     start: 0.0,
//!     stop: None,
//! };
//! let mut tap = Emitter::new(&spec, 0.02).unwrap();
//! assert_eq!(tap.layer.len(), 21); // the lattice points of the disc
//! // one layer at the opening, then one per Δx of travel: 1 m/s × 0.1 s = 5 more
//! for _ in 0..10 {
//!     tap.emit(&mut world, 0.01).unwrap();
//!     world.step(Vector::new(0.0, -9.81, 0.0), 0.01).unwrap();
//! }
//! assert_eq!(tap.emitted, 6 * 21);
//! assert_eq!(world.fluid().len(), 6 * 21);
//! ```

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::world::FluidWorld;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Shape of an emitter's outlet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum OutletSpec {
    /// A disc.
    Disc {
        /// Radius, m.
        radius: f32,
    },
    /// A rectangle.
    Rectangle {
        /// Half sizes along the outlet's two in-plane axes, m.
        half_extents: [f32; 2],
    },
}

/// An inflow emitter: a tap that adds fluid through an outlet at a velocity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterSpec {
    /// Centre of the outlet, m.
    pub center: [f32; 3],
    /// Velocity of the emitted fluid, m/s; the outlet is perpendicular to it.
    pub velocity: [f32; 3],
    /// Outlet shape.
    pub outlet: OutletSpec,
    /// When it opens, s.
    #[serde(default, skip_serializing_if = "is_zero1")]
    pub start: f32,
    /// When it closes, s (`None`: never).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<f32>,
}

fn is_zero1(v: &f32) -> bool {
    *v == 0.0
}

/// An inflow emitter. Each time the fluid it emitted last has travelled one spacing it adds a
/// new layer of carriers on the outlet's lattice, placed where that layer would be by now, so
/// the outflow rate is `speed × outlet area × ρ̄` on average.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Emitter {
    /// Layer of carriers on the outlet (world positions at the outlet).
    pub layer: Vec<Vector>,
    /// Unit outflow direction.
    pub direction: Vector,
    /// Velocity of the emitted fluid, m/s.
    pub velocity: Vector,
    /// Opening time, s.
    pub start: f64,
    /// Closing time, s.
    pub stop: Option<f64>,
    /// Distance the last layer has travelled, m.
    pub travelled: f32,
    /// Spacing Δx.
    pub spacing: f32,
    /// Carriers emitted so far.
    pub emitted: u64,
    /// Layer points skipped so far because fluid still occupied them (a blocked outlet).
    pub blocked: u64,
}

impl Emitter {
    /// An emitter from its scene description at spacing `dx`: an error for a velocity that is
    /// zero, not finite or above [`crate::params::MAX_SPEED`], a centre beyond
    /// [`crate::params::MAX_LENGTH`], or an outlet whose layer would exceed
    /// [`crate::params::MAX_PARTICLES`] carriers (counted before any is placed).
    pub fn new(spec: &EmitterSpec, dx: f32) -> Result<Self> {
        use crate::params::{check_count, MAX_LENGTH, MAX_PARTICLES, MAX_SPEED};
        crate::error::positive("spacing", dx as f64)?;
        let velocity = Vector::from(spec.velocity);
        let centre = Vector::from(spec.center);
        if !crate::math::finite(velocity) || !crate::math::finite(centre) {
            return Err(FluidError::NonFinite {
                what: "emitter centre or velocity".into(),
            });
        }
        let speed = velocity.length();
        if !(speed > 0.0 && speed <= MAX_SPEED) {
            return Err(FluidError::OutOfRange {
                name: "emitter velocity",
                value: speed as f64,
                range: "(0, 1000] m/s (params::MAX_SPEED)",
            });
        }
        if centre.abs().max_element() > MAX_LENGTH {
            return Err(FluidError::OutOfRange {
                name: "emitter centre",
                value: centre.abs().max_element() as f64,
                range: "within ±1e6 m (params::MAX_LENGTH)",
            });
        }
        let (ru, rw) = match spec.outlet {
            OutletSpec::Disc { radius } => (radius, radius),
            OutletSpec::Rectangle { half_extents } => (half_extents[0], half_extents[1]),
        };
        crate::error::positive("emitter outlet size", ru.min(rw) as f64)?;
        let per_axis = |r: f32| 2.0 * (r as f64 / dx as f64).floor() + 1.0;
        check_count(
            "carriers in one emitter layer",
            per_axis(ru) * per_axis(rw),
            MAX_PARTICLES,
        )?;
        let n = velocity.normalize();
        // an in-plane basis
        let a = if n.x.abs() < 0.9 {
            Vector::X
        } else {
            Vector::Y
        };
        let u = n.cross(a).normalize();
        let w = n.cross(u);
        let (ru, rw, disc) = match spec.outlet {
            OutletSpec::Disc { radius } => (radius, radius, true),
            OutletSpec::Rectangle { half_extents } => (half_extents[0], half_extents[1], false),
        };
        let (ku, kw) = ((ru / dx).floor() as i32, (rw / dx).floor() as i32);
        let mut layer = Vec::new();
        for i in -ku..=ku {
            for j in -kw..=kw {
                let (a, b) = (i as f32 * dx, j as f32 * dx);
                if !disc || a * a + b * b <= ru * ru {
                    layer.push(centre + u * a + w * b);
                }
            }
        }
        Ok(Self {
            layer,
            direction: n,
            velocity,
            start: spec.start as f64,
            stop: spec.stop.map(f64::from),
            // the first layer leaves as soon as the emitter opens
            travelled: dx,
            spacing: dx,
            emitted: 0,
            blocked: 0,
        })
    }

    /// Whether the emitter is open at time `t`.
    pub fn open(&self, t: f64) -> bool {
        t >= self.start - 1e-9 && self.stop.is_none_or(|s| t < s)
    }

    /// Advances the emitter over a step of `dt` starting at the world's time: adds the layers
    /// due and returns how many carriers it added.
    pub fn emit(&mut self, world: &mut FluidWorld, dt: f32) -> Result<u64> {
        if !self.open(world.time()) || self.layer.is_empty() {
            return Ok(0);
        }
        let mut added = 0u64;
        self.travelled += self.velocity.length() * dt;
        while self.travelled >= self.spacing {
            self.travelled -= self.spacing;
            // the layer left the outlet `travelled` ago
            let shift = self.direction * self.travelled;
            // where the water in front has not moved on (a submerged or blocked outlet) a new
            // carrier would sit on an old one: those points are skipped and counted
            let r = 0.5 * self.spacing;
            let pts: Vec<Vector> = self.layer.iter().map(|p| *p + shift).collect();
            // one pass over the fluid for the carriers near the outlet, then the points
            let (lo, hi) = crate::math::bounding_box(&pts);
            let (lo, hi) = (lo - Vector::splat(r), hi + Vector::splat(r));
            let near: Vec<Vector> = world
                .fluid()
                .x
                .par_iter()
                .filter(|x| (0..3).all(|k| x[k] >= lo[k] && x[k] <= hi[k]))
                .copied()
                .collect();
            let pts: Vec<Vector> = pts
                .into_iter()
                .filter(|q| !near.iter().any(|x| (*x - *q).length_squared() < r * r))
                .collect();
            self.blocked += (self.layer.len() - pts.len()) as u64;
            if !pts.is_empty() {
                world.add_particles(&pts, self.velocity)?;
            }
            added += pts.len() as u64;
        }
        self.emitted += added;
        Ok(added)
    }
}

/// An outflow sink: the box `[min, max]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Sink {
    /// Lower corner.
    pub min: Vector,
    /// Upper corner.
    pub max: Vector,
}

impl Sink {
    /// Removes the fluid carriers inside the sink; returns how many.
    pub fn drain(&self, world: &mut FluidWorld) -> u64 {
        let (lo, hi) = (self.min, self.max);
        world.remove_fluid_where(|p| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]))
    }
}
