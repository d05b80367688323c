//! # staggered-fluid
//!
//! Incompressible liquid for [rapier3d](https://rapier.rs) worlds with two-way coupling, after
//! He et al. 2012, *Staggered Meshless Solid-Fluid Coupling* (ACM TOG 31(6) 149). Fluid and
//! solids are carrier particles; each step creates staggered particles between neighbouring
//! carriers, enforces the density constraint (iterative EOS pressure p^d ≥ 0, held to a
//! tolerance) and then the velocity constraint (a Poisson equation for p^v over the staggered
//! divergence, solved by Jacobi-preconditioned conjugate residuals, with free-surface and
//! free-/no-/partial-slip wall conditions). Rapier keeps the rigid bodies and their contacts;
//! the fluid pushes them and they push back.
//!
//! ## Water in a rapier world
//!
//! ```
//! use rapier3d::pipeline::PhysicsWorld;
//! use rapier3d::prelude::*;
//! use staggered_fluid::prelude::*;
//!
//! // rapier's side: a ground and a box of pine (500 kg/m³), stepped at rapier's 1/60 s
//! let mut physics = PhysicsWorld::new();
//! physics.integration_parameters.dt = 1.0 / 60.0;
//! let ground = ColliderBuilder::cuboid(2.0, 0.1, 2.0).translation(Vector::new(0.0, -0.15, 0.0));
//! physics.colliders.insert(ground);
//! let start = Vector::new(0.0, 0.25, 0.0);
//! let boat = physics.bodies.insert(RigidBodyBuilder::dynamic().translation(start));
//! let hull = physics.colliders.insert_with_parent(
//!     ColliderBuilder::cuboid(0.1, 0.05, 0.1).density(500.0),
//!     boat,
//!     &mut physics.bodies,
//! );
//!
//! // the fluid's side: a tank's walls, the box coupled, 0.2 m of water around it
//! let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
//! let (lo, hi) = (Vector::new(-0.3, 0.0, -0.3), Vector::new(0.3, 0.5, 0.3));
//! fluid.add_open_tank(lo, hi, Slip::FreeSlip)?;
//! fluid.couple_collider(&physics.bodies, &physics.colliders, hull, Slip::FreeSlip)?;
//! fluid.add_block_around(lo, Vector::new(0.3, 0.2, 0.3), Vector::ZERO, &physics.colliders)?;
//!
//! for _ in 0..30 {
//!     // one frame: the fluid step (its own substeps), rapier's step, the hand-back
//!     let report = fluid.step_physics_world(&mut physics)?;
//!     assert!(report.compression_mean <= 0.01 && report.removed_outside == 0);
//! }
//! let y = physics.bodies[boat].translation().y;
//! assert!(y > 0.15 && y < 0.25, "the box floats, its centre at {y} m");
//! # Ok::<(), FluidError>(())
//! ```
//!
//! [`FluidWorld::couple_all`] couples every collider at once (those it cannot sample are
//! listed, not coupled); an engine that steps rapier itself calls
//! [`FluidWorld::step_with_rapier`], its own `PhysicsPipeline::step` and
//! [`FluidWorld::correct_after_rapier`] instead (the same physics, bit for bit). A fluid-only
//! world steps with [`FluidWorld::step`].
//!
//! ## Which parameters matter
//!
//! [`FluidParams`] has many fields; these are the ones to set, the rest are the method's own
//! settings (each documents its unit and the measurement behind its default):
//!
//! - **`spacing`** (m, default 0.02): the carrier spacing Δx, the resolution. Cost grows as
//!   Δx⁻³ carriers times Δx^-½ (at rest) to Δx⁻¹ (in fast flow) more substeps; a body should
//!   be at least 6Δx across to float within about 10 % of its draft (see *Limits*).
//! - **the step length** is yours (rapier's `dt`, or the `dt` of [`FluidWorld::step`]): each
//!   step is split into substeps by the CFL limit (`max_cfl`, 0.4 of Δx per substep), the
//!   body-force limit (`body_force_limit`, Δt ≤ 0.2 √(Δx/g)), the viscosity limit and the
//!   density constraint's own controller (up to 8× more while the compression is above its
//!   tolerance). [`StepReport::substeps`] says how many a step took; substeps are what a
//!   frame costs.
//! - **slip** per solid ([`Slip`]): `FreeSlip` (pressure only, the cheapest), `NoSlip` (the
//!   paper's Eq. 26: the wall's velocity imposed on the first layer), `BoundaryLayer` (a wall
//!   shear from the fluid's viscosity, as thin as water's real boundary layer: slight for
//!   water), `Partial { viscosity }` (a wall friction of your choosing).
//! - **incompressibility**: `density_mean_tolerance` (0.001 = 0.1 % mean compression of the
//!   inner carriers) and `density_max_tolerance` (1 % at any carrier) bound the density;
//!   `relative_residual` (0.1) and `density_error_tolerance` (E, Eq. 29, 1 %) bound the
//!   velocity's divergence. Looser tolerances take fewer iterations and substeps.
//!   [`StepReport`] carries what was reached (`compression_mean`, `compression_max`, `error`).
//! - `viscosity` (m²/s, water's 1e-6) and `xsph` (velocity smoothing, 0.1) shape the flow;
//!   `solver` picks He 2012 (default) or PCISPH (Shao et al. 2014) for comparison.
//!
//! ## Limits
//!
//! What the defaults give, measured at Δx = 2 cm (BENCHMARKS.md, ARCHITECTURE.md "Known
//! problems"):
//!
//! - **Floating bodies sit high**: about 0.3Δx — cubes 8Δx across of 250 / 500 / 750 kg/m³
//!   13 / 6 / 6 % short of Archimedes' draft, the five-ball scene's floating balls (radius 3Δx)
//!   6–9 % short; a body held under water feels 2–16 % more than ρgV (more for round and
//!   small bodies), so a neutrally buoyant body rises.
//! - **Accuracy needs resolution**: the dam-break front is within 8.5 % of Martin & Moyce at
//!   30 carriers across the column; at 20 across smoothing slows it by 12 %.
//! - **Shapes**: closed parry shapes, compounds and oriented closed triangle meshes couple;
//!   half-spaces, height fields, open meshes, polylines and voxels are left to rapier
//!   ([`FluidError::UnsupportedShape`]); a collider thinner than about one spacing can leak
//!   at speed; a very large collider (a 200 m ground) is sampled whole and can exceed
//!   [`params::MAX_PARTICLES`].
//! - **Speed**: about 2.5–3.2 µs per fluid carrier and substep on 2 cores (Table 3 in
//!   BENCHMARKS.md); a 10k-carrier pool at 1/60 s frames runs several times slower than real
//!   time.
//! - **Long steps** are split into substeps rather than refused; at 8× a scene's stable step
//!   water can still be thrown out of the domain, which [`StepReport::removed_outside`]
//!   counts.
//!
//! ## Beyond a world in code
//!
//! Whole runs can also be described as data: [`scenes::SceneFile`] (RON or JSON; every
//! built-in scene ships as one in `assets/scenes/`) builds a [`scenes::Scene`] that steps the
//! fluid and its rapier world together, with [`emitter`]s and sinks; [`frames`] and
//! [`preview`] write what a run looks like, and [`snapshot`] saves and resumes it (features
//! `scenes` and `output`, on by default; `default-features = false` keeps the simulation and
//! the rapier coupling only).
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
            solid_depth: &$w.solid.depth,
            solid_u: &$w.solid.u,
            solid_body: &$w.solid.body,
            bodies: $bodies,
        }
    };
}

mod choices;
pub mod coupling;
pub mod deform;
pub mod emitter;
pub mod error;
#[cfg(feature = "output")]
pub mod frames;
pub mod heat;
mod hull;
mod kernel;
mod limits;
pub mod math;
pub mod metrics;
mod neighbors;
pub mod params;
pub mod particles;
mod presets;
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

pub use coupling::{CoupledColliders, RapierTank};
pub use error::{FluidError, Result};
pub use heat::{FluidHeat, HeatSource};
pub use metrics::{StageTimes, StepReport};
pub use params::{FluidParams, Krylov, OnFailure, Preconditioner, Remap, Solver};
pub use solver::staggered::Slip;
pub use world::{FluidWorld, SettleReport, Solid, SolidHandle, SolidKind};

/// Internals exposed for this crate's own tests and benchmarks (kernel, neighbour search,
/// sampling, the Poisson solve). Not a user's API: no stability promise.
#[doc(hidden)]
pub mod internals {
    pub use crate::kernel::CubicSpline;
    pub use crate::neighbors::{brute_force, build_lists, counting_sort, Grid, NeighborLists};
    pub use crate::sampling::{
        fill_box, sample_shell, sample_shell_in, signed_distance, ShellSample,
    };
    pub use crate::step::{PCISPH_BODY_FORCE_LIMIT, PCISPH_MAX_CFL};
    pub use crate::world::volumes::relative_volumes;
    /// The Krylov solve of the velocity constraint.
    pub mod pcg {
        pub use crate::solver::pcg::{incompressibility_error, solve, PcgSettings, PcgStats};
        pub use crate::solver::system::{PoissonSystem, RigidLink};
    }
}

/// The README's Rust examples, compiled and run as doc-tests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// Everything a typical user needs.
pub mod prelude {
    pub use crate::math::{Pose, Vector};
    pub use crate::{
        FluidError, FluidParams, FluidWorld, Preconditioner, Slip, SolidHandle, Solver, StepReport,
    };
}
