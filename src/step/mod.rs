//! The step of He 2012 Algorithm 1, one stage per module.
//!
//! [`FluidWorld::step`] splits a step into substeps (CFL, body-force and viscosity limits); each
//! substep runs the neighbour search ([`neighbours`]) and then the chosen [`PressureSolver`]:
//! [`he2012`] (the staggered solver: [`prediction`] → [`density`] → [`creation`] →
//! [`surface`] → [`velocity`] → [`remap`] → [`smoothing`] → [`penetration`]) or [`pcisph`]
//! (Shao et al. 2014: [`prediction`] → [`density`] with its own settings → the
//! velocity–position correction). Every stage is timed into [`StageTimes`].

mod creation;
mod density;
mod guards;
mod he2012;
mod heat;
mod neighbours;
mod pcisph;
mod penetration;
mod placement;
mod prediction;
mod remap;
mod rest_pressure;
mod sealed;
mod smoothing;
mod surface;
mod velocity;

pub(crate) use guards::carrier_energy;
pub use pcisph::{PCISPH_BODY_FORCE_LIMIT, PCISPH_MAX_CFL};

use crate::error::{positive, FluidError, Result};
use crate::math::{finite, Vector};
use crate::metrics::{StageTimes, StepReport};
use crate::params::{FluidParams, OnFailure, Solver};
use crate::rigid;
use crate::solver::BodyView;
use crate::world::{FluidWorld, SolidKind};
use rayon::prelude::*;
use std::time::Instant;

/// Most substeps one step takes.
const MAX_SUBSTEPS: u32 = 1000;

/// Largest distance, in spacings, a moving rigid solid's surface (dynamic or kinematic; a
/// deformable body's surface moves with its lattice) may advance along its normal in one
/// substep: half the quarter spacing the density constraint may move a carrier in one
/// (`he2012::MAX_SHIFT`). Motion along the surface pushes no water aside: counted, a ball
/// spinning at 47 rad/s under water took 16 substeps a 1/60 s frame. A body
/// driven into the water pushes it aside faster than itself (a 25° wedge's jet runs at several
/// times its speed) before the water has the speed the CFL limit sees. With the fluid's CFL
/// limit alone a wedge at 5 m/s moved that whole quarter spacing each 1 ms substep, built a
/// 15 % compression under it within 9 ms, and the substeps the density controller then added
/// released it at once (0.66 m/s lost in 1 ms, Wagner's bound 0.16). Only carriers that can
/// reach the water's bounding box within the step count: a fast body in the air above a pool
/// costs no substeps until the frame in which it may arrive.
const SOLID_SHIFT: f32 = 0.125;

/// Largest body-force limit ([`crate::FluidParams::body_force_limit`]) of a world with
/// deformable bodies (LSM solids, cloth), whose stiffness is set against that limit's
/// substep: at 0.2 an elastic box being filled erupted at its second 1/60 s step (1.25 J
/// added) and a soft cloth let 100 carriers of a dropped column through (thirty-sixth
/// session).
pub(crate) const DEFORMABLE_BODY_FORCE_LIMIT: f32 = 0.15;

/// Largest density-loop spring ([`crate::FluidParams::max_loop_spring`]) of a world with
/// deformable bodies: at 4 (relaxation floor 0.3) a heavy LSM cube resting on the floor kept
/// bouncing on the water squeezed under it (−4.6 cm/s after 1.5 s; at 2, floor 0.5, at rest).
pub(crate) const DEFORMABLE_LOOP_SPRING: f32 = 2.0;

/// Largest factor by which the density constraint multiplies the substeps.
const MAX_DENSITY_SUBSTEPS: f32 = 8.0;

/// Averaging window of the carriers' acceleration for the hydrostatic wall pressure, in units
/// of √(Δx/|g|) (the time a carrier falls half a spacing from rest).
const ACCEL_WINDOW: f32 = 0.1;

/// What every stage of one substep reads: gravity, the substep's length and the solids' view.
pub(crate) struct Substep {
    /// Gravity, m/s².
    pub gravity: Vector,
    /// Substep length, s.
    pub dt: f32,
    /// Per-solid data of the stages (shares, slip, centre of mass, dynamic body).
    pub bodies: Vec<BodyView>,
}

/// A pressure solver: everything of a substep after the neighbour search. One implementation
/// per method, chosen once per substep from [`FluidParams::solver`] ([`solver_for`]); the shared stages (neighbour search,
/// forces, density, coupling) are methods of [`FluidWorld`] that any solver calls.
pub(crate) trait PressureSolver: Sync {
    /// Largest CFL number `v_max Δt/Δx` the solver runs at with parameters `p`.
    fn max_cfl(&self, p: &FluidParams) -> f32;
    /// Longest substep the solver's own iterations converge at in world `w` under `gravity`
    /// (none: no limit).
    fn max_substep(&self, _w: &FluidWorld, _gravity: Vector) -> Option<f32> {
        None
    }
    /// The mean compression its density loop works to with parameters `p`: what the substep
    /// controller ([`FluidWorld::raise_density_substeps`]) compares a substep's with.
    fn mean_tolerance(&self, p: &FluidParams) -> f32 {
        p.density_mean_tolerance
    }
    /// Advances fluid and coupled bodies over one substep, timing its stages into `times` and
    /// adding its counts to `rep`.
    fn substep(
        &self,
        w: &mut FluidWorld,
        s: &Substep,
        times: &mut StageTimes,
        rep: &mut StepReport,
    ) -> Result<()>;
}

/// The solver of [`FluidParams::solver`].
pub(crate) fn solver_for(kind: Solver) -> &'static dyn PressureSolver {
    match kind {
        Solver::Staggered => &he2012::He2012,
        Solver::Pcisph => &pcisph::Pcisph,
    }
}

/// Runs `f`, adding its wall-clock seconds to `slot`.
pub(crate) fn timed<T>(slot: &mut f64, f: impl FnOnce() -> T) -> T {
    let t = Instant::now();
    let out = f();
    *slot += t.elapsed().as_secs_f64();
    out
}

impl FluidWorld {
    /// Advances the fluid by `dt` seconds under `gravity` (He 2012 Algorithm 1), splitting the
    /// step into substeps when the CFL or viscosity limit requires it. Dynamic bodies move with
    /// gravity and the fluid's impulses during the substeps; their total fluid impulse is in
    /// [`FluidWorld::rigids`] (and handed to rapier by [`FluidWorld::step_with_rapier`]).
    /// Returns the step's report by value ([`FluidWorld::last_report`] keeps a copy), so the
    /// world can be read and changed while it is held.
    pub fn step(&mut self, gravity: Vector, dt: f32) -> Result<StepReport> {
        positive("dt", dt as f64)?;
        if !finite(gravity) {
            return Err(FluidError::NonFinite {
                what: "gravity".into(),
            });
        }
        if self.fluid.is_empty() {
            return Err(if self.removed_total > 0 {
                FluidError::FluidLost {
                    removed: self.removed_total,
                }
            } else {
                FluidError::EmptyFluid
            });
        }
        self.ensure_grid()?;
        // the fastest fluid carrier (read by the activity margin and the CFL limit)
        let fluid_speed = self
            .fluid
            .v
            .par_iter()
            .map(|v| v.length())
            .reduce(|| 0.0, f32::max);
        self.update_activity(dt, fluid_speed);
        let energy = self.energy_start(gravity, dt);
        let (substeps, capped) = self.substep_count(gravity, dt, fluid_speed);
        if let (Some(asked), OnFailure::Error) = (capped, self.params.on_failure) {
            // refused before the work: 1 000 substeps of a large world take minutes
            return Err(FluidError::StepFailed {
                step: self.steps + 1,
                time: self.time + dt as f64,
                what: guards::cap_message(asked, dt),
            });
        }
        let mut rep = StepReport {
            converged: true,
            density_converged: true,
            ..Default::default()
        };
        self.impulses.clear();
        self.impulses.resize(self.solids.len(), [0.0; 6]);
        self.solid.f.iter_mut().for_each(|f| *f = Vector::ZERO);
        for r in self.rigids.iter_mut() {
            r.impulse = [0.0; 6];
            r.wall_impulse = [0.0; 6];
        }
        // substeps of equal length, unless the density constraint starts to fail within the
        // step (a substep's iterations diverge, or it ends beyond the tolerance with more
        // compression than the substep before): then the rest of the step is split finer at
        // once, where the controller would otherwise react only after the step
        let (mut left, mut remaining, mut taken, mut raised) = (substeps, dt, 0u32, false);
        let mut before = f64::INFINITY;
        self.set_cloth_reference(gravity, dt, dt / substeps as f32);
        while left > 0 {
            // (dt / substeps until a re-split, so that an undisturbed step is what it was)
            let h = if raised {
                remaining / left as f32
            } else {
                dt / substeps as f32
            };
            self.recent_step = (self.recent_step - h).max(h);
            // kinematic solids first take their pose at the end of the substep
            self.advance_kinematic(h);
            timed(&mut rep.stages.deformable, || {
                self.prepare_deformables(gravity, h)
            });
            self.predict_rigids(gravity, h);
            self.substep_diverged = false;
            self.substep_compression = 0.0;
            self.open_placement_window(gravity, h);
            self.substep(gravity, h, &mut rep)?;
            self.close_placement_window(h);
            timed(&mut rep.stages.deformable, || {
                self.finish_deformables(h);
                rep.cloth_corrections += self.keep_water_off_cloths() as u64;
            });
            remaining -= h;
            left -= 1;
            taken += 1;
            let (c, tol) = (self.substep_compression, self.mean_tolerance());
            let failing = self.substep_diverged || (c > tol && c > before);
            before = c;
            if left > 0 && failing {
                if let Some(f) = self.raise_density_substeps(c.max(1.5 * tol)) {
                    left = ((left as f32 * f).ceil() as u32)
                        .min(MAX_SUBSTEPS.saturating_sub(taken))
                        .max(left);
                    raised = true;
                }
            }
        }
        let substeps = taken;
        if self.heat_on() {
            let t = Instant::now();
            self.exchange_heat(dt, &mut rep);
            self.melt(&mut rep);
            rep.stages.deformable += t.elapsed().as_secs_f64();
        }
        for (s, j) in self.solids.iter_mut().zip(&self.impulses) {
            let (force, torque) = rigid::split(j);
            s.force = force / dt;
            s.torque = torque / dt;
        }
        self.solid.f.iter_mut().for_each(|f| *f /= dt);
        if !raised {
            self.adapt_density_substeps(&rep);
        }
        // a raise this step (within it or after it) continues the burst into the next
        self.density_raised_before = std::mem::take(&mut self.density_raised_now);
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
        let guards = self.check_guards(&energy, capped, &mut rep);
        self.report = rep.clone();
        guards.map(|()| rep)
    }

    /// How many substeps `dt` takes: the CFL limit on fluid (`fluid_speed`, the fastest
    /// carrier's) and active solid speeds (at the solver's largest CFL number), the rigid
    /// shift limit, the body-force limit and the viscosity limit; with the
    /// count the limits asked for when [`MAX_SUBSTEPS`] cut it.
    fn substep_count(&self, gravity: Vector, dt: f32, fluid_speed: f32) -> (u32, Option<f64>) {
        let dx = self.params.spacing;
        // the fluid's bounding box, widened by a support radius: a rigid carrier that cannot
        // reach it within the step pushes no water in it
        let h = self.params.support_radius();
        let (lo, hi) = crate::math::bounding_box(&self.fluid.x);
        let near_water = |p: Vector, reach: f32| {
            let gap = (lo - p).max(p - hi).max(Vector::ZERO);
            gap.length() <= reach + h
        };
        // the fastest active solid carrier, and the fastest advance along its normal of a
        // rigid one that can reach the water
        let (solid_speed, rigid_speed) = (0..self.solid.len())
            .map(|i| {
                (
                    &self.solids[self.solid.body[i] as usize],
                    self.solid.u[i].length(),
                    i,
                )
            })
            .filter(|(s, _, _)| s.active)
            .fold((0.0f32, 0.0f32), |(all, rigid), (s, u, i)| {
                let wet = s.kind != SolidKind::Deformable && near_water(self.solid.x[i], u * dt);
                let advance = self.solid.u[i].dot(self.solid.n[i]).max(0.0);
                (all.max(u), if wet { rigid.max(advance) } else { rigid })
            });
        let vmax = fluid_speed.max(solid_speed);
        let solver = solver_for(self.params.solver);
        let cfl = solver.max_cfl(&self.params);
        let mut dt_max = cfl * dx / (vmax + gravity.length() * dt).max(1e-6);
        if let Some(limit) = solver.max_substep(self, gravity) {
            dt_max = dt_max.min(limit);
        }
        if rigid_speed > 0.0 {
            dt_max = dt_max.min(SOLID_SHIFT * dx / rigid_speed);
        }
        // body-force limit Δt ≤ c √(Δx/|g|), c = 0.2 by default: a fluid at rest has no speed
        // to limit its step; a 1/60 s step at Δx = 1 cm blew up on its second step, and with
        // c = ¼ (2 substeps of 1/60 s at Δx = 2 cm) water 20 carriers deep under floating
        // cubes blew up at 10 density iterations and settled 20 % compressed at 3 (before the
        // loop's spring limit, which now gives that water three)
        if let Some(limit) = self.body_force_step(self.body_force_limit(), gravity) {
            dt_max = dt_max.min(limit);
        }
        let nu = self
            .solids
            .iter()
            .map(|s| s.slip.wall_viscosity(self.params.viscosity))
            .fold(self.params.viscosity, f32::max);
        if nu > 0.0 {
            dt_max = dt_max.min(0.125 * dx * dx / nu);
        }
        let asked = (dt as f64 * self.density_substeps as f64 / dt_max as f64).ceil();
        let capped = (asked.is_nan() || asked > MAX_SUBSTEPS as f64).then_some(asked);
        (asked.clamp(1.0, MAX_SUBSTEPS as f64) as u32, capped)
    }

    /// The density constraint's own limit on the substep length, a step-size controller on
    /// `r = mean / density_mean_tolerance` of the step just taken: the compression a substep
    /// leaves grows about as its length squared, so a step with `r > 1` multiplies the
    /// substeps by `√(2r)` (at most 1.5×, at most 8× in all) to bring the next to `r ≈ ½`.
    /// While `r < ½` the factor relaxes: by 15 % a step down to 1.3× the factor the last
    /// burst of raises started from (the step length known to fail), by 3 % below it (a
    /// faster relaxation all the way made a still tank at 1/60 s swing between 3 and 11
    /// substeps, 14 % compression at the swing's end). After the five balls' splash at 1/60 s
    /// the 3 % alone kept 13–19 substeps a frame for a simulated second at a twentieth of the
    /// tolerance. The largest compression does not steer it: single carriers squeezed where a
    /// body rests on a wall stay compressed at any step length (20–70 % under a ball on the
    /// five-ball floor).
    fn adapt_density_substeps(&mut self, rep: &StepReport) {
        if self.raise_density_substeps(rep.compression_mean).is_none() {
            let r = rep.compression_mean / self.mean_tolerance();
            if r < 0.5 {
                let f = self.density_substeps;
                let floor = 1.3 * self.density_substeps_failed;
                self.density_substeps = if f > floor {
                    (f * 0.85).max(floor)
                } else {
                    f * 0.97
                }
                .max(1.0);
            }
        }
    }

    /// Raises the density constraint's substep factor by `√(2r)` (at most 1.5×, at most 8×
    /// in all) when a step ended at `r = compression / density_mean_tolerance > 1`, or when a
    /// substep failed within a step (then with `r` at least 1.5); returns the factor applied.
    /// The factor a burst of raises starts from is remembered
    /// ([`Self::adapt_density_substeps`] relaxes quickly only down to just above it).
    /// A still tank at 1/60 s relaxed from four substeps to three and its three substeps of
    /// 5.6 ms failed in turn (mean compression 0.06 → 0.12 → 0.6 %, in another run up to 5.7
    /// % with one carrier at 43 % and the kinetic energy ×800) before the step ended; failing
    /// is a substep whose iterations diverged or that ended beyond the tolerance with more
    /// compression than the one before. A substep that is merely beyond the tolerance does not
    /// re-split its step: water pushed in by a submerged tap is compressed at the first
    /// substep and relieved by the next, and re-splitting there left pairs of surface carriers
    /// 0.1Δx apart for 70 of 150 steps instead of 9.
    fn raise_density_substeps(&mut self, compression: f64) -> Option<f32> {
        let r = (compression / self.mean_tolerance()) as f32;
        if r <= 1.0 {
            return None;
        }
        let old = self.density_substeps;
        if !self.density_raised_before && !self.density_raised_now {
            self.density_substeps_failed = old;
        }
        self.density_raised_now = true;
        self.density_substeps = (old * (2.0 * r).sqrt().min(1.5)).min(MAX_DENSITY_SUBSTEPS);
        Some(self.density_substeps / old).filter(|&f| f > 1.0)
    }

    /// Gives each cloth that has none its reference substep `Δt₁` (its stiffness is `α m /
    /// Δt₁²` whatever the substeps then are, `deform/substep.rs`): this step `dt` split by the
    /// shared body-force limit ([`Self::body_force_limit`]) alone, or `first` (the step's
    /// first substep) without gravity. Not the solver's own substep: PCISPH's are shorter
    /// ([`PCISPH_BODY_FORCE_LIMIT`]), and with them the same α made a cloth 6× stiffer (its sag
    /// under a column 38 → 5.5 mm).
    fn set_cloth_reference(&mut self, gravity: Vector, dt: f32, first: f32) {
        let reference = match self.body_force_step(self.body_force_limit(), gravity) {
            Some(limit) => dt / (dt / limit).ceil().max(1.0),
            None => first,
        };
        for b in self.deformables.iter_mut().filter(|b| b.cloth) {
            if b.reference_substep.is_nan() || b.reference_substep <= 0.0 {
                b.reference_substep = reference;
            }
        }
    }

    /// The body-force limit `c` of this world's substeps: [`FluidParams::body_force_limit`],
    /// at most [`DEFORMABLE_BODY_FORCE_LIMIT`] while deformable bodies are in it.
    pub(crate) fn body_force_limit(&self) -> f32 {
        self.capped_with_deformables(self.params.body_force_limit, DEFORMABLE_BODY_FORCE_LIMIT)
    }

    /// The density loop's largest spring `μ` in this world: [`FluidParams::max_loop_spring`],
    /// at most [`DEFORMABLE_LOOP_SPRING`] while deformable bodies are in it.
    pub(crate) fn max_loop_spring(&self) -> f32 {
        self.capped_with_deformables(self.params.max_loop_spring, DEFORMABLE_LOOP_SPRING)
    }

    /// Whether the density loop scales its pressure force ([`FluidParams::pressure_scale`]):
    /// not while deformable bodies are in this world. Their lattice points push along the
    /// normals the lattice gives, not as the pair moment counts them, and the hot melting
    /// scene (`melt_probe`), whose water squeezed into the melting ice winds up to 120 kPa
    /// either way, then threw a carrier out of the tank (`melting_ice_keeps_the_mass`).
    pub(crate) fn pressure_scale(&self) -> bool {
        self.params.pressure_scale && self.deformables.is_empty()
    }

    /// `value`, at most `cap` while deformable bodies are in this world.
    fn capped_with_deformables(&self, value: f32, cap: f32) -> f32 {
        if self.deformables.is_empty() {
            value
        } else {
            value.min(cap)
        }
    }

    /// The body-force step limit `c √(Δx/|g|)` (none without gravity).
    pub(crate) fn body_force_step(&self, c: f32, gravity: Vector) -> Option<f32> {
        let g = gravity.length();
        (g > 0.0).then(|| c * (self.params.spacing / g).sqrt())
    }

    /// The chosen solver's [`PressureSolver::mean_tolerance`].
    fn mean_tolerance(&self) -> f64 {
        solver_for(self.params.solver).mean_tolerance(&self.params) as f64
    }

    /// One substep: the neighbour search, then the pressure solver's stages.
    fn substep(&mut self, gravity: Vector, dt: f32, rep: &mut StepReport) -> Result<()> {
        let mut times = StageTimes::default();
        // Table 3 t_neighbor: cull to the domain, sort by cell, neighbour lists
        timed(&mut times.neighbors, || self.find_neighbours(rep))?;
        self.start_at_rest(gravity);
        self.mark_cloth_start();
        let s = Substep {
            gravity,
            dt,
            bodies: self.body_views(),
        };
        if self.params.hydrostatic_walls {
            self.scratch.v_start.clone_from(&self.fluid.v);
        }
        solver_for(self.params.solver).substep(self, &s, &mut times, rep)?;
        if self.params.hydrostatic_walls && self.scratch.v_start.len() == self.fluid.len() {
            // each carrier's acceleration, averaged over the last ACCEL_WINDOW √(Δx/|g|) of
            // simulated time (weighted by substep length, so a very short substep, whose
            // acceleration is mostly the velocity constraint's correction, barely counts)
            let fl = &mut self.fluid;
            let tau = ACCEL_WINDOW * (self.params.spacing / gravity.length().max(1e-6)).sqrt();
            let alpha = (dt / tau).min(1.0);
            fl.accel.resize(fl.v.len(), Vector::ZERO);
            fl.accel
                .par_iter_mut()
                .zip(fl.v.par_iter().zip(self.scratch.v_start.par_iter()))
                .for_each(|(a, (v, v0))| {
                    *a += alpha * ((*v - *v0) / dt - *a);
                });
        }
        rep.stages.add(&times);
        rep.n_pairs = self.lists.pair_count();
        Ok(())
    }

    /// A NaN or infinite position or velocity anywhere is an error, never silently spread.
    pub(crate) fn check_finite(&self) -> Result<()> {
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

/// The predicted positions of the density constraint: `x = x0 + a Δt²`.
pub(crate) fn predict_positions(x: &mut [Vector], x0: &[Vector], accel: &[Vector], dt: f32) {
    x.par_iter_mut()
        .zip(x0.par_iter())
        .zip(accel.par_iter())
        .for_each(|((x, &x0), &a)| *x = x0 + a * (dt * dt));
}
