//! [`FluidWorld`]: the fluid, its solids and rapier bodies, and what carries between steps.
//!
//! Split by concern: this module holds the state and its accessors; `fill` the fluid (blocks,
//! particles, removal); `solids`, `tank` and `volumes` the sampled solids; `domain` the grid
//! and which moving solids take part; `compact` the removal of single carriers; `bodies` the motion of coupled rapier bodies inside the
//! fluid substeps. Stepping is in `step` (ARCHITECTURE.md), the rapier calls in [`crate::coupling`].

mod bodies;
mod compact;
mod contacts;
mod domain;
mod fill;
mod lumps;
mod seams;
mod settle;
mod solids;
mod tank;
pub(crate) mod volumes;

pub(crate) use compact::retain_where;
pub use settle::SettleReport;
#[cfg(feature = "scenes")]
pub(crate) use settle::{settle_steps, MAX_SETTLE_STEPS};
pub(crate) use solids::named;
pub use solids::{Solid, SolidHandle, SolidKind};

use crate::error::Result;
use crate::kernel::CubicSpline;
use crate::math::Vector;
use crate::metrics::StepReport;
use crate::neighbors::{Grid, NeighborLists};
use crate::params::FluidParams;
use crate::particles::{FluidCarriers, SolidCarriers};
use crate::rigid::Rigid;
use crate::solver::pcg::PoissonSystem;
use crate::solver::staggered::Share;
use rapier3d::geometry::ColliderHandle;
use serde::{Deserialize, Serialize};

#[derive(Default)]
pub(crate) struct Scratch {
    pub(crate) v_old: Vec<Vector>,
    pub(crate) accel: Vec<Vector>,
    pub(crate) rho: Vec<f32>,
    pub(crate) count: Vec<u32>,
    /// Eq. 25's asymmetry per carrier (from the density evaluation it shares a loop with).
    pub(crate) asym: Vec<f32>,
    pub(crate) shares: Vec<Share>,
    pub(crate) surface: Vec<bool>,
    pub(crate) p: Vec<f64>,
    pub(crate) cells: Vec<u32>,
    /// Fluid velocities at the start of the substep (for [`FluidCarriers::accel`]).
    pub(crate) v_start: Vec<Vector>,
    /// Fluid positions and each cloth's points at the start of the substep's stages
    /// ([`crate::deform`]'s crossing check; empty without a cloth).
    pub(crate) x_start: Vec<Vector>,
    pub(crate) cloth_start: Vec<Vec<Vector>>,
    /// Each solid carrier's wetness under the hydrostatic walls (`solver::density::wetness`;
    /// empty without them), from the density loop's start to the staggered creation.
    pub(crate) wet: Vec<f32>,
}

/// Everything of a [`FluidWorld`] that carries from one step to the next (what a snapshot
/// holds). Neighbour lists, the Poisson system and scratch buffers are rebuilt every step, and
/// the kernel constants follow from the parameters.
#[derive(Clone, Serialize, Deserialize)]
pub struct WorldState {
    params: FluidParams,
    fluid: FluidCarriers,
    solid: SolidCarriers,
    solids: Vec<Solid>,
    rigids: Vec<Rigid>,
    next_id: u32,
    time: f64,
    steps: u64,
    removed_total: u64,
    grid: Option<Grid>,
    domain_hint: Option<(Vector, Vector)>,
    report: StepReport,
    #[serde(default)]
    recent_step: f32,
    #[serde(default)]
    placed: bool,
    #[serde(default)]
    placement: Option<(f32, f32)>,
    #[serde(default = "one")]
    density_substeps: f32,
    #[serde(default)]
    last_substep: f32,
    #[serde(default)]
    tank_colliders: Vec<ColliderHandle>,
    #[serde(default)]
    tank_walls: Vec<SolidHandle>,
    #[serde(default)]
    rest_pending: Vec<(u32, u32)>,
    #[serde(default)]
    density_substeps_failed: f32,
    #[serde(default)]
    density_raised_before: bool,
    #[serde(default)]
    deformables: Vec<crate::deform::body::Deformable>,
    #[serde(default)]
    heat: Option<crate::heat::FluidHeat>,
}

fn one() -> f32 {
    1.0
}

/// A body of incompressible fluid and the solids it touches.
///
/// ```
/// use staggered_fluid::prelude::*;
/// let mut world = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
/// world.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip).unwrap();
/// world.add_block(Vector::ZERO, Vector::new(0.5, 0.25, 0.5), Vector::ZERO).unwrap();
/// let report = world.step(Vector::new(0.0, -9.81, 0.0), 0.005).unwrap();
/// assert_eq!(report.n_fluid, 10 * 5 * 10);
/// ```
pub struct FluidWorld {
    pub(crate) params: FluidParams,
    pub(crate) kernel: CubicSpline,
    pub(crate) mass: f32,
    pub(crate) kernel_norm: f32,
    pub(crate) grad_sq: f32,
    pub(crate) rest_neighbors: u32,
    /// Lattice normalisation of the consistent divergence ([`crate::solver::velocity`]).
    pub(crate) div_norm: f32,
    pub(crate) fluid: FluidCarriers,
    pub(crate) solid: SolidCarriers,
    pub(crate) solids: Vec<Solid>,
    pub(crate) rigids: Vec<Rigid>,
    /// Fluid impulse `[J; L]` on each solid over the current step.
    pub(crate) impulses: Vec<[f64; 6]>,
    /// The fluid beside each moving dynamic body this substep (explicit stages share a body's
    /// impulse with it: [`lumps`]).
    pub(crate) lumps: Vec<lumps::Lump>,
    pub(crate) next_id: u32,
    pub(crate) time: f64,
    pub(crate) steps: u64,
    pub(crate) removed_total: u64,
    pub(crate) grid: Option<Grid>,
    /// A box fluid will reach later (emitters), for the automatic domain.
    pub(crate) domain_hint: Option<(Vector, Vector)>,
    pub(crate) solids_dirty: bool,
    /// The box of the grid the neighbour search runs on: the fluid's bounding box with a
    /// margin, so cell ranges are kept for the cells around the fluid, not the whole domain.
    pub(crate) search: Option<Grid>,
    pub(crate) solid_ids: Vec<u32>,
    pub(crate) solid_start: Vec<u32>,
    pub(crate) fluid_start: Vec<u32>,
    pub(crate) lists: NeighborLists,
    pub(crate) system: PoissonSystem,
    pub(crate) scratch: Scratch,
    pub(crate) report: StepReport,
    /// τ, the recent substeps' length, shrinking with the simulated time since (`τ ← max(Δt,
    /// τ − Δt)` every substep): the density constraint's stiffness is that of a step of
    /// `max(Δt, τ)`, so a short step after long ones does not turn the compression they left
    /// into a fast velocity.
    pub(crate) recent_step: f32,
    /// Water was placed at rest since the last substep ([`Self::add_particles`] and the calls
    /// built on it): the next substep first relieves the compression the placement left by
    /// moving positions only (`step/he2012.rs`), which no stiffness can turn into a jet.
    pub(crate) placed: bool,
    /// The window over which what is left of a placement's compression is relieved, `(left,
    /// span)` in seconds: the body-force limit's substep from the placement, the kept share
    /// falling linearly over it ([`FluidCarriers::placed_rho`]). A placement has no history
    /// for τ ([`Self::recent_step`]) to stand for: in a fresh world a first step of 1 µs had
    /// the stiffness of 1 µs and turned what the placement left into 3 m/s.
    pub(crate) placement: Option<(f32, f32)>,
    /// The factor (≥ 1) by which the density constraint asks for more substeps than the CFL
    /// and body-force limits: raised when a step ends beyond the density tolerances, relaxed
    /// back when it ends well within them.
    pub(crate) density_substeps: f32,
    /// The density factor the latest burst of raises started from: the substep length last
    /// known to fail, which the factor relaxes back toward only slowly (0: none yet).
    pub(crate) density_substeps_failed: f32,
    /// Whether the last step raised the density factor (a raise now continues its burst).
    pub(crate) density_raised_before: bool,
    /// Whether this step raised it.
    pub(crate) density_raised_now: bool,
    /// The length of the last substep (the velocity constraint's warm start is dropped when
    /// the substep length jumps by more than 4×: its p^v is mostly the divergence that step
    /// removed, which scales as 1/Δt).
    pub(crate) last_substep: f32,
    /// Rapier colliders of tanks made by [`FluidWorld::add_rapier_tank`]: the fluid has walls
    /// of its own there, so [`FluidWorld::couple_all`] leaves them alone.
    pub(crate) tank_colliders: Vec<ColliderHandle>,
    /// The fluid's walls of those tanks, one per collider (the same faces towards the water).
    pub(crate) tank_walls: Vec<SolidHandle>,
    /// Id ranges `[first, end)` of carriers added at rest whose pressure memory the next
    /// substep may set to their hydrostatic pressure (`step/rest_pressure.rs`).
    pub(crate) rest_pending: Vec<(u32, u32)>,
    /// Deformable bodies ([`crate::deform`]), each owning one solid's carriers.
    pub(crate) deformables: Vec<crate::deform::body::Deformable>,
    /// The fluid's heat, once heat is modelled ([`FluidWorld::set_fluid_heat`], a melting
    /// body, a heat source).
    pub(crate) heat: Option<crate::heat::FluidHeat>,
    /// Mechanical energy of the carriers made during the current step (melting), J (step
    /// guards).
    pub(crate) added_energy: f64,
    /// Whether the last substep's density iterations diverged (the density constraint's
    /// substep controller reads it within a step).
    pub(crate) substep_diverged: bool,
    /// The mean compression the last substep ended with (likewise).
    pub(crate) substep_compression: f64,
    /// Mechanical energy of the carriers removed outside the domain during the current step, J
    /// (step guards).
    pub(crate) removed_energy: f64,
    /// Gravity of the current step (for the energy of removed carriers).
    pub(crate) step_gravity: Vector,
    /// The fluid's recent kinetic energy, J: the largest of the steps' starting values, decaying
    /// over [`crate::step`]'s energy memory (what compression may have stored and can give
    /// back).
    pub(crate) recent_kinetic: f64,
    /// The weight-holding forces [`FluidWorld::apply_to_rapier`] added to rapier bodies for
    /// rapier's next step, taken off again after it ([`FluidWorld::correct_after_rapier`]).
    pub(crate) rapier_forces: Vec<(rapier3d::prelude::RigidBodyHandle, Vector, Vector)>,
    /// The moving bodies [`FluidWorld::apply_to_rapier`] handed to rapier with the velocity
    /// that reaches the fluid's pose: the fluid's end velocity `(v, ω)` and the pose velocity
    /// set `(v̄, ω̄)`, so that after rapier's step the body ends with `v + (v_rapier − v̄)`.
    pub(crate) rapier_handoff: Vec<(rapier3d::prelude::RigidBodyHandle, [Vector; 4])>,
}

impl FluidWorld {
    /// An empty world; fails on invalid parameters.
    pub fn new(params: FluidParams) -> Result<Self> {
        params.validate()?;
        let kernel = CubicSpline::new(params.support_radius());
        let (grad_sq, rest_neighbors) = kernel.lattice_grad_sq_and_count(params.spacing);
        Ok(Self {
            kernel,
            mass: params.particle_mass(),
            kernel_norm: kernel.lattice_sum(params.spacing),
            grad_sq,
            rest_neighbors,
            div_norm: {
                let n = rest_neighbors.max(1) as f32;
                let vol = params.spacing.powi(3);
                3.0 * n * n / (2.0 * vol * kernel.lattice_half_grad_moment(params.spacing))
            },
            params,
            fluid: FluidCarriers::default(),
            solid: SolidCarriers::default(),
            solids: Vec::new(),
            rigids: Vec::new(),
            impulses: Vec::new(),
            lumps: Vec::new(),
            next_id: 0,
            time: 0.0,
            steps: 0,
            removed_total: 0,
            grid: None,
            domain_hint: None,
            solids_dirty: true,
            search: None,
            solid_ids: Vec::new(),
            solid_start: Vec::new(),
            fluid_start: Vec::new(),
            lists: NeighborLists::default(),
            system: PoissonSystem::new(),
            scratch: Scratch::default(),
            report: StepReport::default(),
            recent_step: 0.0,
            placed: false,
            placement: None,
            density_substeps: 1.0,
            density_substeps_failed: 0.0,
            density_raised_before: false,
            density_raised_now: false,
            last_substep: 0.0,
            substep_diverged: false,
            substep_compression: 0.0,
            removed_energy: 0.0,
            step_gravity: Vector::ZERO,
            recent_kinetic: 0.0,
            rapier_forces: Vec::new(),
            rapier_handoff: Vec::new(),
            tank_colliders: Vec::new(),
            tank_walls: Vec::new(),
            rest_pending: Vec::new(),
            deformables: Vec::new(),
            heat: None,
            added_energy: 0.0,
        })
    }

    /// The state that carries between steps ([`WorldState`]), for snapshots.
    pub fn state(&self) -> WorldState {
        WorldState {
            params: self.params.clone(),
            fluid: self.fluid.clone(),
            solid: self.solid.clone(),
            solids: self.solids.clone(),
            rigids: self.rigids.clone(),
            next_id: self.next_id,
            time: self.time,
            steps: self.steps,
            removed_total: self.removed_total,
            grid: self.grid,
            domain_hint: self.domain_hint,
            report: self.report.clone(),
            recent_step: self.recent_step,
            placed: self.placed,
            placement: self.placement,
            density_substeps: self.density_substeps,
            density_substeps_failed: self.density_substeps_failed,
            density_raised_before: self.density_raised_before,
            last_substep: self.last_substep,
            tank_colliders: self.tank_colliders.clone(),
            tank_walls: self.tank_walls.clone(),
            rest_pending: self.rest_pending.clone(),
            deformables: self.deformables.clone(),
            heat: self.heat,
        }
    }

    /// A world continuing from `state` (see [`Self::state`]); the next step gives the same
    /// result, bit for bit, as the world the state was taken from.
    pub fn from_state(state: WorldState) -> Result<Self> {
        let mut w = Self::new(state.params)?;
        w.fluid = state.fluid;
        w.solid = state.solid;
        // a state from before depths were stored: the first layer's depth
        let n = w.solid.len();
        w.solid.depth.resize(n, 0.5 * w.params.spacing);
        w.solids = state.solids;
        w.rigids = state.rigids;
        w.next_id = state.next_id;
        w.time = state.time;
        w.steps = state.steps;
        w.removed_total = state.removed_total;
        w.grid = state.grid;
        w.domain_hint = state.domain_hint;
        w.report = state.report;
        w.recent_step = state.recent_step;
        w.placed = state.placed;
        w.placement = state.placement;
        w.density_substeps = state.density_substeps;
        w.density_substeps_failed = state.density_substeps_failed;
        w.density_raised_before = state.density_raised_before;
        w.last_substep = state.last_substep;
        w.tank_colliders = state.tank_colliders;
        w.tank_walls = state.tank_walls;
        w.rest_pending = state.rest_pending;
        w.deformables = state.deformables;
        w.heat = state.heat;
        w.solids_dirty = true;
        Ok(w)
    }

    /// The parameters.
    pub fn params(&self) -> &FluidParams {
        &self.params
    }

    /// Fluid carriers.
    pub fn fluid(&self) -> &FluidCarriers {
        &self.fluid
    }

    /// Solid carriers.
    pub fn solid_carriers(&self) -> &SolidCarriers {
        &self.solid
    }

    /// Solids, indexed by `SolidHandle.0`.
    pub fn solids(&self) -> &[Solid] {
        &self.solids
    }

    /// One solid.
    pub fn solid(&self, h: SolidHandle) -> Option<&Solid> {
        self.solids.get(h.0 as usize)
    }

    /// Dynamic rapier bodies coupled to the fluid (their state during the last step).
    pub fn rigids(&self) -> &[Rigid] {
        &self.rigids
    }

    pub(crate) fn rigids_mut(&mut self) -> &mut [Rigid] {
        &mut self.rigids
    }

    pub(crate) fn set_rigids(&mut self, r: Vec<Rigid>) {
        self.rigids = r;
    }

    pub(crate) fn solid_mut(&mut self, h: SolidHandle) -> &mut Solid {
        &mut self.solids[h.0 as usize]
    }

    pub(crate) fn report_mut(&mut self) -> &mut StepReport {
        &mut self.report
    }

    /// Simulated time, seconds.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Report of the last step.
    pub fn last_report(&self) -> &StepReport {
        &self.report
    }

    /// Mass of one fluid carrier, kg.
    pub fn particle_mass(&self) -> f32 {
        self.mass
    }

    /// Total fluid mass, kg.
    pub fn fluid_mass(&self) -> f64 {
        self.mass as f64 * self.fluid.len() as f64
    }

    /// Total momentum of the fluid, kg·m/s, summed in f64 in a fixed order (`[x, y, z]`: f64
    /// so that momentum balances over one step can be checked to round-off).
    pub fn fluid_momentum(&self) -> [f64; 3] {
        let m = self.mass as f64;
        let v = &self.fluid.v;
        [0, 1, 2].map(|k| crate::solver::det_sum(v.len(), |i| v[i][k] as f64 * m))
    }

    /// Fluid carriers removed so far because they left the domain.
    pub fn removed_total(&self) -> u64 {
        self.removed_total
    }

    /// The kernel.
    #[doc(hidden)]
    pub fn kernel(&self) -> &CubicSpline {
        &self.kernel
    }

    /// Simulation domain (fixed at the first step).
    pub fn domain(&self) -> Option<(Vector, Vector)> {
        self.grid.map(|g| (g.lo, g.hi()))
    }

    /// Neighbour lists of the last substep (for diagnostics and tests).
    #[doc(hidden)]
    pub fn neighbor_lists(&self) -> &NeighborLists {
        &self.lists
    }

    /// The Poisson system of the last substep (Eq. 13), for diagnostics and tests.
    #[doc(hidden)]
    pub fn poisson_system(&self) -> &PoissonSystem {
        &self.system
    }
}
