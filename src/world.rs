//! [`FluidWorld`]: the fluid, its solids, and the step of He 2012 Algorithm 1.

use crate::error::{positive, FluidError, Result};
use crate::kernel::CubicSpline;
use crate::math::{arr, bounding_box, finite, Pose, Rotation, Vector};
use crate::metrics::{StageTimes, StepReport};
use crate::neighbors::{build_lists, counting_sort_into, Grid, NeighborLists};
use crate::params::Solver;
use crate::params::{FluidParams, MAX_CELLS, MAX_PARTICLES};
use crate::particles::{FluidCarriers, SolidCarriers};
use crate::rigid::{self, Rigid};
use crate::sampling::{fill_box, sample_shell_on};
use crate::solver::pcg::{self, PcgSettings, PoissonSystem};
use crate::solver::staggered::{Share, Slip};
use crate::solver::{density, forces, projection, surface, velocity, BodyView, Ctx};
use rapier3d::geometry::ColliderHandle;
use rapier3d::math::Matrix;
use rapier3d::parry::shape::SharedShape;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Read-only view of a world's fluid–solid state for the solver stages. A macro rather than a
/// method so that the borrows stay per field: a stage may write the fluid arrays while it reads
/// the solids and the lists through the view.
macro_rules! ctx {
    ($w:ident, $bodies:expr) => {
        Ctx {
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

/// Handle of a solid added to a [`FluidWorld`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct SolidHandle(pub u32);

/// How a solid moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SolidKind {
    /// Never moves (walls, tanks).
    Static,
    /// Scripted (He 2012 §6): moves with the velocity given by
    /// [`FluidWorld::set_kinematic`] (or its rapier body's), pushes the fluid, and reports the
    /// fluid's force and torque, but is not pushed back.
    Kinematic,
    /// A collider of a dynamic rapier body: moved by gravity and the fluid during the fluid
    /// substeps, its fluid impulse handed back to rapier (two-way coupling, Eq. 21).
    Dynamic,
}

/// A solid sampled into solid carriers.
#[derive(Clone, Serialize, Deserialize)]
pub struct Solid {
    /// Name used in errors and reports.
    pub name: String,
    /// How it moves.
    pub kind: SolidKind,
    /// Its shape (local frame).
    pub shape: SharedShape,
    /// World pose.
    pub pose: Pose,
    /// Slip condition of its walls.
    pub slip: Slip,
    /// If true the no-stick inequality of §5.2 is off: fluid may stick to the wall.
    pub stick: bool,
    /// Its carriers in [`FluidWorld::solid_carriers`].
    pub range: std::ops::Range<usize>,
    /// Force of the fluid on the solid over the last step, N (Eq. 21).
    pub force: Vector,
    /// Torque of the fluid on the solid about [`Self::com`] over the last step, N·m (Eq. 21).
    pub torque: Vector,
    /// Velocity of the point [`Self::com`], m/s.
    pub linvel: Vector,
    /// Angular velocity, rad/s.
    pub angvel: Vector,
    /// Centre of rotation and torque reference: the body's centre of mass for rapier bodies,
    /// the pose origin otherwise.
    pub com: Vector,
    /// Index of the dynamic body in [`FluidWorld::rigids`], for [`SolidKind::Dynamic`].
    pub rigid: Option<usize>,
    /// The rapier collider it was sampled from, if any.
    pub collider: Option<ColliderHandle>,
    /// Whether its carriers take part in the current step (some fluid is near, it is not
    /// removed, it lies inside the domain).
    pub active: bool,
    /// Uncoupled or its collider removed: no carriers any more.
    pub removed: bool,
    /// Pose at the start of the current substep.
    pub(crate) pose_start: Pose,
    /// Body-frame position and outward normal of each carrier, for solids that move (empty
    /// for static ones, whose carriers keep world coordinates only).
    #[serde(default)]
    pub(crate) local: Vec<(Vector, Vector)>,
    /// The pose the carriers were last placed at.
    #[serde(default)]
    pub(crate) placed: Pose,
}

#[derive(Default)]
struct Scratch {
    v_old: Vec<Vector>,
    accel: Vec<Vector>,
    rho: Vec<f32>,
    count: Vec<u32>,
    /// Eq. 25's asymmetry per carrier (from the density evaluation it shares a loop with).
    asym: Vec<f32>,
    shares: Vec<Share>,
    surface: Vec<bool>,
    p: Vec<f64>,
    cells: Vec<u32>,
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
    params: FluidParams,
    kernel: CubicSpline,
    mass: f32,
    kernel_norm: f32,
    grad_sq: f32,
    rest_neighbors: u32,
    /// Lattice normalisation of the consistent divergence ([`crate::solver::velocity`]).
    div_norm: f32,
    fluid: FluidCarriers,
    solid: SolidCarriers,
    solids: Vec<Solid>,
    rigids: Vec<Rigid>,
    /// Fluid impulse `[J; L]` on each solid over the current step.
    impulses: Vec<[f64; 6]>,
    next_id: u32,
    time: f64,
    steps: u64,
    removed_total: u64,
    grid: Option<Grid>,
    /// A box fluid will reach later (emitters), for the automatic domain.
    domain_hint: Option<(Vector, Vector)>,
    solids_dirty: bool,
    /// The box of the grid the neighbour search runs on: the fluid's bounding box with a
    /// margin, so cell ranges are kept for the cells around the fluid, not the whole domain.
    search: Option<Grid>,
    solid_ids: Vec<u32>,
    solid_start: Vec<u32>,
    fluid_start: Vec<u32>,
    lists: NeighborLists,
    system: PoissonSystem,
    scratch: Scratch,
    report: StepReport,
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
        }
    }

    /// A world continuing from `state` (see [`Self::state`]); the next step gives the same
    /// result, bit for bit, as the world the state was taken from.
    pub fn from_state(state: WorldState) -> Result<Self> {
        let mut w = Self::new(state.params)?;
        w.fluid = state.fluid;
        w.solid = state.solid;
        w.solids = state.solids;
        w.rigids = state.rigids;
        w.next_id = state.next_id;
        w.time = state.time;
        w.steps = state.steps;
        w.removed_total = state.removed_total;
        w.grid = state.grid;
        w.domain_hint = state.domain_hint;
        w.report = state.report;
        w.solids_dirty = true;
        Ok(w)
    }

    /// Checks that fluid placed at `positions` would lie inside no solid (what
    /// [`Self::add_particles`] checks before adding), without adding it.
    pub fn check_free(&self, positions: &[Vector]) -> Result<()> {
        for s in self.solids.iter().filter(|s| !s.removed) {
            check_overlap(s, positions)?;
        }
        Ok(())
    }

    /// Makes the automatic domain (fixed at the first step, see [`FluidParams::domain`])
    /// include the box `[lo, hi]`, where fluid will appear later (an emitter's outlet).
    /// No effect once the world has stepped or with an explicit domain.
    pub fn include_in_domain(&mut self, lo: Vector, hi: Vector) {
        self.domain_hint = Some(match self.domain_hint {
            Some((a, b)) => (a.min(lo), b.max(hi)),
            None => (lo, hi),
        });
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

    /// Removes a solid: its carriers are deleted, its handle stays valid (and marked
    /// [`Solid::removed`]) so other handles do not change.
    pub fn remove_solid(&mut self, h: SolidHandle) -> Result<()> {
        let k = h.0 as usize;
        let Some(s) = self.solids.get(k) else {
            return Err(FluidError::OutOfRange {
                name: "solid handle",
                value: h.0 as f64,
                range: "a handle returned by this world",
            });
        };
        if s.removed {
            return Ok(());
        }
        let r = s.range.clone();
        self.solid.remove_range(r.clone());
        let len = r.len();
        for o in self.solids.iter_mut() {
            if o.range.start >= r.end {
                o.range = o.range.start - len..o.range.end - len;
            }
        }
        let s = &mut self.solids[k];
        s.range = r.start..r.start;
        s.local = Vec::new();
        s.removed = true;
        s.active = false;
        s.collider = None;
        s.rigid = None;
        self.solids_dirty = true;
        Ok(())
    }

    /// Uncouples a solid (same as [`Self::remove_solid`]): the fluid no longer sees it.
    pub fn uncouple(&mut self, h: SolidHandle) -> Result<()> {
        self.remove_solid(h)
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

    /// Removes the fluid carriers whose position satisfies `inside` (an outflow sink, see
    /// [`crate::emitter::Sink`]); returns how many. The caller counts them: this is not a
    /// silent loss.
    pub fn remove_fluid_where(&mut self, inside: impl Fn(Vector) -> bool + Sync) -> u64 {
        let keep: Vec<bool> = self.fluid.x.par_iter().map(|p| !inside(*p)).collect();
        let removed = keep.iter().filter(|k| !**k).count() as u64;
        if removed > 0 {
            self.fluid.retain(&keep);
        }
        removed
    }

    /// The kernel.
    pub fn kernel(&self) -> &CubicSpline {
        &self.kernel
    }
    /// Simulation domain (fixed at the first step).
    pub fn domain(&self) -> Option<(Vector, Vector)> {
        self.grid.map(|g| (g.lo, g.hi()))
    }

    /// Neighbour lists of the last substep (for diagnostics and tests).
    pub fn neighbor_lists(&self) -> &NeighborLists {
        &self.lists
    }

    /// The Poisson system of the last substep (Eq. 13), for diagnostics and tests.
    pub fn poisson_system(&self) -> &PoissonSystem {
        &self.system
    }

    /// Adds fluid carriers at `positions`, all with velocity `velocity`.
    pub fn add_particles(&mut self, positions: &[Vector], velocity: Vector) -> Result<()> {
        if positions.is_empty() {
            return Err(FluidError::EmptyFluid);
        }
        if !finite(velocity) {
            return Err(FluidError::NonFinite {
                what: "fluid velocity".into(),
            });
        }
        let total = (self.fluid.len() + self.solid.len() + positions.len()) as u64;
        if total > MAX_PARTICLES {
            return Err(FluidError::TooMany {
                what: "particles",
                count: total,
                limit: MAX_PARTICLES,
            });
        }
        if let Some(k) = positions.iter().position(|p| !finite(*p)) {
            return Err(FluidError::NonFinite {
                what: format!("fluid particle {k} position"),
            });
        }
        if let Some((lo, hi)) = self
            .domain()
            .or(self.params.domain.map(|(a, b)| (a.into(), b.into())))
        {
            if let Some(p) = positions
                .iter()
                .find(|p| (0..3).any(|k| p[k] < lo[k] || p[k] > hi[k]))
            {
                return Err(FluidError::OutsideDomain {
                    what: format!("fluid particle at {:?}", arr(*p)),
                    mins: arr(lo),
                    maxs: arr(hi),
                });
            }
        }
        for s in &self.solids {
            check_overlap(s, positions)?;
        }
        for &p in positions {
            self.fluid.push(p, velocity, self.next_id);
            self.next_id += 1;
        }
        Ok(())
    }

    /// Fills the box `[mins, maxs]` with fluid at rest spacing; returns the number added.
    pub fn add_block(&mut self, mins: Vector, maxs: Vector, velocity: Vector) -> Result<usize> {
        if !finite(mins) || !finite(maxs) {
            return Err(FluidError::NonFinite {
                what: "fluid block corners".into(),
            });
        }
        let dx = self.params.spacing;
        let count: u64 = (0..3)
            .map(|k| (((maxs[k] - mins[k]) / dx) + 1e-4).floor().max(0.0) as u64)
            .product();
        if count == 0 {
            return Err(FluidError::EmptyBlock {
                mins: arr(mins),
                maxs: arr(maxs),
                spacing: dx,
            });
        }
        if count > MAX_PARTICLES {
            return Err(FluidError::TooMany {
                what: "fluid block particles",
                count,
                limit: MAX_PARTICLES,
            });
        }
        let pts = fill_box(mins, maxs, dx);
        self.add_particles(&pts, velocity)?;
        Ok(pts.len())
    }

    /// Samples `shape` at `pose` into a static solid with the given slip condition.
    pub fn add_static_solid(
        &mut self,
        name: impl Into<String>,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
    ) -> Result<SolidHandle> {
        self.add_sampled(name.into(), shape, pose, slip, SolidKind::Static)
    }

    /// Samples `shape` at `pose` into a kinematic (scripted) solid, at rest until
    /// [`Self::set_kinematic`] gives it a velocity.
    ///
    /// ```
    /// use staggered_fluid::prelude::*;
    /// use rapier3d::parry::shape::SharedShape;
    /// let mut w = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
    /// let paddle = w
    ///     .add_kinematic_solid("paddle", SharedShape::cuboid(0.1, 0.2, 0.1), Pose::IDENTITY, Slip::NoSlip)
    ///     .unwrap();
    /// w.set_kinematic(paddle, Pose::IDENTITY, Vector::new(0.5, 0.0, 0.0), Vector::ZERO).unwrap();
    /// ```
    pub fn add_kinematic_solid(
        &mut self,
        name: impl Into<String>,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
    ) -> Result<SolidHandle> {
        self.add_sampled(name.into(), shape, pose, slip, SolidKind::Kinematic)
    }

    /// Sets a kinematic solid's pose and velocity (linear velocity of the pose origin, angular
    /// velocity about it). Between calls it keeps moving with that velocity.
    pub fn set_kinematic(
        &mut self,
        h: SolidHandle,
        pose: Pose,
        linvel: Vector,
        angvel: Vector,
    ) -> Result<()> {
        let s = self
            .solids
            .get(h.0 as usize)
            .ok_or(FluidError::OutOfRange {
                name: "solid handle",
                value: h.0 as f64,
                range: "a handle returned by this world",
            })?;
        if s.kind != SolidKind::Kinematic {
            return Err(FluidError::OutOfRange {
                name: "solid handle",
                value: h.0 as f64,
                range: "a kinematic solid",
            });
        }
        if !pose.is_finite() || !finite(linvel) || !finite(angvel) {
            return Err(FluidError::NonFinite {
                what: format!("pose or velocity of solid `{}`", s.name),
            });
        }
        let s = &mut self.solids[h.0 as usize];
        s.pose = pose;
        s.com = pose.translation;
        s.linvel = linvel;
        s.angvel = angvel;
        self.place_solid(h.0 as usize);
        Ok(())
    }

    /// Recomputes the world position, normal and velocity of a solid's carriers from its pose
    /// and velocity.
    pub(crate) fn place_solid(&mut self, k: usize) {
        place(&mut self.solids[k], &mut self.solid);
        self.solids_dirty = true;
    }

    /// Moves every kinematic solid with its velocity over `dt`.
    fn advance_kinematic(&mut self, dt: f32) {
        for k in 0..self.solids.len() {
            let s = &mut self.solids[k];
            if s.kind != SolidKind::Kinematic
                || (s.linvel == Vector::ZERO && s.angvel == Vector::ZERO)
            {
                continue;
            }
            (s.pose, s.com) = rigid::advance(s.pose, s.com, s.linvel, s.angvel, dt);
            self.place_solid(k);
        }
    }

    /// Samples `shape` at `pose` into a solid of the given kind (the shell fluid can reach,
    /// parry's normals).
    pub(crate) fn add_sampled(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
        kind: SolidKind,
    ) -> Result<SolidHandle> {
        self.add_sampled_on(name, shape, pose, slip, kind, None, &|_| true, &|_, n| n)
    }

    /// Samples a solid on the lattice through the world point `anchor` (see
    /// [`crate::sampling::sample_shell_on`]), keeping only carriers at world points where
    /// `reach` is true (the part of the shell fluid can reach) and giving each the normal
    /// `normal(x, n_shape)`.
    #[allow(clippy::too_many_arguments)]
    fn add_sampled_on(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
        kind: SolidKind,
        anchor: Option<Vector>,
        reach: &dyn Fn(Vector) -> bool,
        normal: &dyn Fn(Vector, Vector) -> Vector,
    ) -> Result<SolidHandle> {
        if !pose.is_finite() {
            return Err(FluidError::NonFinite {
                what: format!("pose of solid `{name}`"),
            });
        }
        if let Slip::Partial { viscosity } = slip {
            if !(viscosity.is_finite() && viscosity >= 0.0) {
                return Err(FluidError::OutOfRange {
                    name: "Slip::Partial::viscosity",
                    value: viscosity as f64,
                    range: ">= 0",
                });
            }
        }
        let mut samples = sample_shell_on(
            shape.as_ref(),
            self.params.spacing,
            self.params.support_radius(),
            anchor.map(|a| pose.inverse_transform_point(a)),
        )?;
        samples.retain(|s| reach(pose.transform_point(s.x)));
        // Overlapping static solids form a union: carriers already inside an earlier static
        // solid are skipped, so the overlap is sampled once and internal faces carry no carriers.
        // (moving solids are sampled whole: they will not stay where they are)
        if kind == SolidKind::Static {
            samples.retain(|s| {
                let w = pose.transform_point(s.x);
                !self.solids.iter().any(|o| {
                    o.kind == SolidKind::Static && !o.removed && o.shape.contains_point(&o.pose, w)
                })
            });
        }
        if samples.is_empty() {
            return Err(FluidError::DegenerateShape {
                shape: format!("{:?}", shape.shape_type()),
                why: format!("solid `{name}` lies entirely inside earlier solids"),
            });
        }
        let total = (self.fluid.len() + self.solid.len() + samples.len()) as u64;
        if total > MAX_PARTICLES {
            return Err(FluidError::TooMany {
                what: "particles",
                count: total,
                limit: MAX_PARTICLES,
            });
        }
        let start = self.solid.len();
        let idx = self.solids.len() as u32;
        // a static solid's carriers never move: no body-frame copy (24 B a carrier)
        let local: Vec<(Vector, Vector)> = if kind == SolidKind::Static {
            Vec::new()
        } else {
            samples.iter().map(|s| (s.x, s.n)).collect()
        };
        for s in &samples {
            self.solid.body.push(idx);
            let x = pose.transform_point(s.x);
            self.solid.x.push(x);
            self.solid.n.push(normal(x, pose.rotation * s.n));
            self.solid.u.push(Vector::ZERO);
            self.solid.f.push(Vector::ZERO);
            self.solid.volume.push(1.0);
        }
        let solid = Solid {
            name,
            kind,
            shape,
            pose,
            slip,
            stick: false,
            range: start..self.solid.len(),
            force: Vector::ZERO,
            torque: Vector::ZERO,
            linvel: Vector::ZERO,
            angvel: Vector::ZERO,
            com: pose.translation,
            rigid: None,
            collider: None,
            active: true,
            removed: false,
            pose_start: pose,
            local,
            placed: pose,
        };
        if let Err(e) = check_overlap(&solid, &self.fluid.x) {
            let end = self.solid.len();
            self.solid.remove_range(start..end);
            return Err(e);
        }
        self.solids.push(solid);
        self.solids_dirty = true;
        self.update_volumes(idx as usize);
        Ok(SolidHandle(idx))
    }

    /// Sets the relative volumes ([`SolidCarriers::volume`]) of solid `k`'s carriers: the
    /// kernel sum that a cubic lattice of spacing Δx would give over the solid's shell around
    /// each carrier, over the sum its actual neighbours in the shell give (Akinci et al. 2012
    /// boundary volumes, made relative so that any lattice-like sampling, flat, convex or at
    /// an edge, has volume 1). Where the shell is packed more densely than the lattice (the
    /// outer layer of a ball, moved to depth ½Δx) carriers weigh less. Static walls are
    /// sampled on the fluid lattice itself and keep 1.
    fn update_volumes(&mut self, k: usize) {
        let solid = &self.solids[k];
        if solid.kind == SolidKind::Static {
            return;
        }
        let h = self.params.support_radius();
        let dx = self.params.spacing;
        let kern = self.kernel;
        let shape = solid.shape.clone();
        let range = solid.range.clone();
        let local = |i: usize| solid.local[i - range.start].0;
        let reach = (h / dx).ceil() as i32;
        let in_shell = |p: Vector| {
            let d = crate::sampling::signed_distance(shape.as_ref(), p);
            d <= 0.0 && d >= -h
        };
        let key = |p: Vector| {
            (
                (p.x / h).floor() as i32,
                (p.y / h).floor() as i32,
                (p.z / h).floor() as i32,
            )
        };
        let mut cells: std::collections::HashMap<(i32, i32, i32), Vec<usize>> =
            std::collections::HashMap::new();
        for i in range.clone() {
            cells.entry(key(local(i))).or_default().push(i);
        }
        let vols: Vec<f32> = range
            .clone()
            .into_par_iter()
            .map(|i| {
                let p = local(i);
                let mut lattice = 0.0;
                for a in -reach..=reach {
                    for b in -reach..=reach {
                        for c in -reach..=reach {
                            let d = Vector::new(a as f32, b as f32, c as f32) * dx;
                            let r = d.length();
                            if r < h && in_shell(p + d) {
                                lattice += kern.w(r);
                            }
                        }
                    }
                }
                let c = key(p);
                let mut actual = 0.0f32;
                for dz in -1..=1 {
                    for dy in -1..=1 {
                        for dxc in -1..=1 {
                            for &j in cells
                                .get(&(c.0 + dxc, c.1 + dy, c.2 + dz))
                                .into_iter()
                                .flatten()
                            {
                                let r = (local(j) - p).length();
                                if r < h {
                                    actual += kern.w(r);
                                }
                            }
                        }
                    }
                }
                (lattice / actual.max(1e-12)).clamp(0.25, 4.0)
            })
            .collect();
        for (i, v) in range.zip(vols) {
            self.solid.volume[i] = v;
        }
    }

    /// Changes the slip condition of a solid (e.g. a no-slip floor in a free-slip tank).
    pub fn set_slip(&mut self, h: SolidHandle, slip: Slip) {
        if let Some(s) = self.solids.get_mut(h.0 as usize) {
            s.slip = slip;
        }
    }

    /// Lets fluid stick to a solid (turns the §5.2 no-stick inequality off), e.g. for the tap
    /// water that flows around a ball in He 2012 Fig. 13(b).
    pub fn set_sticky(&mut self, h: SolidHandle, stick: bool) {
        if let Some(s) = self.solids.get_mut(h.0 as usize) {
            s.stick = stick;
        }
    }

    /// Adds an open-topped tank (floor and four walls) whose inner space is
    /// `[inner_min, inner_max]` (y up). Returns the handles `[floor, -x, +x, -z, +z]`.
    ///
    /// The walls are `2h + Δx` thick (h the support radius) so that every carrier fluid can reach
    /// lies nearer the inside than the outside, their carriers sit on the lattice of a fluid
    /// block filled from `inner_min`, only the shell within h of the inside (or of the rim) is
    /// sampled, and each carrier's normal points to the nearest inside point (diagonal along
    /// edges and corners, where a single box's faces would give the wrong direction).
    pub fn add_open_tank(
        &mut self,
        inner_min: Vector,
        inner_max: Vector,
        slip: Slip,
    ) -> Result<[SolidHandle; 5]> {
        let h = self.params.support_radius();
        let t = 2.0 * h + self.params.spacing;
        let (lo, hi) = (inner_min, inner_max);
        if !finite(lo) || !finite(hi) {
            return Err(FluidError::NonFinite {
                what: "tank corners".into(),
            });
        }
        if (0..3).any(|k| hi[k] <= lo[k]) {
            return Err(FluidError::DegenerateShape {
                shape: "tank".into(),
                why: format!("inner extent {:?} is not positive", arr(hi - lo)),
            });
        }
        // Boxes overlap at the edges (a later box skips carriers inside earlier ones).
        let boxes = [
            (
                "floor",
                Vector::new(lo.x - t, lo.y - t, lo.z - t),
                Vector::new(hi.x + t, lo.y, hi.z + t),
            ),
            (
                "wall -x",
                Vector::new(lo.x - t, lo.y - t, lo.z - t),
                Vector::new(lo.x, hi.y, hi.z + t),
            ),
            (
                "wall +x",
                Vector::new(hi.x, lo.y - t, lo.z - t),
                Vector::new(hi.x + t, hi.y, hi.z + t),
            ),
            (
                "wall -z",
                Vector::new(lo.x - t, lo.y - t, lo.z - t),
                Vector::new(hi.x + t, hi.y, lo.z),
            ),
            (
                "wall +z",
                Vector::new(lo.x - t, lo.y - t, hi.z),
                Vector::new(hi.x + t, hi.y, hi.z + t),
            ),
        ];
        // fluid lives in the open column above the floor, or spills over the rim
        let reach = move |p: Vector| {
            let q = Vector::new(p.x.clamp(lo.x, hi.x), p.y.max(lo.y), p.z.clamp(lo.z, hi.z));
            (p - q).length() <= h || p.y >= hi.y - h
        };
        let normal = move |p: Vector, n_box: Vector| {
            let q = p.clamp(lo, hi);
            let d = q - p;
            let l = d.length();
            if l > 1e-6 && l < hi.y - p.y {
                d / l
            } else {
                n_box
            }
        };
        let mut out = [SolidHandle(0); 5];
        for (k, (name, a, b)) in boxes.into_iter().enumerate() {
            let half = (b - a) * 0.5;
            out[k] = self.add_sampled_on(
                name.into(),
                SharedShape::cuboid(half.x, half.y, half.z),
                Pose::from_translation((a + b) * 0.5),
                slip,
                SolidKind::Static,
                Some(lo),
                &reach,
                &normal,
            )?;
        }
        Ok(out)
    }

    /// Adds a static axis-aligned box `[mins, maxs]`.
    pub fn add_static_box(
        &mut self,
        name: &str,
        mins: Vector,
        maxs: Vector,
        slip: Slip,
    ) -> Result<SolidHandle> {
        if !finite(mins) || !finite(maxs) {
            return Err(FluidError::NonFinite {
                what: format!("box `{name}` corners"),
            });
        }
        let half = (maxs - mins) * 0.5;
        if half.min_element() <= 0.0 {
            return Err(FluidError::DegenerateShape {
                shape: "Cuboid".into(),
                why: format!(
                    "box `{name}` has non-positive extent {:?}",
                    arr(maxs - mins)
                ),
            });
        }
        self.add_static_solid(
            name,
            SharedShape::cuboid(half.x, half.y, half.z),
            Pose::from_translation((mins + maxs) * 0.5),
            slip,
        )
    }

    fn ensure_grid(&mut self) -> Result<()> {
        if self.grid.is_some() {
            return Ok(());
        }
        let (lo, hi) = match self.params.domain {
            Some((a, b)) => (Vector::from(a), Vector::from(b)),
            None => {
                let (mut flo, mut fhi) = bounding_box(&self.fluid.x);
                if let Some((a, b)) = self.domain_hint {
                    (flo, fhi) = (flo.min(a), fhi.max(b));
                }
                let (slo, shi) = bounding_box(&self.solid.x);
                let (lo, hi) = (flo.min(slo), fhi.max(shi));
                // Along an axis where solids bound the fluid on both sides (a slab between two
                // walls) fluid leaves only over a wall top, so the margin there need not exceed
                // half the extent: a 0.1 m margin around a 7.5 mm slab made the dense cell grid
                // 30× the particles (at 614k fluid: neighbour stage 0.55 → 0.28 s, peak memory
                // 1.73 → 1.39 GiB with the smaller margin)
                let h = self.params.support_radius();
                let m = Vector::from(std::array::from_fn::<f32, 3, _>(|k| {
                    let enclosed = slo[k] < flo[k] && shi[k] > fhi[k];
                    let margin = self.params.domain_margin;
                    if enclosed {
                        margin.min(0.5 * (hi[k] - lo[k]))
                    } else {
                        margin
                    }
                })) + Vector::splat(h);
                (lo - m, hi + m)
            }
        };
        let cell = self.params.support_radius() * (1.0 + self.params.neighbor_skin);
        let grid = Grid::new(lo, hi, cell);
        if grid.cell_count() > MAX_CELLS {
            return Err(FluidError::TooMany {
                what: "neighbour-grid cells (shrink the domain or grow the spacing)",
                count: grid.cell_count(),
                limit: MAX_CELLS,
            });
        }
        self.grid = Some(grid);
        Ok(())
    }

    /// The box of `domain`'s cells the neighbour search runs on this step: the fluid's bounding
    /// box with a margin of 8 cells, kept while the fluid stays 2 cells inside it (so the solids
    /// are sorted into it again only when the fluid has moved on, or when solids moved).
    fn search_box(&mut self, domain: &Grid) -> Grid {
        let (a, b) = bounding_box(&self.fluid.x);
        let (a, b) = (domain.coords(a), domain.coords(b));
        let inside = |s: &Grid| {
            (0..3).all(|k| {
                let (lo, hi) = (s.origin[k], s.origin[k] + s.dims[k] - 1);
                (a[k] >= lo + 2 || lo == 0) && (b[k] + 2 <= hi || hi == domain.dims[k] - 1)
            })
        };
        match self.search {
            Some(s) if !self.solids_dirty && inside(&s) => s,
            _ => {
                let s = domain.crop(a.map(|c| c.saturating_sub(8)), b.map(|c| c + 8));
                self.search = Some(s);
                self.sort_solids(&s);
                s
            }
        }
    }

    fn sort_solids(&mut self, grid: &Grid) {
        // only active solids' carriers inside the domain take part (bodies no fluid is near
        // cost nothing)
        let (lo, hi) = (grid.min(), grid.hi());
        let idx: Vec<u32> = (0..self.solid.len() as u32)
            .filter(|&i| {
                let p = self.solid.x[i as usize];
                self.solids[self.solid.body[i as usize] as usize].active
                    && (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k])
            })
            .collect();
        let cells: Vec<u32> = idx
            .iter()
            .map(|&i| grid.cell_of(self.solid.x[i as usize]))
            .collect();
        let order = counting_sort_into(&cells, grid.cell_count() as usize, &mut self.solid_start);
        self.solid_ids = order.iter().map(|&o| idx[o as usize]).collect();
        self.solids_dirty = false;
    }

    /// Marks moving solids (and their rapier bodies) active when some fluid carrier lies within
    /// two support radii of their bounding box.
    fn update_activity(&mut self) {
        let Some(grid) = self.grid else { return };
        if self.solids.iter().all(|s| s.kind == SolidKind::Static) {
            return;
        }
        let mut occupied = vec![false; grid.cell_count() as usize];
        for p in &self.fluid.x {
            occupied[grid.cell_of(*p) as usize] = true;
        }
        let margin = Vector::splat(2.0 * self.params.support_radius());
        let (glo, ghi) = (grid.lo, grid.hi());
        for s in self.solids.iter_mut() {
            if s.kind == SolidKind::Static || s.removed {
                continue;
            }
            let aabb = s.shape.compute_aabb(&s.pose);
            let (lo, hi) = (aabb.mins - margin, aabb.maxs + margin);
            let was = s.active;
            s.active = if (0..3).any(|k| hi[k] < glo[k] || lo[k] > ghi[k]) {
                false
            } else {
                let (a, b) = (grid.coords(lo), grid.coords(hi));
                (a[2]..=b[2]).any(|z| {
                    (a[1]..=b[1])
                        .any(|y| (a[0]..=b[0]).any(|x| occupied[grid.index([x, y, z]) as usize]))
                })
            };
            self.solids_dirty |= was != s.active;
        }
        for (k, r) in self.rigids.iter_mut().enumerate() {
            r.active = self.solids.iter().any(|s| s.rigid == Some(k) && s.active);
        }
    }

    /// Dynamic bodies at the start of a substep: gravity, then the predicted pose the fluid
    /// sees (He 2012 Algorithm 1 predicts fluid and solids together).
    fn predict_rigids(&mut self, gravity: Vector, dt: f32) {
        for r in self.rigids.iter_mut().filter(|r| r.moving()) {
            let free = r.inv_mass().cmpgt(Vector::ZERO);
            let g = Vector::select(free, gravity * r.gravity_scale, Vector::ZERO);
            r.linvel += g * dt;
            r.start = (r.com, r.rotation);
        }
        self.move_rigid_solids(dt, true);
    }

    /// Dynamic bodies at the end of a substep: the pose reached with the final velocity
    /// (symplectic Euler, as rapier integrates it). The carriers stay where the substep's
    /// forces acted until the next substep (or the next sync) places them.
    fn finish_rigids(&mut self, dt: f32) {
        self.move_rigid_solids(dt, false);
    }

    fn move_rigid_solids(&mut self, dt: f32, start: bool) {
        for r in self.rigids.iter_mut().filter(|r| r.moving()) {
            let (com0, rot0) = r.start;
            r.com = com0 + r.linvel * dt;
            r.rotation = (Rotation::from_scaled_axis(r.angvel * dt) * rot0).normalize();
        }
        for k in 0..self.solids.len() {
            let Some(ri) = self.solids[k].rigid else {
                continue;
            };
            let r = &self.rigids[ri];
            if !r.moving() {
                continue;
            }
            let s = &mut self.solids[k];
            if start {
                s.pose_start = s.pose;
            }
            let (com0, _) = r.start;
            let (pose, com) = rigid::advance(s.pose_start, com0, r.linvel, r.angvel, dt);
            s.pose = pose;
            s.linvel = r.linvel;
            s.angvel = r.angvel;
            if start {
                // the carriers (and the torque reference) stay where this substep's forces act
                s.com = com;
                self.place_solid(k);
            }
        }
    }

    /// Moves the carriers of moving dynamic bodies from `x0` by the displacement `Δt (ΔU + Δω ×
    /// r)` that the impulses `imp` of one density iteration would give them (their velocity is
    /// kicked only once, by [`Self::absorb`], after the last iteration).
    fn shift_rigids(&mut self, imp: &crate::solver::Impulses, x0: &[Vector], dt: f32) {
        let mut per = vec![[0.0f64; 6]; self.rigids.len()];
        for &(s, j) in imp {
            let s = s as usize;
            let b = self.solid.body[s] as usize;
            if let Some(ri) = self.solids[b].rigid {
                add6(&mut per[ri], &rigid::wrench(j, x0[s] - self.solids[b].com));
            }
        }
        let dv: Vec<(Vector, Vector)> = self
            .rigids
            .iter()
            .zip(&per)
            .map(|(r, e)| {
                if !r.moving() {
                    return (Vector::ZERO, Vector::ZERO);
                }
                let (j, l) = rigid::split(e);
                r.response(j, l)
            })
            .collect();
        for sol in &self.solids {
            let Some(ri) = sol.rigid else { continue };
            let (du, dw) = dv[ri];
            if du == Vector::ZERO && dw == Vector::ZERO {
                continue;
            }
            for i in sol.range.clone() {
                self.solid.x[i] = x0[i] + (du + dw.cross(x0[i] - sol.com)) * dt;
            }
        }
    }

    /// Adds the impulses of one stage to the per-carrier and per-solid totals (Eq. 21: torque
    /// about each solid's centre of mass) and kicks the dynamic bodies, whose carriers then move
    /// with the new velocity in the next stage. Takes them by value, so each stage's impulses
    /// are freed once absorbed.
    fn absorb(&mut self, imp: crate::solver::Impulses) {
        if imp.is_empty() {
            return;
        }
        let mut per = vec![[0.0f64; 6]; self.solids.len()];
        for &(s, j) in &imp {
            let s = s as usize;
            // the carrier's impulse so far this step; a force once the step ends
            self.solid.f[s] += j;
            let b = self.solid.body[s] as usize;
            add6(
                &mut per[b],
                &rigid::wrench(j, self.solid.x[s] - self.solids[b].com),
            );
        }
        let mut kicked = vec![false; self.rigids.len()];
        for (b, e) in per.iter().enumerate() {
            add6(&mut self.impulses[b], e);
            if let Some(ri) = self.solids[b].rigid {
                let r = &mut self.rigids[ri];
                add6(&mut r.impulse, e);
                if r.moving() {
                    let (j, l) = rigid::split(e);
                    r.kick(j, l);
                    kicked[ri] = true;
                }
            }
        }
        if kicked.iter().any(|&k| k) {
            for s in self.solids.iter_mut() {
                if let Some(ri) = s.rigid.filter(|&ri| kicked[ri]) {
                    s.linvel = self.rigids[ri].linvel;
                    s.angvel = self.rigids[ri].angvel;
                    let c = &mut self.solid;
                    for i in s.range.clone() {
                        c.u[i] = s.linvel + s.angvel.cross(c.x[i] - s.com);
                    }
                }
            }
        }
    }

    /// Advances the fluid by `dt` seconds under `gravity` (He 2012 Algorithm 1), splitting the
    /// step into substeps when the CFL or viscosity limit requires it. Dynamic bodies move with
    /// gravity and the fluid's impulses during the substeps; their total fluid impulse is in
    /// [`FluidWorld::rigids`] (and handed to rapier by [`FluidWorld::step_with_rapier`]).
    pub fn step(&mut self, gravity: Vector, dt: f32) -> Result<&StepReport> {
        positive("dt", dt as f64)?;
        if !finite(gravity) {
            return Err(FluidError::NonFinite {
                what: "gravity".into(),
            });
        }
        if self.fluid.is_empty() {
            return Err(FluidError::EmptyFluid);
        }
        self.ensure_grid()?;
        self.update_activity();
        let dx = self.params.spacing;
        let solid_speed = (0..self.solid.len())
            .filter(|&i| self.solids[self.solid.body[i] as usize].active)
            .map(|i| self.solid.u[i].length())
            .fold(0.0, f32::max);
        let vmax = self
            .fluid
            .v
            .par_iter()
            .map(|v| v.length())
            .reduce(|| 0.0, f32::max)
            .max(solid_speed);
        // PCISPH has no velocity constraint: where two bodies of water close on each other by
        // more than ≈ 0.2 Δx in one step its iterations diverge (measured: slabs meeting at
        // ±1 m/s explode at CFL 0.4 and 0.2, are fine at 0.1; a 3 m/s impact on a plate is
        // fine at 0.2, with Shao's correction); the staggered solver takes 0.4
        let cfl = match self.params.solver {
            Solver::Pcisph => self.params.max_cfl.min(PCISPH_MAX_CFL),
            Solver::Staggered => self.params.max_cfl,
        };
        let mut dt_max = cfl * dx / (vmax + gravity.length() * dt).max(1e-6);
        // body-force limit Δt ≤ c √(Δx/|g|), c = 0.15 by default: a fluid at rest has no speed
        // to limit its step; a 1/60 s step at Δx = 1 cm blew up on its second step, and with
        // c = ¼ (2 substeps of 1/60 s at Δx = 2 cm) water 20 carriers deep under floating
        // cubes blew up at 10 density iterations and settled 20 % compressed at 3
        if gravity.length() > 0.0 {
            dt_max = dt_max.min(self.params.body_force_limit * (dx / gravity.length()).sqrt());
        }
        let nu = self
            .solids
            .iter()
            .map(|s| s.slip.wall_viscosity(self.params.viscosity))
            .fold(self.params.viscosity, f32::max);
        if nu > 0.0 {
            dt_max = dt_max.min(0.125 * dx * dx / nu);
        }
        let substeps = (dt / dt_max).ceil().clamp(1.0, 1000.0) as u32;
        let h = dt / substeps as f32;
        let mut rep = StepReport {
            converged: true,
            ..Default::default()
        };
        self.impulses.clear();
        self.impulses.resize(self.solids.len(), [0.0; 6]);
        self.solid.f.iter_mut().for_each(|f| *f = Vector::ZERO);
        for r in self.rigids.iter_mut() {
            r.impulse = [0.0; 6];
        }
        for _ in 0..substeps {
            // kinematic solids first take their pose at the end of the substep
            self.advance_kinematic(h);
            self.predict_rigids(gravity, h);
            self.substep(gravity, h, &mut rep)?;
        }
        for (s, j) in self.solids.iter_mut().zip(&self.impulses) {
            let (force, torque) = rigid::split(j);
            s.force = force / dt;
            s.torque = torque / dt;
        }
        self.solid.f.iter_mut().for_each(|f| *f /= dt);
        self.steps += 1;
        self.time += dt as f64;
        rep.step = self.steps;
        rep.time = self.time;
        rep.dt = dt as f64;
        rep.substeps = substeps;
        rep.n_fluid = self.fluid.len();
        rep.n_solid = self.solid_ids.len();
        rep.max_speed = self
            .fluid
            .v
            .par_iter()
            .map(|v| v.length())
            .reduce(|| 0.0, f32::max);
        self.report = rep;
        Ok(&self.report)
    }

    /// The penetration correction once more, against the solids' current poses (after rapier
    /// moved the bodies with its own integration, which differs from the fluid's substeps by
    /// the last contact kick and by gyroscopic terms). Returns the impulse `[J; L]` on each
    /// dynamic body (index into [`Self::rigids`]) and the number of carriers corrected.
    pub(crate) fn correct_after_move(&mut self) -> (Vec<[f64; 6]>, usize) {
        let mut per = vec![[0.0f64; 6]; self.rigids.len()];
        if self.lists.offsets.len() != self.fluid.len() + 1 {
            return (per, 0);
        }
        let bodies = self.body_views();
        let shapes = self.shapes();
        let ctx = ctx!(self, &bodies);
        let (imp, n) = crate::solver::contact::correct_penetration(
            &ctx,
            &shapes,
            &mut self.fluid.x,
            &mut self.fluid.v,
        );
        // these impulses belong to the step just taken: they join its forces (Eq. 21)
        let dt = (self.report.dt as f32).max(1e-12);
        for &(s, j) in &imp {
            let s = s as usize;
            let b = self.solid.body[s] as usize;
            let e = rigid::wrench(j, self.solid.x[s] - self.solids[b].com);
            if let Some(f) = self.solid.f.get_mut(s) {
                *f += j / dt;
            }
            let sol = &mut self.solids[b];
            let (force, torque) = rigid::split(&e);
            sol.force += force / dt;
            sol.torque += torque / dt;
            if let Some(ri) = sol.rigid {
                add6(&mut per[ri], &e);
            }
        }
        (per, n)
    }

    /// Each solid's shape and current world pose (what the penetration correction tests).
    fn shapes(&self) -> Vec<(SharedShape, Pose)> {
        self.solids
            .iter()
            .map(|s| (s.shape.clone(), s.pose))
            .collect()
    }

    fn body_views(&self) -> Vec<BodyView> {
        let static_share = Share::new(self.mass, self.params.rest_density, self.rest_neighbors);
        self.solids
            .iter()
            .map(|s| BodyView {
                share: static_share,
                viscosity: s.slip.wall_viscosity(self.params.viscosity),
                slip: s.slip,
                stick: s.stick,
                com: s.com,
                rigid: s
                    .rigid
                    .filter(|&r| self.rigids[r].moving())
                    .map_or(u32::MAX, |r| r as u32),
            })
            .collect()
    }

    fn substep(&mut self, gravity: Vector, dt: f32, rep: &mut StepReport) -> Result<()> {
        let grid = self.grid.expect("grid initialised in step");
        let mut times = StageTimes::default();
        let t = Instant::now();
        // --- neighbours: cull, sort by cell, lists (Table 3 t_neighbor)
        let (lo, hi) = self.domain().expect("grid");
        let keep: Vec<bool> = self
            .fluid
            .x
            .par_iter()
            .map(|p| (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]))
            .collect();
        let removed = keep.iter().filter(|k| !**k).count();
        if removed > 0 {
            self.fluid.retain(&keep);
            self.removed_total += removed as u64;
            rep.removed_outside += removed as u64;
            if self.fluid.is_empty() {
                return Err(FluidError::EmptyFluid);
            }
        }
        let grid = self.search_box(&grid);
        let sc = &mut self.scratch;
        sc.cells.clear();
        sc.cells
            .par_extend(self.fluid.x.par_iter().map(|p| grid.cell_of(*p)));
        let order =
            counting_sort_into(&sc.cells, grid.cell_count() as usize, &mut self.fluid_start);
        self.fluid.permute(&order);
        let radius = self.params.support_radius() * (1.0 + self.params.neighbor_skin);
        build_lists(
            &grid,
            radius,
            &self.fluid.x,
            &self.fluid_start,
            &self.solid.x,
            &self.solid_ids,
            &self.solid_start,
            &mut self.lists,
        );
        times.neighbors = t.elapsed().as_secs_f64();

        let bodies = self.body_views();
        // (`ctx!` gives a fresh read-only view after every stage that may have kicked a body)
        let n = self.fluid.len();

        // --- body + viscous forces, prediction, density constraint (Alg. 1 l.2–4, Alg. 2)
        let t = Instant::now();
        self.scratch.v_old.clone_from(&self.fluid.v);
        let imp = forces::viscous_prediction(
            &ctx!(self, &bodies),
            &self.fluid.x,
            &self.scratch.v_old,
            &mut self.fluid.v,
            gravity,
            dt,
        );
        self.absorb(imp);
        let fl = &mut self.fluid;
        fl.x.par_iter_mut()
            .zip(fl.v.par_iter())
            .for_each(|(x, v)| *x += *v * dt);
        let sc = &mut self.scratch;
        sc.rho.resize(n, 0.0);
        sc.count.resize(n, 0);
        sc.accel.resize(n, Vector::ZERO);
        // Algorithm 2: iterations of density (Eq. 22) → EOS pressure p^d ≥ 0 (accumulated,
        // PCISPH stiffness) → generalized pressure force (Eq. 23) moving the predicted
        // positions. Dynamic bodies move with the force of each iteration too, so a body the
        // fluid pushes gives way instead of the fluid alone taking up the compression.
        // PCISPH (Shao 2014): iterate to the solver tolerance on the mean compression with the
        // full stiffness of Eq. 5, Akinci boundary forces and Eq. 12's position correction
        // inside the loop
        let pcisph = self.params.solver == Solver::Pcisph;
        let relax = if pcisph {
            1.0
        } else {
            self.params.density_relaxation
        };
        let k = relax * density::stiffness(&ctx!(self, &bodies), self.grad_sq, dt);
        let rest = self.params.rest_density;
        let x0 = self.fluid.x.clone();
        let solid_x0 = self
            .rigids
            .iter()
            .any(|r| r.moving())
            .then(|| self.solid.x.clone());
        self.fluid.p_density.par_iter_mut().for_each(|p| *p = 0.0);
        let mut imp = crate::solver::Impulses::new();
        let mut done = 0;
        let (min_it, max_it, tol) = if pcisph {
            (
                self.params.density_iterations.max(1),
                self.params.max_pcisph_iterations.max(1),
                self.params.density_error_tolerance,
            )
        } else {
            (
                self.params.density_iterations,
                self.params
                    .max_density_iterations
                    .max(self.params.density_iterations),
                self.params.density_tolerance,
            )
        };
        let solid_mass = if pcisph {
            self.carrier_masses()
        } else {
            Vec::new()
        };
        let mut compression = 0.0;
        // whether rho, count and asym hold the current positions' values: an evaluation that
        // may end the loop also computes the asymmetry, so the staggered creation and the
        // surface marking reuse it instead of running their own neighbour loops
        let mut fresh = false;
        self.scratch.asym.resize(n, 0.0);
        for it in 0..max_it {
            let sc = &mut self.scratch;
            density::density_and_count(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &mut sc.rho,
                &mut sc.count,
                (it >= min_it && !pcisph).then_some(&mut sc.asym[..]),
            );
            // the mean compression is needed for the stopping rule (and PCISPH's report) only
            if it >= min_it || pcisph {
                let rho = &sc.rho;
                compression = crate::solver::det_sum(n, |i| (rho[i] - rest).max(0.0) as f64)
                    / n as f64
                    / rest as f64;
                if it >= min_it && compression <= tol as f64 {
                    fresh = !pcisph;
                    break;
                }
            }

            done += 1;
            // the last iteration's impulses are replaced: freed before the new ones are built
            drop(std::mem::take(&mut imp));
            self.fluid
                .p_density
                .par_iter_mut()
                .zip(sc.rho.par_iter())
                .for_each(|(p, &r)| *p = (*p + k * (r - rest)).max(0.0));
            imp = density::pressure_accel(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &self.fluid.p_density,
                &sc.rho,
                &mut sc.accel,
                dt,
                pcisph,
            );
            predict(&mut self.fluid.x, &x0, &sc.accel, dt);
            if pcisph && !self.solid.x.is_empty() {
                let sc = &mut self.scratch;
                sc.v_old.clear();
                sc.v_old.par_extend(
                    self.fluid
                        .v
                        .par_iter()
                        .zip(sc.accel.par_iter())
                        .map(|(&v, &a)| v + a * dt),
                );
                crate::solver::contact::shao_correction(
                    &ctx!(self, &bodies),
                    self.params.spacing,
                    &solid_mass,
                    &sc.v_old,
                    &mut self.fluid.x,
                    None,
                );
            }
            if let Some(sx0) = &solid_x0 {
                self.shift_rigids(&imp, sx0, dt);
            }
        }
        if done > 0 && pcisph {
            // Eq. 12 inside the loop served the density prediction only: the step itself
            // integrates the final pressure force, and the correction after it (end_pcisph)
            // then sees the true penetrations
            predict(&mut self.fluid.x, &x0, &self.scratch.accel, dt);
        }
        if done > 0 {
            let sc = &self.scratch;
            self.fluid
                .v
                .par_iter_mut()
                .zip(sc.accel.par_iter())
                .for_each(|(v, &a)| *v += a * dt);
        }
        self.absorb(imp);
        // not needed past the density constraint: freed before the solve's vectors exist
        drop((x0, solid_x0));
        times.density = t.elapsed().as_secs_f64();
        rep.density_iterations += done;
        if pcisph {
            return self.end_pcisph(&bodies, &solid_mass, compression, dt, times, rep);
        }

        // --- staggered creation: ρ_i, N_i, shares (Eqs. 7, 9, 22)
        let t = Instant::now();
        let sc = &mut self.scratch;
        if !fresh {
            density::density_and_count(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &mut sc.rho,
                &mut sc.count,
                Some(&mut sc.asym),
            );
        }
        sc.shares.clear();
        let mass = self.mass;
        sc.shares.par_extend(
            sc.rho
                .par_iter()
                .zip(sc.count.par_iter())
                .map(|(&r, &c)| Share::new(mass, r, c)),
        );
        times.staggered = t.elapsed().as_secs_f64();

        // --- free surface (Eq. 25) and isolated regions
        let t = Instant::now();
        sc.surface.resize(n, false);
        surface::detect(
            &ctx!(self, &bodies),
            &sc.rho,
            &sc.asym,
            self.params.surface_asymmetry,
            self.params.surface_density,
            &mut sc.surface,
        );
        let up = (-gravity).try_normalize().unwrap_or(Vector::Y);
        surface::mark_isolated(&ctx!(self, &bodies), &self.fluid.x, up, &mut sc.surface);
        times.surface = t.elapsed().as_secs_f64();
        // the density stage's buffers are refilled next step: freed here, so the solve's
        // vectors take their place instead of adding to the peak (32 B per carrier)
        sc.v_old = Vec::new();
        sc.accel = Vec::new();
        sc.asym = Vec::new();
        sc.cells = Vec::new();

        // --- assembly of Eq. 13 with wall conditions (Eqs. 26–27)
        let t = Instant::now();
        let consistent = self.params.remap == crate::params::Remap::Consistent;
        if consistent {
            let ctx = ctx!(self, &bodies);
            velocity::assemble(
                &ctx,
                &self.fluid.x,
                &self.fluid.v,
                &sc.shares,
                &sc.surface,
                dt,
                self.div_norm,
                self.params.gradient_correction,
                self.params.preconditioner == crate::params::Preconditioner::BlockSsor,
                &mut self.system,
            );
            let inv: Vec<(Vector, Matrix)> = self
                .rigids
                .iter()
                .map(|r| (r.inv_mass(), r.inv_inertia()))
                .collect();
            velocity::link_rigids(&ctx, &inv, &mut self.system);
        } else {
            projection::assemble(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &self.fluid.v,
                &sc.shares,
                &sc.surface,
                dt,
                &mut self.system,
            );
        }
        times.assembly = t.elapsed().as_secs_f64();

        // --- PCG solve, warm-started from last step's p^v
        let t = Instant::now();
        sc.p.clear();
        sc.p.par_extend(
            self.fluid
                .p_velocity
                .par_iter()
                .zip(self.system.unknown.par_iter())
                .map(|(&p, &u)| if u { p as f64 } else { 0.0 }),
        );
        let settings = PcgSettings {
            kind: self.params.preconditioner,
            krylov: self.params.krylov,
            omega: self.params.ssor_omega as f64,
            block: self.params.ssor_block,
            tolerance: self.params.density_error_tolerance as f64,
            relative_residual: self.params.relative_residual as f64,
            max_iterations: self.params.max_pcg_iterations,
            dt: dt as f64,
        };
        let mut stats = pcg::solve(&self.system, &self.lists, &mut sc.p, settings);
        if consistent
            && self.params.no_stick
            && velocity::release_wall_suction(
                &ctx!(self, &bodies),
                &self.fluid.v,
                &mut self.system,
                &mut sc.p,
            ) > 0
        {
            let again = pcg::solve(&self.system, &self.lists, &mut sc.p, settings);
            stats = pcg::PcgStats {
                iterations: stats.iterations + again.iterations,
                initial_error: stats.initial_error,
                ..again
            };
        }
        times.solve = t.elapsed().as_secs_f64();

        // --- remap (Eq. 19) and bookkeeping
        let t = Instant::now();
        let p = std::mem::take(&mut self.scratch.p);
        if consistent {
            let imp = velocity::apply_pressure(
                &ctx!(self, &bodies),
                &self.system,
                &p,
                dt,
                &mut self.fluid.v,
            );
            self.absorb(imp);
            let sc = &self.scratch;
            let imp = velocity::no_slip(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &sc.shares,
                &sc.count,
                &mut self.fluid.v,
            );
            self.absorb(imp);
            let sc = &self.scratch;
            let imp = velocity::surface_walls(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &sc.shares,
                &sc.count,
                &self.system.unknown,
                &mut self.fluid.v,
            );
            self.absorb(imp);
        } else {
            let sc = &mut self.scratch;
            sc.v_old.clone_from(&self.fluid.v);
            let imp = projection::remap(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &sc.v_old,
                &sc.shares,
                &sc.count,
                &p,
                dt,
                self.params.remap,
                &mut self.fluid.v,
            );
            self.absorb(imp);
            if self.params.remap == crate::params::Remap::Conservative {
                let sc = &mut self.scratch;
                sc.accel.resize(n, Vector::ZERO);
                let imp = density::pressure_accel(
                    &ctx!(self, &bodies),
                    &self.fluid.x,
                    &p,
                    &sc.rho,
                    &mut sc.accel,
                    dt,
                    false,
                );
                self.absorb(imp);
                let fl = &mut self.fluid;
                fl.v.par_iter_mut()
                    .zip(self.scratch.accel.par_iter())
                    .for_each(|(v, &a)| *v += a * dt);
            }
        }
        if self.params.xsph > 0.0 {
            let sc = &mut self.scratch;
            sc.v_old.clone_from(&self.fluid.v);
            let imp = forces::xsph(
                &ctx!(self, &bodies),
                &self.fluid.x,
                &sc.v_old,
                &sc.rho,
                self.params.xsph,
                self.params.xsph_walls,
                &mut self.fluid.v,
            );
            self.absorb(imp);
        }
        // against the pose dynamic bodies reach at the end of the substep (they move with their
        // final velocity; the fluid's positions were predicted): no carrier is left inside
        // (the correction's own impulses change the bodies' velocities for the next substep,
        // like rapier's velocity-level contacts)
        self.finish_rigids(dt);
        let final_shapes = self.shapes();
        let (imp, corrected) = crate::solver::contact::correct_penetration(
            &ctx!(self, &bodies),
            &final_shapes,
            &mut self.fluid.x,
            &mut self.fluid.v,
        );
        self.absorb(imp);
        rep.penetrations_corrected += corrected as u64;
        self.scratch.p = p;
        let sc = &mut self.scratch;
        let fl = &mut self.fluid;
        fl.p_velocity
            .par_iter_mut()
            .zip(sc.p.par_iter())
            .for_each(|(d, &s)| *d = s as f32);
        fl.density.clone_from(&sc.rho);
        fl.neighbors.clone_from(&sc.count);
        fl.surface.clone_from(&sc.surface);
        self.check_finite()?;
        let sc = &self.scratch;
        let sys = &self.system;
        let n_unknown = sys.unknown.iter().filter(|&&u| u).count();
        let dev = crate::solver::det_sum(n, |i| {
            if sys.unknown[i] {
                ((sc.rho[i] - self.params.rest_density).abs() / self.params.rest_density) as f64
            } else {
                0.0
            }
        });
        times.other = t.elapsed().as_secs_f64();

        rep.stages.add(&times);
        rep.pcg_iterations += stats.iterations;
        rep.error = rep.error.max(stats.error);
        rep.initial_error = rep.initial_error.max(stats.initial_error);
        rep.converged &= stats.converged;
        rep.n_surface = n - n_unknown;
        rep.n_unknown = n_unknown;
        rep.n_pairs = self.lists.pair_count();
        rep.density_deviation = if n_unknown > 0 {
            dev / n_unknown as f64
        } else {
            0.0
        };
        Ok(())
    }
}

impl FluidWorld {
    /// The mass a solid carrier of each body stands for in Shao's correction (Eq. 13–17):
    /// the body's mass over its carriers for moving dynamic bodies, `∞` for the rest.
    fn carrier_masses(&self) -> Vec<f32> {
        self.solids
            .iter()
            .map(|s| match s.rigid.map(|r| &self.rigids[r]) {
                Some(r) if r.moving() && r.mprops.inv_mass > 0.0 => {
                    1.0 / (r.mprops.inv_mass * s.range.len().max(1) as f32)
                }
                _ => f32::INFINITY,
            })
            .collect()
    }

    /// The end of a PCISPH substep (Shao 2014 Algorithm 1): bodies take their end pose, then
    /// the velocity–position correction (Eqs. 11–17) runs against their carriers.
    fn end_pcisph(
        &mut self,
        bodies: &[BodyView],
        solid_mass: &[f32],
        compression: f64,
        dt: f32,
        mut times: StageTimes,
        rep: &mut StepReport,
    ) -> Result<()> {
        let t = Instant::now();
        // (the correction reads only the bodies' slip from `bodies`; the carriers' new poses
        // come from the solid arrays)
        self.finish_rigids(dt);
        let v_now = self.fluid.v.clone();
        let (imp, corrected) = crate::solver::contact::shao_correction(
            &ctx!(self, bodies),
            self.params.spacing,
            solid_mass,
            &v_now,
            &mut self.fluid.x,
            Some(&mut self.fluid.v),
        );
        self.absorb(imp);
        rep.penetrations_corrected += corrected as u64;
        let n = self.fluid.len();
        let sc = &self.scratch;
        let fl = &mut self.fluid;
        fl.p_velocity.iter_mut().for_each(|p| *p = 0.0);
        fl.density.clone_from(&sc.rho);
        fl.neighbors.clone_from(&sc.count);
        fl.surface.clear();
        fl.surface.resize(n, false);
        self.check_finite()?;
        times.other = t.elapsed().as_secs_f64();
        rep.stages.add(&times);
        rep.error = rep.error.max(compression);
        rep.converged &= compression <= self.params.density_error_tolerance as f64;
        rep.n_surface = 0;
        rep.n_unknown = n;
        rep.n_pairs = self.lists.pair_count();
        let rest = self.params.rest_density;
        let rho = &self.scratch.rho;
        rep.density_deviation =
            crate::solver::det_sum(n, |i| ((rho[i] - rest).abs() / rest) as f64) / n.max(1) as f64;
        Ok(())
    }

    /// A NaN or infinite position or velocity anywhere is an error, never silently spread.
    fn check_finite(&self) -> Result<()> {
        let fl = &self.fluid;
        if let Some(i) =
            fl.x.iter()
                .zip(&fl.v)
                .position(|(x, v)| !finite(*x) || !finite(*v))
        {
            return Err(FluidError::Diverged {
                step: self.steps,
                what: format!(
                    "fluid particle {} (id {}) position or velocity",
                    i, fl.id[i]
                ),
            });
        }
        if let Some(r) = self
            .rigids
            .iter()
            .find(|r| !finite(r.linvel) || !finite(r.angvel))
        {
            return Err(FluidError::Diverged {
                step: self.steps,
                what: format!("rigid body {:?} velocity", r.handle),
            });
        }
        Ok(())
    }
}

/// Largest CFL number the PCISPH solver runs at, whatever [`FluidParams::max_cfl`] says.
pub const PCISPH_MAX_CFL: f32 = 0.1;

/// The predicted positions of the density constraint: `x = x0 + a Δt²`.
fn predict(x: &mut [Vector], x0: &[Vector], accel: &[Vector], dt: f32) {
    x.par_iter_mut()
        .zip(x0.par_iter())
        .zip(accel.par_iter())
        .for_each(|((x, &x0), &a)| *x = x0 + a * (dt * dt));
}

fn check_overlap(solid: &Solid, positions: &[Vector]) -> Result<()> {
    let inside: Vec<&Vector> = positions
        .iter()
        .filter(|p| solid.shape.contains_point(&solid.pose, **p))
        .collect();
    if let Some(first) = inside.first() {
        return Err(FluidError::FluidOverlapsSolid {
            solid: solid.name.clone(),
            count: inside.len(),
            first: arr(**first),
        });
    }
    Ok(())
}

/// Puts a solid's carriers at their world position, normal and velocity from its pose and
/// motion (`u = U + ω × (x − X)`, X the centre of rotation).
///
/// A static solid keeps no body-frame copy: a new pose moves its carriers by the change of
/// pose (applied only when the pose changed, so an unchanged pose adds no rounding).
pub(crate) fn place(s: &mut Solid, c: &mut SolidCarriers) {
    let (pose, v, w, com) = (s.pose, s.linvel, s.angvel, s.com);
    if s.local.is_empty() {
        if s.placed != pose {
            let rel = pose * s.placed.inverse();
            for i in s.range.clone() {
                c.x[i] = rel.transform_point(c.x[i]);
                c.n[i] = rel.rotation * c.n[i];
            }
        }
        for i in s.range.clone() {
            c.u[i] = v + w.cross(c.x[i] - com);
        }
    } else {
        for (i, &(p, n)) in s.range.clone().zip(&s.local) {
            let x = pose.transform_point(p);
            c.x[i] = x;
            c.n[i] = pose.rotation * n;
            c.u[i] = v + w.cross(x - com);
        }
    }
    s.placed = pose;
}

/// `a += b` for `[J; L]` impulse pairs.
fn add6(a: &mut [f64; 6], b: &[f64; 6]) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}
