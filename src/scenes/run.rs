//! Running a scene: the fluid (and its rapier world) stepped for a duration, with emitters and
//! sinks, the scene's metric and the tracked bodies sampled after every step, into a
//! [`RunReport`].

use super::probe::{Comparison, Draft, Sample};
use super::Scene;
use crate::error::{FluidError, Result};
use crate::metrics::{StageTimes, StepReport};
use crate::world::SettleReport;
use serde::Serialize;
use std::time::Instant;

/// Summary of a whole run (the `--report` JSON).
#[derive(Debug, Clone, Serialize)]
pub struct RunReport {
    /// Scene name.
    pub scene: String,
    /// Fluid carriers at the end.
    pub n_fluid: usize,
    /// Solid carriers.
    pub n_solid: usize,
    /// Steps taken.
    pub steps: u64,
    /// Step length, s.
    pub dt: f64,
    /// Simulated seconds of this run (a resumed run counts from where it resumed).
    pub simulated_seconds: f64,
    /// Simulated time at the end of the run, s.
    #[serde(default)]
    pub end_time: f64,
    /// Wall-clock seconds.
    pub wall_seconds: f64,
    /// Wall seconds per simulated second of this run.
    pub wall_per_simulated_second: f64,
    /// What settling the water before the run did (the scene's `settle` field, its wall time
    /// not in `wall_seconds`), if this run started the scene (settled by it or just before
    /// it, by [`Scene::settle`]).
    pub settled: Option<SettleReport>,
    /// Seconds per stage, summed over the run.
    pub stage_seconds: StageTimes,
    /// Mean E (Eq. 29) over steps.
    pub mean_error: f64,
    /// Largest E over steps.
    pub max_error: f64,
    /// Mean PCG iterations per step.
    pub mean_pcg_iterations: f64,
    /// Mean over steps of the inner carriers' mean compression (SPH density), fraction.
    pub mean_compression: f64,
    /// Largest compression of any inner carrier in any step, fraction.
    pub max_compression: f64,
    /// Steps that ended beyond the density tolerances ([`StepReport::density_converged`]).
    pub steps_off_density: u64,
    /// Microseconds per fluid-particle step.
    pub us_per_particle_step: f64,
    /// Fluid carriers removed because they left the domain.
    pub removed_outside: u64,
    /// Fluid carriers added by emitters.
    pub emitted: u64,
    /// Fluid carriers removed by sinks.
    pub sunk: u64,
    /// E, PCG iterations and counts after every step.
    pub steps_log: Vec<StepLog>,
    /// The scene's metric over time.
    pub metric_name: String,
    /// What a sample's `value` is, with its unit (a plot's axis).
    #[serde(default)]
    pub metric_axis: String,
    /// Samples of the metric.
    pub metric: Vec<Sample>,
    /// The run against the scene's reference (Martin & Moyce's front, the still tank's floor
    /// force, Archimedes' drafts).
    pub comparison: Comparison,
    /// Tracked rapier bodies over time.
    pub bodies: Vec<BodyTrack>,
}

/// One step of a run, as the report logs it.
#[derive(Debug, Clone, Serialize)]
pub struct StepLog {
    /// Simulated time at the end of the step, s.
    pub t: f64,
    /// Incompressibility error E (Eq. 29).
    pub error: f64,
    /// PCG iterations of the step.
    pub pcg_iterations: u32,
    /// Fluid carriers.
    pub n_fluid: usize,
    /// Fluid substeps the step took.
    pub substeps: u32,
    /// Mean compression of the inner carriers, fraction.
    pub compression: f64,
}

/// One rapier body over a run.
#[derive(Debug, Clone, Serialize)]
pub struct BodyTrack {
    /// Its name in the scene.
    pub name: String,
    /// Samples after every step.
    pub samples: Vec<BodySample>,
}

/// A tracked body after one step.
#[derive(Debug, Clone, Serialize)]
pub struct BodySample {
    /// Simulated time, s.
    pub t: f64,
    /// Centre of mass, m.
    pub position: [f32; 3],
    /// Velocity of the centre of mass, m/s.
    pub velocity: [f32; 3],
    /// Angular velocity, rad/s.
    pub angvel: [f32; 3],
    /// Force of the fluid over the last step, N (Eq. 21).
    pub fluid_force: [f32; 3],
    /// Torque of the fluid about the centre of mass over the last step, N·m (Eq. 21).
    pub fluid_torque: [f32; 3],
}

impl Scene {
    /// Appends the tracked bodies' state to `tracks`.
    fn track(&self, tracks: &mut [BodyTrack]) {
        let Some(ph) = &self.physics else { return };
        let dt = self.dt.max(1e-12);
        for ((_, h), tr) in self.tracked.iter().zip(tracks.iter_mut()) {
            let Some(rb) = ph.bodies.get(*h) else {
                continue;
            };
            // dynamic bodies: the impulse handed to rapier; others (kinematic): their solids'
            let j = match self.world.rigids().iter().find(|r| r.handle == *h) {
                Some(r) => r.impulse.map(|v| v / dt as f64),
                None => {
                    let mut j = [0.0f64; 6];
                    for &c in rb.colliders() {
                        if let Some(s) = self.world.solid_of(c).and_then(|s| self.world.solid(s)) {
                            for k in 0..3 {
                                j[k] += s.force[k] as f64;
                                j[3 + k] += s.torque[k] as f64;
                            }
                        }
                    }
                    j
                }
            };
            let f = |k: usize| j[k] as f32;
            tr.samples.push(BodySample {
                t: self.world.time(),
                position: crate::math::arr(rb.center_of_mass()),
                velocity: crate::math::arr(rb.linvel()),
                angvel: crate::math::arr(rb.angvel()),
                fluid_force: [f(0), f(1), f(2)],
                fluid_torque: [f(3), f(4), f(5)],
            });
        }
    }

    /// Lets the water settle as the scene's `settle` field asks ([`FluidWorld::settle`] at the
    /// scene's step and gravity), once, before its first step; [`Self::run`] calls it. Returns
    /// what settling did, or `None` when the scene does not settle or has already stepped.
    ///
    /// [`FluidWorld::settle`]: crate::FluidWorld::settle
    pub fn settle(&mut self) -> Result<Option<&SettleReport>> {
        if let (Some(seconds), None, 0) = (self.spec.settle, &self.settled, self.world.steps) {
            self.settled = Some(self.world.settle(self.gravity, self.dt, seconds)?);
            return Ok(self.settled.as_ref());
        }
        Ok(None)
    }

    /// Runs for `seconds`, calling `each` after every step; returns the run summary. A scene
    /// with a `settle` field settles first ([`Self::settle`]; not counted in the run's time).
    pub fn run(
        &mut self,
        seconds: f64,
        mut each: impl FnMut(&Scene, &StepReport),
    ) -> Result<RunReport> {
        self.run_with(seconds, |s, r| {
            each(s, r);
            Ok(())
        })
    }

    /// Like [`Self::run`], stopping at the first error `each` returns (frame output).
    pub fn run_with(
        &mut self,
        seconds: f64,
        mut each: impl FnMut(&Scene, &StepReport) -> Result<()>,
    ) -> Result<RunReport> {
        let max = super::validate::MAX_STEPS;
        let steps = (seconds / self.dt as f64).round().max(1.0);
        if !(seconds.is_finite() && seconds > 0.0 && steps <= max) {
            return Err(FluidError::OutOfRange {
                name: "seconds",
                value: seconds,
                range: "> 0, at most 1e8 steps of the scene's dt per run",
            });
        }
        let steps = steps as u64;
        let first = self.world.steps == 0;
        self.settle()?;
        let start = Instant::now();
        let t0 = self.world.time();
        // floating bodies' drafts, averaged over the last quarter of the run
        let draft_from = steps - steps / 4;
        let mut drafts: Vec<Draft> = Vec::new();
        let mut draft_samples = 0usize;
        let mut stages = StageTimes::default();
        let (mut esum, mut emax, mut iters, mut removed) = (0.0, 0.0f64, 0u64, 0u64);
        let (mut csum, mut cmax, mut off) = (0.0, 0.0f64, 0u64);
        let mut metric = vec![self.sample()];
        let mut bodies: Vec<BodyTrack> = self
            .tracked
            .iter()
            .map(|(name, _)| BodyTrack {
                name: name.clone(),
                samples: Vec::new(),
            })
            .collect();
        self.track(&mut bodies);
        let mut particle_steps = 0.0f64;
        let (mut emitted, mut sunk) = (0u64, 0u64);
        // grown as the run goes: `seconds` is the caller's and may ask for more steps than
        // memory holds (the run then ends in an error, not an abort before the first step)
        let mut log = Vec::with_capacity(steps.min(1 << 16) as usize);
        for k in 0..steps {
            for e in self.emitters.iter_mut() {
                emitted += e.emit(&mut self.world, self.dt)?;
            }
            let rep = match self.physics.as_mut() {
                Some(ph) => self.world.step_physics_world(ph)?,
                None => self.world.step(self.gravity, self.dt)?,
            };
            for k in &self.sinks {
                sunk += k.drain(&mut self.world);
            }
            self.track(&mut bodies);
            stages.add(&rep.stages);
            esum += rep.error;
            emax = emax.max(rep.error);
            iters += rep.pcg_iterations as u64;
            removed += rep.removed_outside;
            csum += rep.compression_mean;
            cmax = cmax.max(rep.compression_max);
            off += (!rep.density_converged) as u64;
            particle_steps += rep.n_fluid as f64 * rep.substeps as f64;
            metric.push(self.sample());
            if k >= draft_from {
                let now = self.drafts_now();
                if drafts.is_empty() {
                    drafts = now;
                    draft_samples = 1;
                } else if now.len() == drafts.len() {
                    for (d, n) in drafts.iter_mut().zip(now) {
                        d.draft += n.draft;
                    }
                    draft_samples += 1;
                }
            }
            log.push(StepLog {
                t: rep.time,
                error: rep.error,
                pcg_iterations: rep.pcg_iterations,
                n_fluid: rep.n_fluid,
                substeps: rep.substeps,
                compression: rep.compression_mean,
            });
            each(self, &rep)?;
        }
        let wall = start.elapsed().as_secs_f64();
        for d in drafts.iter_mut() {
            d.draft /= draft_samples.max(1) as f64;
        }
        let comparison = self.compare(&metric, &drafts);
        let simulated = self.world.time() - t0;
        Ok(RunReport {
            scene: self.name.clone(),
            n_fluid: self.world.fluid().len(),
            n_solid: self.world.solid_carriers().len(),
            steps,
            dt: self.dt as f64,
            simulated_seconds: simulated,
            end_time: self.world.time(),
            wall_seconds: wall,
            wall_per_simulated_second: wall / simulated.max(1e-12),
            settled: self.settled.clone().filter(|_| first),
            stage_seconds: stages,
            mean_error: esum / steps as f64,
            max_error: emax,
            mean_pcg_iterations: iters as f64 / steps as f64,
            mean_compression: csum / steps as f64,
            max_compression: cmax,
            steps_off_density: off,
            us_per_particle_step: 1e6 * stages.total() / particle_steps.max(1.0),
            removed_outside: removed,
            emitted,
            sunk,
            steps_log: log,
            metric_name: self.metric_name().into(),
            metric_axis: self.metric_axis().into(),
            metric,
            comparison,
            bodies,
        })
    }
}
