//! Stage: the density constraint (He 2012 Algorithm 2): iterations of density (Eq. 22) → EOS
//! pressure p^d ≥ 0, accumulated with the PCISPH stiffness → generalized pressure force
//! (Eq. 23) moving the predicted positions. Dynamic bodies move with the force of each
//! iteration too, so a body the fluid pushes gives way instead of the fluid alone taking up the
//! compression. Shao et al. 2014's PCISPH loop is the same loop with other settings
//! ([`DensityLoop`]) and the velocity–position correction inside it.

use super::{predict_positions, Substep};
use crate::math::Vector;
use crate::solver::regions::Regions;
use crate::solver::{density, det_sum, Impulses};
use crate::world::FluidWorld;
use rayon::prelude::*;

/// Settings of one run of the density loop.
pub(crate) struct DensityLoop {
    /// EOS stiffness `k` of `p^d += k (ρ − ρ̄)`, Pa per kg/m³.
    pub stiffness: f32,
    /// Iterations always run.
    pub min_iterations: u32,
    /// Iteration cap.
    pub max_iterations: u32,
    /// Mean compression `mean(max(ρ − ρ̄, 0))/ρ̄` (fraction) below which the loop stops once
    /// `min_iterations` ran.
    pub tolerance: f32,
    /// Largest compression of one carrier (fraction) the loop may stop at.
    pub max_tolerance: f32,
    /// Whether the compression is taken over the inner carriers (not marked free surface at
    /// the last step) instead of all.
    pub inner_only: bool,
    /// Whether the loop also stops, once past `min_iterations`, when an iteration removed less
    /// than a tenth of the compression (compression the fluid cannot relieve, such as a sealed
    /// box's, only raises the pressure with more iterations).
    pub stop_on_stall: bool,
    /// Whether each connected body of water's lowest p^d is held at zero ([`zero_lowest`]).
    pub anchor: bool,
    /// Displacement (m) the loop's pressure force should not give a carrier in one substep
    /// (the pressure of a carrier it would move further is scaled down, so the velocity a
    /// correction adds stays about this over Δt); `None`: unbounded, as printed.
    pub max_shift: Option<f32>,
    /// Solid carriers push as Akinci et al. 2012 boundary particles (Shao 2014 Eq. 7) instead
    /// of along their normals (Eq. 23).
    pub akinci: bool,
    /// An evaluation that may end the loop also computes Eq. 25's asymmetry, so that the
    /// staggered creation and the surface marking reuse it.
    pub asymmetry: bool,
    /// Pressure memory ([`crate::FluidParams::density_memory`]): p^d starts from each carrier's
    /// remembered pressure, which then moves this fraction toward the final p^d (0: p^d starts
    /// from zero, as printed).
    pub memory: f32,
    /// Free-surface carriers' p^d extrapolated from the inner carriers
    /// ([`crate::FluidParams::surface_extrapolation`], [`super::surface::extrapolate_surface`]).
    pub surface_extrapolation: bool,
    /// Wall carriers take the fluid's pressure carried hydrostatically to them
    /// ([`crate::FluidParams::hydrostatic_walls`]).
    pub hydrostatic_walls: bool,
    /// Walls push as their geometry says ([`crate::FluidParams::wall_support`],
    /// [`density::WallSupport`]; not with `akinci` or `hydrostatic_walls`).
    pub wall_support: bool,
    /// Share `α` of the spring the predicted positions follow: after the first iteration
    /// they take `ā_k = a(p_k) − (1 − α) (a(p_{k−1}) − ā_{k−1})` at the moved positions
    /// ([`density::Spring`]; impulses likewise): the pressure's increment in full, the last
    /// pressure's change of force with the moved positions relaxed (1: all of it, as printed).
    /// Relaxing the whole force instead (`ā ← ā + α (a − ā)`) held the density error's decay
    /// to `√(1 − α)` an iteration: at two substeps of a 1/60 s frame the five balls' loop
    /// stalled at 0.08–0.11 % mean compression (0.05–0.06 % split).
    pub position_relaxation: f32,
    /// Positions only ([`crate::FluidParams::drift_iterations`]): p^d starts from zero, moves
    /// the positions and nothing else (no velocity, no body, no memory), and carriers beside
    /// a deformable body take no part.
    pub position_only: bool,
    /// Free-surface carriers compare their density with that of a flat rest surface's carrier
    /// as exposed as they are ([`FluidWorld::surface_rest_densities`]) instead of ρ̄.
    pub surface_rest: bool,
    /// The pressure force scaled per carrier so that a linear pressure gives its own gradient
    /// ([`crate::FluidParams::pressure_scale`], computed by [`density::density_and_count`]).
    pub pressure_scale: bool,
}

/// What a run of the density loop did.
pub(crate) struct DensityOutcome {
    /// Iterations that applied a pressure force.
    pub iterations: u32,
    /// Mean compression (fraction) at the last evaluation.
    pub compression: f64,
    /// Largest compression of one carrier (fraction) at the last evaluation.
    pub largest: f64,
    /// Whether `rho`, `count` and `asym` in the scratch hold the final positions' values.
    pub fresh: bool,
    /// Whether the iterations made it worse: the last evaluation's mean compression above
    /// the first's and above the tolerance (the iteration diverges at this substep length).
    pub diverged: bool,
}

impl FluidWorld {
    /// The density loop's PCISPH stiffness for substep `s`, that of a step of `max(Δt, τ)` (τ
    /// the recent substeps' length, `FluidWorld::recent_step`): a 1 µs step after 5 ms ones
    /// then moves a carrier no further than those would, and the velocity it adds stays δx/τ
    /// (with Δt alone the compression stored over the long steps came out over the 1 µs: 285
    /// m/s on 78174e6 under the staggered solver, 19 J added under PCISPH).
    pub(crate) fn loop_stiffness(&self, s: &Substep) -> f32 {
        density::stiffness(
            &ctx!(self, &s.bodies),
            self.grad_sq,
            s.dt.max(self.recent_step),
        )
    }
}

/// A position correction run after every iteration's prediction (Shao's Eq. 12 inside the
/// PCISPH loop). With one, the final positions are predicted again from the final force: the
/// correction served the density prediction only.
pub(crate) type Correction<'a> = &'a dyn Fn(&mut FluidWorld, &Substep);

impl FluidWorld {
    /// Runs the density loop on the predicted positions and velocities.
    pub(crate) fn density_constraint(
        &mut self,
        s: &Substep,
        cfg: &DensityLoop,
        correction: Option<Correction>,
    ) -> DensityOutcome {
        let (n, dt) = (self.fluid.len(), s.dt);
        let sc = &mut self.scratch;
        sc.rho.resize(n, 0.0);
        sc.count.resize(n, 0);
        sc.accel.resize(n, Vector::ZERO);
        let rest = self.params.rest_density;
        let x0 = self.fluid.x.clone();
        // the bodies' carriers before the iterations move them (the drift pass moves none)
        let solid_x0 = (!cfg.position_only && self.rigids.iter().any(|r| r.moving()))
            .then(|| self.solid.x.clone());
        let fl = &mut self.fluid;
        if cfg.memory > 0.0 && fl.p_memory.len() == n && !cfg.position_only {
            fl.p_density.clone_from(&fl.p_memory);
        } else {
            fl.p_density.par_iter_mut().for_each(|p| *p = 0.0);
        }
        let mut imp = Impulses::new();
        let mut relaxed = Relaxed::default();
        let (mut done, mut compression_now, mut largest, mut fresh) = (0, 0.0, 0.0, false);
        let mut first = f64::INFINITY;
        let mut before = (f64::INFINITY, f64::INFINITY);
        self.scratch.asym.resize(n, 0.0);
        let mut g = self.loop_inputs(s, cfg);
        for it in 0..cfg.max_iterations {
            let sc = &mut self.scratch;
            let last = it >= cfg.min_iterations;
            density::density_and_count(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &mut sc.rho,
                &mut sc.count,
                (last && cfg.asymmetry).then_some(&mut sc.asym[..]),
                (it == 0 && cfg.pressure_scale).then(|| {
                    g.scale.resize(n, 1.0);
                    (&mut g.scale[..], &self.fluid.surface[..])
                }),
                density::WallHead::new(s.gravity, &self.fluid.accel, rest, &g.wet).as_ref(),
            );
            let rho = &sc.rho;
            let surface = &self.fluid.surface;
            let inner = |i: usize| !cfg.inner_only || !surface.get(i).copied().unwrap_or(false);
            let (mean, max) = compression(rho, inner, rest);
            (compression_now, largest) = (mean, max);
            if it == 0 {
                first = mean;
            }
            let met = mean <= cfg.tolerance as f64 && max <= cfg.max_tolerance as f64;
            let stalled = cfg.stop_on_stall && mean > 0.9 * before.0 && max > 0.9 * before.1;
            if last && (met || (it > cfg.min_iterations && stalled)) {
                fresh = cfg.asymmetry;
                break;
            }
            before = (mean, max);
            done += 1;
            // the last iteration's impulses are replaced (freed before the new ones are
            // built) or, relaxed, blended into them
            let last_imp = std::mem::take(&mut imp);
            if cfg.position_relaxation < 1.0 {
                relaxed.imp = last_imp;
            }
            // after the first iteration, only the spring is relaxed ([`density::Spring`])
            let split = cfg.position_relaxation < 1.0 && relaxed.accel.len() == n;
            if split {
                relaxed.p_old.clone_from(&self.fluid.p_density);
                relaxed.next.resize(n, Vector::ZERO);
            }
            let lag = 1.0 - cfg.position_relaxation;
            self.update_pressure(cfg, it > 0, &g);
            imp = self.pressure_pass(s, cfg, &g, split.then_some((&mut relaxed, lag)));
            let ahead = if split {
                std::mem::swap(&mut relaxed.accel, &mut relaxed.next);
                let kept = std::mem::take(&mut relaxed.imp);
                imp = Impulses::combine(vec![(1.0, imp), (lag, kept)]);
                &relaxed.accel
            } else if cfg.position_relaxation < 1.0 {
                // the first iteration's positions follow its whole force
                relaxed.accel.clone_from(&self.scratch.accel);
                &relaxed.accel
            } else {
                &self.scratch.accel
            };
            predict_positions(&mut self.fluid.x, &x0, ahead, dt);
            if let Some(c) = correction {
                c(self, s);
            }
            if let Some(sx0) = &solid_x0 {
                self.shift_rigids(&imp, sx0, dt);
            }
        }
        if done > 0 && correction.is_some() {
            predict_positions(&mut self.fluid.x, &x0, &self.scratch.accel, dt);
        }
        if cfg.position_only {
            return DensityOutcome {
                iterations: done,
                compression: compression_now,
                largest,
                fresh: false,
                diverged: false,
            };
        }
        if done > 0 {
            let accel = if relaxed.accel.len() == n {
                &relaxed.accel
            } else {
                &self.scratch.accel
            };
            self.fluid
                .v
                .par_iter_mut()
                .zip(accel.par_iter())
                .for_each(|(v, &a)| *v += a * dt);
        }
        // with `wall_support` the pushes' couples were made against the bodies' carriers
        // before the iterations moved them: their arms stay there (against the moved ones a
        // 10 kg/m³ ball spun up to 62 rad/s in one substep, each iteration's turn adding to
        // the next one's torque)
        match (&solid_x0, &g.support) {
            (Some(sx0), Some(_)) => self.absorb_shared_from(imp, sx0),
            _ => self.absorb_shared(imp),
        }
        self.scratch.wet = g.wet;
        if cfg.memory > 0.0 {
            remember(&mut self.fluid, cfg.memory);
        }
        DensityOutcome {
            iterations: done,
            compression: compression_now,
            largest,
            fresh,
            diverged: compression_now > first && compression_now > cfg.tolerance as f64,
        }
    }
}

impl FluidWorld {
    /// One iteration's pressure force (Eq. 23) into `scratch.accel` and, with `spring`, the
    /// positions' relaxed accelerations into its `next` ([`density::Spring`]); with
    /// `max_shift`, a second pass when the first would move a carrier too far. Returns the
    /// impulses.
    fn pressure_pass(
        &mut self,
        s: &Substep,
        cfg: &DensityLoop,
        g: &LoopInputs,
        mut spring: Option<(&mut Relaxed, f32)>,
    ) -> Impulses {
        let (dt, rest) = (s.dt, self.params.rest_density);
        let sc = &mut self.scratch;
        let mut capped = cfg.max_shift.is_none();
        loop {
            let imp = density::pressure_accel(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &self.fluid.p_density,
                &sc.rho,
                &mut sc.accel,
                dt,
                if cfg.akinci {
                    density::WallPush::Akinci
                } else if let Some(h) =
                    density::WallHead::new(s.gravity, &self.fluid.accel, rest, &g.wet)
                {
                    density::WallPush::Hydrostatic(h)
                } else {
                    density::WallPush::Normal(s.gravity * rest)
                },
                g.support.as_ref(),
                &g.scale,
                spring.as_mut().map(|(r, lag)| density::Spring {
                    p: &r.p_old,
                    lag: *lag,
                    ahead: &r.accel,
                    next: &mut r.next,
                }),
            );
            let shift = cfg.max_shift.unwrap_or(f32::INFINITY);
            if capped || !cap_pressures(&mut self.fluid.p_density, &sc.accel, shift / (dt * dt)) {
                return imp;
            }
            capped = true;
        }
    }
}

/// What the density loop's iterations read besides the positions, set up once a run.
struct LoopInputs {
    /// Carriers beside a deformable body (the drift pass leaves them out; empty otherwise).
    beside_soft: Vec<bool>,
    /// Each carrier's connected body of water (`anchor`; empty otherwise).
    region: Vec<u32>,
    /// Each solid carrier's wetness (`hydrostatic_walls`; empty otherwise).
    wet: Vec<f32>,
    /// Each carrier's EOS rest density (`surface_rest`; empty: ρ̄).
    rest_of: Vec<f32>,
    /// The walls' push as the geometry says (`wall_support`).
    support: Option<density::WallSupport>,
    /// Each carrier's pressure scale (`pressure_scale`, from the first evaluation; empty
    /// otherwise).
    scale: Vec<f32>,
}

impl FluidWorld {
    /// The density loop's [`LoopInputs`] at the predicted positions.
    fn loop_inputs(&self, s: &Substep, cfg: &DensityLoop) -> LoopInputs {
        let n = self.fluid.len();
        let beside_soft = if cfg.position_only {
            self.beside_deformables()
        } else {
            Vec::new()
        };
        let region = if cfg.anchor {
            regions(&self.lists, n)
        } else {
            Vec::new()
        };
        let wet = self.wet_walls(s, cfg.hydrostatic_walls);
        let mut rest_of = if cfg.surface_rest {
            self.surface_rest_densities(&wet)
        } else {
            Vec::new()
        };
        if !cfg.position_only {
            self.raise_by_kept(&mut rest_of, s.dt);
        }
        let support = (cfg.wall_support && !cfg.akinci && !cfg.hydrostatic_walls).then(|| {
            density::WallSupport::new(
                &ctx!(self, &s.bodies),
                &self.fluid.x,
                &self.fluid.surface,
                s.gravity.normalize_or_zero(),
                &self.shapes(),
            )
        });
        LoopInputs {
            beside_soft,
            region,
            wet,
            rest_of,
            support,
            scale: Vec::new(),
        }
    }
}

impl FluidWorld {
    /// Which wall carriers stand for water at the current positions
    /// ([`density::wetness`]) when `hydrostatic` walls are on; empty otherwise.
    pub(super) fn wet_walls(&self, s: &Substep, hydrostatic: bool) -> Vec<f32> {
        if !hydrostatic {
            return Vec::new();
        }
        let up = (-s.gravity).try_normalize().unwrap_or(Vector::Y);
        density::wetness(
            &ctx!(self, &s.bodies),
            &self.fluid.x,
            up,
            self.params.spacing,
        )
    }
}

/// The prediction of [`DensityLoop::position_relaxation`]: the accelerations `ā` the positions
/// follow and, between iterations, their impulses, the last iteration's pressure and the
/// buffer of the next `ā` ([`density::Spring`]). The memory's pressure on the carriers'
/// disorder is a spring whose fixed-point iteration diverges beyond `μ = 1`
/// (`step/he2012.rs`); the surface extrapolation keeps reading the force itself.
#[derive(Default)]
struct Relaxed {
    accel: Vec<Vector>,
    imp: Impulses,
    p_old: Vec<f32>,
    next: Vec<Vector>,
}

/// Algorithm 2's EOS step `p^d ← max(p^d + k (ρ − ρ̄_i), 0)`, ρ̄_i the carrier's entry in
/// `rest_of` or, when that is empty, `rest`; carriers marked in `skip` (when it is not empty)
/// keep no pressure.
fn eos(p: &mut [f32], rho: &[f32], k: f32, rest: f32, skip: &[bool], rest_of: &[f32]) {
    p.par_iter_mut()
        .zip(rho.par_iter())
        .enumerate()
        .for_each(|(i, (p, &r))| {
            *p = if skip.get(i) == Some(&true) {
                0.0
            } else {
                (*p + k * (r - rest_of.get(i).copied().unwrap_or(rest))).max(0.0)
            }
        });
}

/// Moves each carrier's remembered pressure the fraction `g` toward its final p^d.
fn remember(fl: &mut crate::particles::FluidCarriers, g: f32) {
    fl.p_memory.resize(fl.len(), 0.0);
    fl.p_memory
        .par_iter_mut()
        .zip(fl.p_density.par_iter())
        .for_each(|(m, &p)| *m += g * (p - *m));
}

impl FluidWorld {
    /// One iteration's pressure: the EOS step, each region's lowest at zero (`anchor`), the
    /// free surface continued (after the first iteration, whose accelerations are this
    /// substep's pressure gradients).
    fn update_pressure(&mut self, cfg: &DensityLoop, after_first: bool, g: &LoopInputs) {
        let rest = self.params.rest_density;
        let p = &mut self.fluid.p_density;
        eos(
            p,
            &self.scratch.rho,
            cfg.stiffness,
            rest,
            &g.beside_soft,
            &g.rest_of,
        );
        if cfg.anchor {
            zero_lowest(p, &g.region);
        }
        if cfg.surface_extrapolation && after_first {
            super::surface::extrapolate_surface(
                p,
                &self.fluid.surface,
                &self.fluid.x,
                &self.scratch.accel,
                &self.lists,
                &self.kernel,
                rest,
            );
        }
    }

    /// Per fluid carrier, the rest density the EOS compares its SPH density with
    /// ([`DensityLoop::surface_rest`]); empty when the last step marked no surface. A
    /// free-surface carrier's sum lacks its air side (a flat rest surface's carrier reads
    /// `(1 − m) ρ̄`, m ≈ 0.15), so against ρ̄ it has no pressure until packed some 15 % closer
    /// than the bulk, and the surface layer packs. A surface carrier with an inner fluid
    /// neighbour is compared instead with a flat rest surface's carrier as exposed as it is,
    /// `ρ̄ (1 − m min(Asy_i / a, 1))`, `Asy_i` its asymmetry at the predicted positions over
    /// its fluid neighbours and its solid ones weighted by volume and wetness (`wet`, empty:
    /// all wet), so a wall beside it completes its side as water would, and `a` the flat
    /// surface carrier's (m and a from the kernel on the rest lattice,
    /// [`crate::kernel::CubicSpline::surface_deficit_and_asymmetry`]). On rest lattices the
    /// estimate is never below an uncompressed carrier's true density (an edge carrier 0.78
    /// against 0.72 ρ̄, a corner 0.72 against 0.61).
    fn surface_rest_densities(&self, wet: &[f32]) -> Vec<f32> {
        let (n, rest) = (self.fluid.len(), self.params.rest_density);
        let surface = &self.fluid.surface;
        if surface.len() != n || !surface.contains(&true) || self.lists.offsets.len() != n + 1 {
            return Vec::new();
        }
        let (m, a) = self
            .kernel
            .surface_deficit_and_asymmetry(self.params.spacing);
        let (x, lists, k, solid) = (&self.fluid.x, &self.lists, &self.kernel, &self.solid);
        (0..n)
            .into_par_iter()
            .map(|i| {
                if !surface[i] {
                    return rest;
                }
                let (mut moment, mut wsum, mut inner) = (Vector::ZERO, k.w(0.0), false);
                for &j in &lists.indices[lists.fluid_range(i)] {
                    let d = x[j as usize] - x[i];
                    let w = k.w(d.length());
                    moment += d * w;
                    wsum += w;
                    inner |= w > 0.0 && !surface[j as usize];
                }
                for &j in &lists.indices[lists.solid_range(i)] {
                    let s = j as usize - n;
                    let d = solid.x[s] - x[i];
                    let w = k.w(d.length()) * solid.volume[s] * wet.get(s).copied().unwrap_or(1.0);
                    moment += d * w;
                    wsum += w;
                }
                if inner {
                    rest * (1.0 - m * (moment.length() / (wsum * a)).min(1.0))
                } else {
                    rest
                }
            })
            .collect()
    }

    /// Per fluid carrier, whether a deformable body's carrier is among its neighbours (empty
    /// when the world has no deformable body).
    fn beside_deformables(&self) -> Vec<bool> {
        let soft: Vec<bool> = self
            .solids
            .iter()
            .map(|b| b.kind == crate::world::SolidKind::Deformable)
            .collect();
        if !soft.contains(&true) {
            return Vec::new();
        }
        let (nf, lists, body) = (self.fluid.len(), &self.lists, &self.solid.body);
        (0..nf)
            .into_par_iter()
            .map(|i| {
                lists.indices[lists.solid_range(i)]
                    .iter()
                    .any(|&j| soft[body[j as usize - nf] as usize])
            })
            .collect()
    }
}

/// The connected bodies of water: for every carrier the smallest index of the carriers the
/// fluid neighbour lists link it to.
fn regions(lists: &crate::neighbors::NeighborLists, n: usize) -> Vec<u32> {
    let n = n.min(lists.offsets.len().saturating_sub(1));
    let r = Regions::new(n);
    (0..n).into_par_iter().for_each(|i| {
        for &j in &lists.indices[lists.fluid_range(i)] {
            if (j as usize) < n && j as usize > i {
                r.union(i as u32, j);
            }
        }
    });
    r.roots()
}

/// Lowers every region's pressures so that its lowest is zero. Pressure is defined up to a
/// constant where no free surface fixes it: in a sealed box a compression the walls do not let
/// relax (0.1–0.2 % as carriers settle into the wall layers of a full 0.2 m box) would
/// otherwise raise it uniformly each iteration and, through the memory, without bound (the
/// lid's force grew by 9 N a step, to 5 kN after 1 s). The convention is the sealed box's "p = 0
/// at its least loaded carrier"; an open body's lowest pressure is already 0 at its surface.
fn zero_lowest(p: &mut [f32], region: &[u32]) {
    if region.len() != p.len() {
        return;
    }
    let mut low = vec![f32::INFINITY; p.len()];
    for (&r, &v) in region.iter().zip(p.iter()) {
        low[r as usize] = low[r as usize].min(v);
    }
    for (v, &r) in p.iter_mut().zip(region) {
        let l = low[r as usize];
        if l > 0.0 && l.is_finite() {
            *v -= l;
        }
    }
}

/// Scales down the pressure of every carrier whose acceleration exceeds `cap` by the excess
/// (a correction moves no carrier by much more than the shift the cap stands for in one
/// substep; pressures rather than accelerations, so every pair stays equal and opposite and
/// momentum is kept). Returns whether any was scaled.
fn cap_pressures(p: &mut [f32], accel: &[Vector], cap: f32) -> bool {
    p.par_iter_mut()
        .zip(accel.par_iter())
        .map(|(p, a)| {
            let m = a.length();
            if m > cap {
                *p *= cap / m;
                1u32
            } else {
                0
            }
        })
        .sum::<u32>()
        > 0
}

/// The compression `max(ρ − ρ̄, 0)/ρ̄` of the carriers `inner` selects: mean and largest
/// (fractions).
pub(crate) fn compression(
    rho: &[f32],
    inner: impl Fn(usize) -> bool + Sync,
    rest: f32,
) -> (f64, f64) {
    let n = rho.len();
    let count = (0..n).into_par_iter().filter(|&i| inner(i)).count();
    if count == 0 {
        return (0.0, 0.0);
    }
    let c = |i: usize| {
        if inner(i) {
            (rho[i] - rest).max(0.0) as f64
        } else {
            0.0
        }
    };
    let mean = det_sum(n, c) / count as f64 / rest as f64;
    let max = (0..n).into_par_iter().map(c).reduce(|| 0.0, f64::max) / rest as f64;
    (mean, max)
}
