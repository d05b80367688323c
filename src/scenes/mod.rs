//! Scenes: a whole run as data (RON, or JSON), parsed with serde and turned into a ready
//! [`Scene`] by [`SceneFile::build`]; the built-in scenes; running them.
//!
//! A scene file names the fluid parameters, open tanks and static boxes (fluid-only walls),
//! rapier bodies with their colliders (shape, pose, velocity, density or mass, friction, and
//! whether and with which slip each couples to the fluid), fluid blocks, emitters and sinks,
//! what to measure, how long to run and which frames to write. Every built-in scene is such a
//! description ([`spec_by_name`]) and ships as a file in `assets/scenes/`.
//!
//! Errors name the file, the line and the field ([`crate::FluidError::Scene`]): syntax and type
//! errors through the parser's position and the field path, inconsistent values (a negative
//! radius, a block inside a wall, a hull of coplanar points) through the path of the value
//! that caused them, located in the text.
//!
//! ```
//! use staggered_fluid::scenes::SceneFile;
//! let text = r#"(
//!     name: "tiny_tank",
//!     dt: 0.004,
//!     seconds: 0.02,
//!     params: (spacing: 0.05),
//!     tanks: [(min: (0, 0, 0), max: (0.5, 0.5, 0.5), slip: FreeSlip)],
//!     fluid: [(min: (0, 0, 0), max: (0.5, 0.25, 0.5))],
//! )"#;
//! let spec = SceneFile::parse(text, "tiny_tank.ron").unwrap();
//! let mut scene = spec.build().unwrap();
//! let report = scene.run(0.02, |_, _| {}).unwrap();
//! assert_eq!(report.n_fluid, 10 * 5 * 10);
//!
//! let bad = text.replace("spacing: 0.05", "spacing: -0.05");
//! let err = SceneFile::parse(&bad, "tiny_tank.ron").unwrap_err().to_string();
//! assert!(err.starts_with("tiny_tank.ron:5:"), "{err}");
//! assert!(err.contains("params.spacing"), "{err}");
//! ```

mod build;
mod builtin;
mod locate;
mod parts;
mod probe;
mod run;
mod spec;
mod validate;
mod wedge;

pub use builtin::*;
pub use probe::{
    carriers_inside_solids, channel_profile, martin_moyce_front, surge_front, wetting, Comparison,
    Draft, Probe, Sample,
};
pub use run::{BodySample, BodyTrack, RunReport, StepLog};
pub use spec::*;
pub use validate::FieldError;
pub use wedge::*;

use crate::emitter::{Emitter, Sink};
use crate::math::Vector;
use crate::world::FluidWorld;
use rapier3d::dynamics::RigidBodyHandle;
use rapier3d::pipeline::PhysicsWorld;

/// Standard gravity (y up), m/s².
pub const G: f32 = 9.81;

/// A ready-to-run scene.
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// The world.
    pub world: FluidWorld,
    /// Gravity.
    pub gravity: Vector,
    /// Step length, s.
    pub dt: f32,
    /// Default duration, s.
    pub seconds: f32,
    /// What to measure.
    pub probe: Probe,
    /// The rapier world of a coupled scene (stepped with the fluid).
    pub physics: Option<PhysicsWorld>,
    /// Named rapier bodies whose pose and fluid force go into the report.
    pub tracked: Vec<(String, RigidBodyHandle)>,
    /// Inflow emitters, run before each step.
    pub emitters: Vec<Emitter>,
    /// Outflow sinks, drained after each step.
    pub sinks: Vec<Sink>,
    /// The description it was built from.
    pub spec: SceneFile,
    /// What settling the water did, once the scene has settled (its `settle` field).
    pub settled: Option<crate::world::SettleReport>,
}
