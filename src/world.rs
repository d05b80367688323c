//! [`FluidWorld`]: the fluid, its solids, and the step of He 2012 Algorithm 1.

use crate::error::{positive, FluidError, Result};
use crate::kernel::CubicSpline;
use crate::math::{arr, finite, Pose, Rotation, Vector};
use crate::metrics::{StageTimes, StepReport};
use crate::neighbors::{build_lists, counting_sort, Grid, NeighborLists};
use crate::params::{FluidParams, MAX_CELLS, MAX_PARTICLES};
use crate::particles::{FluidCarriers, SolidCarriers};
use crate::sampling::{fill_box, sample_shell_on};
use crate::solver::pcg::{self, PcgSettings, PoissonSystem};
use crate::solver::staggered::{Share, Slip};
use crate::solver::{density, forces, projection, surface, velocity, BodyView, Ctx};
use rapier3d::parry::shape::SharedShape;
use rayon::prelude::*;
use std::time::Instant;

/// Handle of a solid added to a [`FluidWorld`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SolidHandle(pub u32);

/// How a solid moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolidKind {
    /// Never moves (walls, tanks).
    Static,
    /// Scripted (He 2012 §6): moves with the velocity given by
    /// [`FluidWorld::set_kinematic`], pushes the fluid, and reports the fluid's force and
    /// torque, but is not pushed back.
    Kinematic,
}

/// A solid sampled into solid carriers.
#[derive(Clone)]
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
    /// Torque of the fluid on the solid about its pose origin over the last step, N·m (Eq. 21).
    pub torque: Vector,
    /// Linear velocity of the pose origin, m/s (kinematic solids).
    pub linvel: Vector,
    /// Angular velocity, rad/s (kinematic solids).
    pub angvel: Vector,
}

#[derive(Default)]
struct Scratch {
    v_old: Vec<Vector>,
    accel: Vec<Vector>,
    rho: Vec<f32>,
    count: Vec<u32>,
    shares: Vec<Share>,
    surface: Vec<bool>,
    p: Vec<f64>,
    cells: Vec<u32>,
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
    next_id: u32,
    time: f64,
    steps: u64,
    removed_total: u64,
    grid: Option<Grid>,
    solids_dirty: bool,
    solid_sorted: Vec<Vector>,
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
            next_id: 0,
            time: 0.0,
            steps: 0,
            removed_total: 0,
            grid: None,
            solids_dirty: true,
            solid_sorted: Vec::new(),
            solid_ids: Vec::new(),
            solid_start: Vec::new(),
            fluid_start: Vec::new(),
            lists: NeighborLists::default(),
            system: PoissonSystem::new(),
            scratch: Scratch::default(),
            report: StepReport::default(),
        })
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
    pub fn kernel(&self) -> &CubicSpline {
        &self.kernel
    }
    /// Simulation domain (fixed at the first step).
    pub fn domain(&self) -> Option<(Vector, Vector)> {
        self.grid.map(|g| {
            let hi =
                g.lo + Vector::new(g.dims[0] as f32, g.dims[1] as f32, g.dims[2] as f32) * g.cell;
            (g.lo, hi)
        })
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
        self.add_static_sampled(name.into(), shape, pose, slip, None, &|_| true, &|_, n| n)
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
        let h = self.add_static_solid(name, shape, pose, slip)?;
        self.solids[h.0 as usize].kind = SolidKind::Kinematic;
        Ok(h)
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
        s.linvel = linvel;
        s.angvel = angvel;
        self.place_solid(h.0 as usize);
        Ok(())
    }

    /// Recomputes the world position, normal and velocity of a solid's carriers from its pose
    /// and velocity.
    fn place_solid(&mut self, k: usize) {
        let s = &self.solids[k];
        let (pose, v, w) = (s.pose, s.linvel, s.angvel);
        let c = &mut self.solid;
        for i in s.range.clone() {
            let x = pose.transform_point(c.local[i]);
            c.x[i] = x;
            c.n[i] = pose.rotation * c.local_normal[i];
            c.u[i] = v + w.cross(x - pose.translation);
        }
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
            let rot = Rotation::from_scaled_axis(s.angvel * dt) * s.pose.rotation;
            s.pose = Pose::from_parts(s.pose.translation + s.linvel * dt, rot.normalize());
            self.place_solid(k);
        }
    }

    /// [`Self::add_static_solid`] on the lattice through the world point `anchor` (see
    /// [`crate::sampling::sample_shell_on`]), keeping only carriers at world points where
    /// `reach` is true (the part of the shell fluid can reach) and giving each the normal
    /// `normal(x, n_shape)`.
    #[allow(clippy::too_many_arguments)]
    fn add_static_sampled(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
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
        samples.retain(|s| {
            let w = pose.transform_point(s.x);
            !self
                .solids
                .iter()
                .any(|o| o.kind == SolidKind::Static && o.shape.contains_point(&o.pose, w))
        });
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
        for s in &samples {
            self.solid.body.push(idx);
            self.solid.local.push(s.x);
            self.solid.local_normal.push(s.n);
            self.solid.phi.push(s.phi);
            let x = pose.transform_point(s.x);
            self.solid.x.push(x);
            self.solid.n.push(normal(x, pose.rotation * s.n));
            self.solid.u.push(Vector::ZERO);
        }
        let solid = Solid {
            name,
            kind: SolidKind::Static,
            shape,
            pose,
            slip,
            stick: false,
            range: start..self.solid.len(),
            force: Vector::ZERO,
            torque: Vector::ZERO,
            linvel: Vector::ZERO,
            angvel: Vector::ZERO,
        };
        if let Err(e) = check_overlap(&solid, &self.fluid.x) {
            self.solid_truncate(start);
            return Err(e);
        }
        self.solids.push(solid);
        self.solids_dirty = true;
        Ok(SolidHandle(idx))
    }

    fn solid_truncate(&mut self, n: usize) {
        let s = &mut self.solid;
        s.body.truncate(n);
        s.local.truncate(n);
        s.local_normal.truncate(n);
        s.phi.truncate(n);
        s.x.truncate(n);
        s.n.truncate(n);
        s.u.truncate(n);
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
            out[k] = self.add_static_sampled(
                name.into(),
                SharedShape::cuboid(half.x, half.y, half.z),
                Pose::from_translation((a + b) * 0.5),
                slip,
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
                let mut lo = Vector::splat(f32::INFINITY);
                let mut hi = Vector::splat(f32::NEG_INFINITY);
                for p in self.fluid.x.iter().chain(self.solid.x.iter()) {
                    lo = lo.min(*p);
                    hi = hi.max(*p);
                }
                let m = Vector::splat(self.params.domain_margin + self.params.support_radius());
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

    fn sort_solids(&mut self, grid: &Grid) {
        let cells: Vec<u32> = self.solid.x.iter().map(|p| grid.cell_of(*p)).collect();
        let (order, start) = counting_sort(&cells, grid.cell_count() as usize);
        self.solid_sorted = order.iter().map(|&o| self.solid.x[o as usize]).collect();
        self.solid_ids = order;
        self.solid_start = start;
        self.solids_dirty = false;
    }

    /// Advances the fluid by `dt` seconds under `gravity` (He 2012 Algorithm 1), splitting the
    /// step into substeps when the CFL or viscosity limit requires it.
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
        let dx = self.params.spacing;
        let vmax = self
            .fluid
            .v
            .par_iter()
            .map(|v| v.length())
            .reduce(|| 0.0, f32::max)
            .max(self.solid.u.iter().map(|u| u.length()).fold(0.0, f32::max));
        let mut dt_max = self.params.max_cfl * dx / (vmax + gravity.length() * dt).max(1e-6);
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
        let mut impulses = vec![[0.0f64; 6]; self.solids.len()];
        for _ in 0..substeps {
            // kinematic solids first take their pose at the end of the substep
            self.advance_kinematic(h);
            self.substep(gravity, h, &mut rep, &mut impulses)?;
        }
        for (s, j) in self.solids.iter_mut().zip(&impulses) {
            s.force = Vector::new(j[0] as f32, j[1] as f32, j[2] as f32) / dt;
            s.torque = Vector::new(j[3] as f32, j[4] as f32, j[5] as f32) / dt;
        }
        self.steps += 1;
        self.time += dt as f64;
        rep.step = self.steps;
        rep.time = self.time;
        rep.dt = dt as f64;
        rep.substeps = substeps;
        rep.n_fluid = self.fluid.len();
        rep.n_solid = self.solid.len();
        rep.max_speed = self
            .fluid
            .v
            .par_iter()
            .map(|v| v.length())
            .reduce(|| 0.0, f32::max);
        self.report = rep;
        Ok(&self.report)
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
                com: s.pose.translation,
            })
            .collect()
    }

    fn substep(
        &mut self,
        gravity: Vector,
        dt: f32,
        rep: &mut StepReport,
        impulses: &mut [[f64; 6]],
    ) -> Result<()> {
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
        if self.solids_dirty {
            self.sort_solids(&grid);
        }
        let sc = &mut self.scratch;
        sc.cells.clear();
        sc.cells
            .par_extend(self.fluid.x.par_iter().map(|p| grid.cell_of(*p)));
        let (order, start) = counting_sort(&sc.cells, grid.cell_count() as usize);
        self.fluid.permute(&order);
        self.fluid_start = start;
        let radius = self.params.support_radius() * (1.0 + self.params.neighbor_skin);
        build_lists(
            &grid,
            radius,
            &self.fluid.x,
            &self.fluid_start,
            &self.solid_sorted,
            &self.solid_ids,
            &self.solid_start,
            &mut self.lists,
        );
        times.neighbors = t.elapsed().as_secs_f64();

        let bodies = self.body_views();
        let ctx = Ctx {
            kernel: self.kernel,
            mass: self.mass,
            rest_density: self.params.rest_density,
            kernel_norm: self.kernel_norm,
            viscosity: self.params.viscosity,
            lists: &self.lists,
            solid_x: &self.solid.x,
            solid_n: &self.solid.n,
            solid_phi: &self.solid.phi,
            solid_u: &self.solid.u,
            solid_body: &self.solid.body,
            bodies: &bodies,
        };
        let n = self.fluid.len();
        let sc = &mut self.scratch;
        let fl = &mut self.fluid;

        // --- body + viscous forces, prediction, density constraint (Alg. 1 l.2–4, Alg. 2)
        let t = Instant::now();
        sc.v_old.clone_from(&fl.v);
        let imp = forces::viscous_prediction(&ctx, &fl.x, &sc.v_old, &mut fl.v, gravity, dt);
        crate::solver::add_impulses(impulses, &imp);
        fl.x.par_iter_mut()
            .zip(fl.v.par_iter())
            .for_each(|(x, v)| *x += *v * dt);
        sc.rho.resize(n, 0.0);
        sc.count.resize(n, 0);
        sc.accel.resize(n, Vector::ZERO);
        let k = self.params.density_relaxation * density::stiffness(&ctx, self.grad_sq, dt);
        let imp = density::density_constraint(
            &ctx,
            &mut fl.x,
            &mut fl.v,
            &mut sc.rho,
            &mut sc.count,
            &mut fl.p_density,
            &mut sc.accel,
            k,
            self.params.density_iterations,
            dt,
        );
        crate::solver::add_impulses(impulses, &imp);
        times.density = t.elapsed().as_secs_f64();

        // --- staggered creation: ρ_i, N_i, shares (Eqs. 7, 9, 22)
        let t = Instant::now();
        density::density_and_count(&ctx, &fl.x, &mut sc.rho, &mut sc.count);
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
            &ctx,
            &fl.x,
            &sc.rho,
            self.params.surface_asymmetry,
            self.params.surface_density,
            &mut sc.surface,
        );
        let up = (-gravity).try_normalize().unwrap_or(Vector::Y);
        surface::mark_isolated(&ctx, &fl.x, up, &mut sc.surface);
        times.surface = t.elapsed().as_secs_f64();

        // --- assembly of Eq. 13 with wall conditions (Eqs. 26–27)
        let t = Instant::now();
        let consistent = self.params.remap == crate::params::Remap::Consistent;
        if consistent {
            velocity::assemble(
                &ctx,
                &fl.x,
                &fl.v,
                &sc.shares,
                &sc.surface,
                dt,
                self.div_norm,
                self.params.gradient_correction,
                &mut self.system,
            );
        } else {
            projection::assemble(
                &ctx,
                &fl.x,
                &fl.v,
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
            fl.p_velocity
                .par_iter()
                .zip(self.system.unknown.par_iter())
                .map(|(&p, &u)| if u { p as f64 } else { 0.0 }),
        );
        let settings = PcgSettings {
            kind: self.params.preconditioner,
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
            && velocity::release_wall_suction(&ctx, &fl.v, &mut self.system, &mut sc.p) > 0
        {
            let again = pcg::solve(&self.system, &self.lists, &mut sc.p, settings);
            stats = pcg::PcgStats {
                iterations: stats.iterations + again.iterations,
                initial_error: stats.initial_error,
                ..again
            };
        }
        let sys = &self.system;
        times.solve = t.elapsed().as_secs_f64();

        // --- remap (Eq. 19) and bookkeeping
        let t = Instant::now();
        if consistent {
            let imp = velocity::apply_pressure(&ctx, sys, &sc.p, dt, &mut fl.v);
            crate::solver::add_impulses(impulses, &imp);
            let imp = velocity::no_slip(&ctx, &fl.x, &sc.shares, &sc.count, &mut fl.v);
            crate::solver::add_impulses(impulses, &imp);
            let imp = velocity::surface_walls(
                &ctx,
                &fl.x,
                &sc.shares,
                &sc.count,
                &sys.unknown,
                &mut fl.v,
            );
            crate::solver::add_impulses(impulses, &imp);
        } else {
            sc.v_old.clone_from(&fl.v);
            let imp = projection::remap(
                &ctx,
                &fl.x,
                &sc.v_old,
                &sc.shares,
                &sc.count,
                &sc.p,
                dt,
                self.params.remap,
                &mut fl.v,
            );
            crate::solver::add_impulses(impulses, &imp);
            if self.params.remap == crate::params::Remap::Conservative {
                let imp = density::pressure_accel(&ctx, &fl.x, &sc.p, &sc.rho, &mut sc.accel, dt);
                crate::solver::add_impulses(impulses, &imp);
                fl.v.par_iter_mut()
                    .zip(sc.accel.par_iter())
                    .for_each(|(v, &a)| *v += a * dt);
            }
        }
        let (imp, corrected) =
            crate::solver::contact::correct_penetration(&ctx, &mut fl.x, &mut fl.v);
        crate::solver::add_impulses(impulses, &imp);
        rep.penetrations_corrected += corrected as u64;
        fl.p_velocity
            .par_iter_mut()
            .zip(sc.p.par_iter())
            .for_each(|(d, &s)| *d = s as f32);
        fl.density.clone_from(&sc.rho);
        fl.neighbors.clone_from(&sc.count);
        fl.surface.clone_from(&sc.surface);
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
