//! The staggered solver of He et al. 2012 (Algorithm 1 after the neighbour search): forces and
//! prediction, the density constraint (Algorithm 2), the staggered particles, the free
//! surface, the velocity constraint (assembly and solve) and the remap with its wall
//! conditions, then XSPH smoothing and the penetration correction.

use super::density::{compression, DensityLoop};
use super::{timed, PressureSolver, Substep};
use crate::error::Result;
use crate::metrics::{StageTimes, StepReport};
use crate::params::FluidParams;
use crate::solver::pcg::PcgStats;
use crate::solver::{density, det_sum};
use crate::world::FluidWorld;
use rayon::prelude::*;
use std::time::Instant;

/// He et al. 2012, *Staggered Meshless Solid-Fluid Coupling*.
pub(crate) struct He2012;

impl PressureSolver for He2012 {
    fn max_cfl(&self, p: &FluidParams) -> f32 {
        p.max_cfl
    }

    /// The substep at which the density loop's spring ([`SPRING`]) has `μ` =
    /// [`FluidParams::max_loop_spring`] (at most 2 with deformable bodies,
    /// [`FluidWorld::max_loop_spring`]) at the bulk's remembered pressure ([`bulk_memory`], with the pressure memory on).
    fn max_substep(&self, w: &FluidWorld, _gravity: crate::math::Vector) -> Option<f32> {
        Some((w.max_loop_spring() / spring(w, bulk_memory(w)?, 1.0)).sqrt())
    }

    fn substep(
        &self,
        w: &mut FluidWorld,
        s: &Substep,
        times: &mut StageTimes,
        rep: &mut StepReport,
    ) -> Result<()> {
        // the drift the last substep left, moved out of the positions (Hu & Adams 2007)
        let t = Instant::now();
        if let Some(cfg) = drift_loop(w, s) {
            rep.drift_iterations += w.density_constraint(s, &cfg, None).iterations;
        }
        w.keep_placement_compression(s);
        // Alg. 1 l.2–4: body and viscous forces (Eq. 24), prediction, density constraint (Alg. 2)
        w.predict(s);
        let cfg = density_loop(w, s);
        let d = w.density_constraint(s, &cfg, None);
        times.density += t.elapsed().as_secs_f64();
        rep.density_iterations += d.iterations;
        w.substep_diverged = d.diverged;
        // issue 19: the water's pressure on faces resting on a wall with no water between
        rep.sealed_faces += w.press_sealed_faces(s) as u64;
        // Eqs. 7–9, 22: staggered particles
        timed(&mut times.staggered, || w.create_staggered(s, d.fresh));
        // Eq. 25: free surface and isolated regions
        timed(&mut times.surface, || w.mark_surface(s));
        w.release_density_buffers();
        // Eqs. 10–13, 26–27: the velocity constraint
        timed(&mut times.assembly, || w.assemble_velocity_constraint(s));
        let stats = timed(&mut times.solve, || w.solve_velocity_constraint(s));
        // Eq. 19 and the wall conditions, smoothing, penetration, bookkeeping
        timed(&mut times.other, || {
            w.remap(s);
            w.smooth(s);
            w.finish_rigids(s.dt);
            w.correct_penetration(s, rep);
            keep_fields(w);
            w.check_finite()?;
            report(w, &stats, rep);
            Ok(())
        })
    }
}

/// The displacement, in spacings, beyond which the density constraint's pressure force is
/// scaled down for a carrier in one substep (with the pressure memory on). Long steps (a still tank at 8× its
/// step with the CFL and body-force limits scaled too) and a ball settling on the floor
/// squeeze carriers far beyond what one substep should undo (127 % compression); removed at
/// once it became a jet: the tank gained 521 J (7× its energy) and lost 265 carriers, the five
/// balls at 2× 17 J in one step. With the cap: +9 J and none lost, and none. A cap on the
/// pressure rise instead (5 % or 20 % of compression a substep) also held the compression under
/// a falling wedge, which then decelerated faster than Wagner's bound; this one leaves it.
const MAX_SHIFT: f32 = 0.25;

/// `μ = SPRING p Δt² / (ρ̄ Δx²)`: the squared frequency (times Δt²) of a carrier's oscillation
/// about the middle of its neighbours under a uniform pressure `p`. The symmetric pressure force
/// of a uniform pressure pushes a carrier back toward that middle with a stiffness that grows
/// with the pressure; the density loop's prediction `x = x₀ + Δt² a(p, x)` is a fixed-point
/// iteration on that spring, which multiplies its error by `−μ` an iteration. Measured: in the
/// still tank (bulk pressure 3.6 kPa, [`bulk_memory`]) the mean compression grew 1.6–1.8× an
/// iteration at 5.6 ms substeps and went up as often as down at 4.2 ms (μ ≈ 1).
const SPRING: f32 = 6.1;

/// The floor of [`position_relaxation`], `1.5/(1 + μ_max)` with `μ_max` the substep limit's
/// spring ([`FluidParams::max_loop_spring`]; 0.3 at the default 4: at `μ = 4` the smallest
/// relaxation still halves the spring's error an iteration). Before only the spring was
/// relaxed ([`crate::solver::density::Spring`]), a floor below 0.5 let the pressure
/// accumulate faster than the positions followed it: a heavy LSM cube
/// resting on a tank's floor (with μ from the largest remembered pressure, 8 kPa in the water
/// squeezed under it: μ = 3.8 at 5.6 ms, α = 0.32) built its compression over a frame, and the
/// memory wound up to 200 kPa in the re-split frame before the step failed (with μ from the
/// bulk's 99th percentile it rests).
fn min_position_relaxation(w: &FluidWorld) -> f32 {
    1.5 / (1.0 + w.max_loop_spring())
}

/// Share `α` of the density loop's spring the predicted positions follow
/// ([`DensityLoop::position_relaxation`]): `1.5 / (1 + μ)` with `μ` ([`SPRING`]) at the
/// bulk's remembered pressure, so that the spring's error shrinks by at least half an
/// iteration (`|1 − α (1 + μ)| ≤ ½`), within [`min_position_relaxation`] and 1. Short
/// substeps (an impact's) keep the paper's full step (α = 1; at α = 0.5 throughout, the
/// falling wedge braked faster than Wagner's bound).
/// Without it the still tank at rapier's 1/60 s diverged whenever the step controller tried
/// three substeps (5.6 ms: every twelfth frame, kinetic energy to 0.035 J); with it, it holds
/// three. Only with the pressure memory (without it the loop starts from zero pressure each
/// substep).
fn position_relaxation(w: &FluidWorld, dt: f32) -> f32 {
    let Some(top) = bulk_memory(w) else {
        return 1.0;
    };
    (1.5 / (1.0 + spring(w, top, dt))).clamp(min_position_relaxation(w), 1.0)
}

/// The spring's `μ` ([`SPRING`]) at pressure `p` (Pa) and substep `dt`.
fn spring(w: &FluidWorld, p: f32, dt: f32) -> f32 {
    let q = &w.params;
    SPRING * p * dt * dt / (q.rest_density * q.spacing * q.spacing)
}

/// The remembered pressure of the bulk — its 99th percentile, so that a few carriers squeezed
/// under a resting body do not set it — with the pressure memory on and some remembered.
fn bulk_memory(w: &FluidWorld) -> Option<f32> {
    if w.params.density_memory <= 0.0 || w.fluid.p_memory.is_empty() {
        return None;
    }
    let mut p = w.fluid.p_memory.clone();
    let k = (p.len() - 1) * 99 / 100;
    let (_, top, _) = p.select_nth_unstable_by(k, f32::total_cmp);
    let top = *top;
    (top > 0.0).then_some(top)
}

/// Algorithm 2's settings: the paper's fixed iterations (at least `density_iterations`, more
/// up to `max_density_iterations` while the inner carriers miss `density_mean_tolerance` or
/// `density_max_tolerance`),
/// the PCISPH stiffness times `density_relaxation`, pressure pushing along wall normals.
///
/// The stiffness is PCISPH's for a step of `max(Δt, τ)`, τ the recent substeps' length
/// ([`FluidWorld::step`]): one iteration removes a full neighbourhood's density error over
/// the recent step length, so the velocity it adds is bounded by what those steps would add,
/// and a short step after long ones does not turn the compression they left into a jet.
fn density_loop(w: &FluidWorld, s: &Substep) -> DensityLoop {
    relaxed_loop(w, s, position_relaxation(w, s.dt))
}

/// [`density_loop`] with the positions following the share `alpha` of each iteration's force.
fn relaxed_loop(w: &FluidWorld, s: &Substep, alpha: f32) -> DensityLoop {
    let p = &w.params;
    DensityLoop {
        stiffness: p.density_relaxation * w.loop_stiffness(s),
        min_iterations: p.density_iterations,
        max_iterations: p.max_density_iterations.max(p.density_iterations),
        tolerance: p.density_mean_tolerance,
        max_tolerance: p.density_max_tolerance,
        inner_only: true,
        stop_on_stall: true,
        anchor: p.density_memory > 0.0,
        max_shift: (p.density_memory > 0.0).then_some(MAX_SHIFT * p.spacing),
        akinci: false,
        asymmetry: true,
        memory: p.density_memory,
        surface_extrapolation: p.surface_extrapolation,
        hydrostatic_walls: p.hydrostatic_walls,
        wall_support: p.wall_support,
        position_relaxation: alpha,
        position_only: false,
        surface_rest: p.surface_rest_density,
        pressure_scale: w.pressure_scale(),
    }
}

/// Cap of the position-only pass that relieves a placement's compression (it runs once).
const PLACEMENT_ITERATIONS: u32 = 32;

/// The position-only drift correction ([`FluidParams::drift_iterations`]): Algorithm 2's
/// loop on the substep's starting positions, from zero pressure, with the stiffness of the
/// substep itself (positions move by `a Δt²`, so the gain is the same at any length);
/// `None` when it is off. The first substep after water was placed ([`FluidWorld::placed`])
/// runs it whatever the setting, with up to [`PLACEMENT_ITERATIONS`]: the compression a
/// placement leaves (water packed against a body's face by `add_block_around`) was never a
/// velocity, and the velocity loop would kick it out over the substep — over a world's very
/// first step of 1 µs at 3 m/s.
fn drift_loop(w: &FluidWorld, s: &Substep) -> Option<DensityLoop> {
    let p = &w.params;
    let iterations = if w.placed {
        p.drift_iterations.max(PLACEMENT_ITERATIONS)
    } else {
        p.drift_iterations
    };
    (iterations > 0).then(|| {
        let k = density::stiffness(&ctx!(w, &s.bodies), w.grad_sq, s.dt);
        let base = relaxed_loop(w, s, 1.0);
        // a placement's compression, however small, is relieved until the iterations stall
        let (tolerance, max_tolerance) = if w.placed {
            (0.0, 0.0)
        } else {
            (base.tolerance, base.max_tolerance)
        };
        DensityLoop {
            stiffness: p.density_relaxation * k,
            min_iterations: 0,
            max_iterations: iterations,
            tolerance,
            max_tolerance,
            memory: 0.0,
            asymmetry: false,
            surface_extrapolation: false,
            position_only: true,
            // a fictitious pressure that only moves positions apart: no gradient to keep
            pressure_scale: false,
            ..base
        }
    })
}

/// The fields a user reads after the step: p^v, ρ, N and the surface flags.
fn keep_fields(w: &mut FluidWorld) {
    let sc = &w.scratch;
    let fl = &mut w.fluid;
    fl.p_velocity
        .par_iter_mut()
        .zip(sc.p.par_iter())
        .for_each(|(d, &s)| *d = s as f32);
    fl.density.clone_from(&sc.rho);
    fl.neighbors.clone_from(&sc.count);
    fl.surface.clone_from(&sc.surface);
}

/// The velocity constraint's figures: E (Eq. 29), iterations, unknowns and the mean density
/// deviation of the inner carriers.
fn report(w: &mut FluidWorld, stats: &PcgStats, rep: &mut StepReport) {
    let n = w.fluid.len();
    let sc = &w.scratch;
    let sys = &w.system;
    let rest = w.params.rest_density;
    let n_unknown = sys.unknown.iter().filter(|&&u| u).count();
    let dev = det_sum(n, |i| {
        if sys.unknown[i] {
            ((sc.rho[i] - rest).abs() / rest) as f64
        } else {
            0.0
        }
    });
    rep.pcg_iterations += stats.iterations;
    rep.error = rep.error.max(stats.error);
    rep.initial_error = rep.initial_error.max(stats.initial_error);
    rep.converged &= stats.converged;
    rep.n_surface = n - n_unknown;
    rep.n_unknown = n_unknown;
    rep.density_deviation = if n_unknown > 0 {
        dev / n_unknown as f64
    } else {
        0.0
    };
    let (mean, max) = compression(&sc.rho, |i| sys.unknown[i], rest);
    w.substep_compression = mean;
    rep.compression_mean = rep.compression_mean.max(mean);
    rep.compression_max = rep.compression_max.max(max);
    rep.density_converged &= mean <= w.params.density_mean_tolerance as f64
        && max <= w.params.density_max_tolerance as f64;
}
