//! # staggered-fluid
//!
//! Incompressible liquid for [rapier3d](https://rapier.rs) worlds, after He et al. 2012,
//! *Staggered Meshless Solid-Fluid Coupling* (ACM TOG 31(6) 149). Fluid and solids are carrier
//! particles; each step creates staggered particles between neighbouring carriers, enforces the
//! density constraint (iterative EOS pressure p^d ≥ 0) and then the velocity constraint (a
//! Poisson equation for p^v over the staggered divergence, solved by Jacobi-preconditioned
//! conjugate residuals, with free-surface and free-/no-/partial-slip wall conditions on
//! staggered particles).
//!
//! ```
//! use staggered_fluid::prelude::*;
//! let mut world = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
//! world.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip)?;
//! world.add_block(Vector::ZERO, Vector::new(0.25, 0.4, 0.5), Vector::ZERO)?;
//! for _ in 0..10 {
//!     let r = world.step(Vector::new(0.0, -9.81, 0.0), 0.005)?;
//!     assert!(r.error <= 0.01);
//! }
//! # Ok::<(), staggered_fluid::FluidError>(())
//! ```
//!
//! Whole runs can also be described as data: [`scenes::SceneFile`] (RON or JSON; every
//! built-in scene ships as one in `assets/scenes/`) builds a [`scenes::Scene`] that steps the
//! fluid and its rapier world together, with [`emitter`]s and sinks; [`frames`] and
//! [`preview`] write what a run looks like, and [`snapshot`] saves and resumes it.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

/// Read-only view of a world's fluid–solid state for the solver stages
/// ([`solver::Ctx`]). A macro rather than a method so that the borrows stay per field: a stage
/// may write the fluid arrays while it reads the solids and the lists through the view.
macro_rules! ctx {
    ($w:ident, $bodies:expr) => {
        $crate::solver::Ctx {
            kernel: $w.kernel,
            mass: $w.mass,
            rest_density: $w.params.rest_density,
            kernel_norm: $w.kernel_norm,
            viscosity: $w.params.viscosity,
            lists: &$w.lists,
            solid_x: &$w.solid.x,
            solid_n: &$w.solid.n,
            solid_volume: &$w.solid.volume,
            solid_u: &$w.solid.u,
            solid_body: &$w.solid.body,
            bodies: $bodies,
        }
    };
}

pub mod coupling;
pub mod emitter;
pub mod error;
#[cfg(feature = "output")]
pub mod frames;
mod kernel;
pub mod math;
pub mod metrics;
mod neighbors;
pub mod params;
pub mod particles;
#[cfg(feature = "output")]
pub mod preview;
pub mod rigid;
mod sampling;
#[cfg(feature = "scenes")]
pub mod scenes;
#[cfg(feature = "scenes")]
pub mod snapshot;
mod solver;
mod step;
#[cfg(feature = "surface")]
pub mod surface;
pub mod world;

pub use coupling::CoupledColliders;
pub use error::{FluidError, Result};
pub use metrics::{StageTimes, StepReport};
pub use params::{FluidParams, Krylov, Preconditioner, Remap, Solver};
pub use solver::staggered::Slip;
pub use world::{FluidWorld, Solid, SolidHandle, SolidKind};

/// Internals exposed for this crate's own tests and benchmarks (kernel, neighbour search,
/// sampling, the Poisson solve). Not a user's API: no stability promise.
#[doc(hidden)]
pub mod internals {
    pub use crate::kernel::CubicSpline;
    pub use crate::neighbors::{brute_force, build_lists, counting_sort, Grid, NeighborLists};
    pub use crate::sampling::{fill_box, sample_shell, signed_distance, ShellSample};
    pub use crate::step::PCISPH_MAX_CFL;
    /// The Krylov solve of the velocity constraint.
    pub mod pcg {
        pub use crate::solver::pcg::{incompressibility_error, solve, PcgSettings, PcgStats};
        pub use crate::solver::system::{PoissonSystem, RigidLink};
    }
}

/// Everything a typical user needs.
pub mod prelude {
    pub use crate::math::{Pose, Vector};
    pub use crate::{
        FluidError, FluidParams, FluidWorld, Preconditioner, Slip, SolidHandle, Solver, StepReport,
    };
}
