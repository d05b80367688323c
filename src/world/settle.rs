//! Water left to settle before a run: the fluid stepped with every body held still, then its
//! velocities cleared, so the first frames start from the scheme's own rest arrangement.

use super::{FluidWorld, SolidKind};
use crate::error::{positive, FluidError, Result};
use crate::math::Vector;
use crate::solver::det_sum;

/// Most steps one [`FluidWorld::settle`] call takes.
pub(crate) const MAX_SETTLE_STEPS: u64 = 1_000_000;

/// Steps [`FluidWorld::settle`] takes for `seconds` at `dt` (a whole number within rounding:
/// 0.1 s at 1/60 s in f32 is 6, not 7; at least one).
pub(crate) fn settle_steps(seconds: f32, dt: f32) -> u64 {
    (seconds as f64 / dt as f64 - 1e-6).ceil().max(1.0) as u64
}

/// What [`FluidWorld::settle`] did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SettleReport {
    /// Steps taken.
    pub steps: u64,
    /// Fluid substeps over them.
    pub substeps: u64,
    /// Largest fluid speed when the settling ended, before the velocities were cleared, m/s.
    pub final_speed: f32,
    /// Kinetic energy the clearing removed, J.
    pub kinetic_energy_cleared: f64,
    /// Mean compression of the inner carriers at the end (as
    /// [`crate::StepReport::compression_mean`]).
    pub compression_mean: f64,
    /// Wall-clock seconds the settling took.
    pub wall_seconds: f64,
}

impl FluidWorld {
    /// Lets the water settle: steps the fluid for `seconds` of simulated time at `dt` under
    /// `gravity`, then sets every fluid velocity to zero and puts the clock back where it was.
    /// The pressure the water built up stays, so a run that follows starts from the
    /// arrangement and pressure the scheme holds at rest.
    ///
    /// A block cut from the lattice is not that arrangement: left to itself a 0.3 m deep still
    /// tank breathes (its centre of mass 0.4–0.5 mm up and back over 0.4 s, whichever
    /// pressure it starts from), and the fall back compresses it enough to make its 1/60 s
    /// frames split finer: 218 substeps in its first second started hydrostatic
    /// ([`crate::FluidParams::hydrostatic_start`]), 344 from zero pressure, 180 settled
    /// (docs/experiments.md, twenty-seventh session). About a second is enough for such a
    /// tank.
    ///
    /// Coupled rigid bodies and kinematic solids are held where they are while the water
    /// settles (asleep, at zero velocity: the water settles around them as around walls) and
    /// get their velocities back afterwards; rapier never steps. A deformable body, or a world
    /// modelling heat, is an error: settle before adding them.
    ///
    /// ```
    /// use staggered_fluid::prelude::*;
    /// let mut world = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
    /// world.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip).unwrap();
    /// world.add_block(Vector::ZERO, Vector::new(0.5, 0.25, 0.5), Vector::ZERO).unwrap();
    /// let g = Vector::new(0.0, -9.81, 0.0);
    /// let r = world.settle(g, 1.0 / 60.0, 0.1).unwrap();
    /// assert_eq!(r.steps, 6);
    /// assert_eq!(world.time(), 0.0);
    /// assert!(world.fluid().v.iter().all(|v| *v == Vector::ZERO));
    /// assert!(world.settle(g, 0.0, 0.1).is_err());
    /// ```
    pub fn settle(&mut self, gravity: Vector, dt: f32, seconds: f32) -> Result<SettleReport> {
        positive("dt", dt as f64)?;
        positive("seconds", seconds as f64)?;
        let steps = settle_steps(seconds, dt);
        if steps > MAX_SETTLE_STEPS {
            return Err(FluidError::TooMany {
                what: "settling steps (seconds / dt)",
                count: steps,
                limit: MAX_SETTLE_STEPS,
            });
        }
        if let Some(s) = self
            .solids
            .iter()
            .find(|s| !s.removed && s.kind == SolidKind::Deformable)
        {
            return Err(FluidError::Coupling(format!(
                "settle: solid `{}` is deformable, which settling cannot hold still (settle \
                 before adding deformable bodies)",
                s.name
            )));
        }
        if self.heat.is_some() {
            return Err(FluidError::Coupling(
                "settle: the world models heat, which settling would run on; settle before \
                 setting the fluid's heat"
                    .into(),
            ));
        }
        let start = std::time::Instant::now();
        let (time, count) = (self.time, self.steps);
        let held = self.hold_bodies();
        let mut substeps = 0u64;
        let mut last = None;
        let mut run = || -> Result<()> {
            for _ in 0..steps {
                let r = self.step(gravity, dt)?;
                substeps += r.substeps as u64;
                last = Some(r);
            }
            Ok(())
        };
        let outcome = run();
        self.release_bodies(held);
        outcome?;
        // (steps ≥ 1, so the last step's report is there)
        let last = last.unwrap_or_default();
        let v = &self.fluid.v;
        let kinetic_energy_cleared =
            self.mass as f64 * det_sum(v.len(), |i| 0.5 * v[i].length_squared() as f64);
        self.fluid.v.iter_mut().for_each(|v| *v = Vector::ZERO);
        self.time = time;
        self.steps = count;
        Ok(SettleReport {
            steps,
            substeps,
            final_speed: last.max_speed,
            kinetic_energy_cleared,
            compression_mean: last.compression_mean,
            wall_seconds: start.elapsed().as_secs_f64(),
        })
    }

    /// Holds every moving body still for settling: rigid bodies asleep (the fluid treats a
    /// sleeping body as fixed), rigid and kinematic solids at zero velocity; returns what
    /// [`Self::release_bodies`] restores.
    fn hold_bodies(&mut self) -> Held {
        let rigids = self
            .rigids
            .iter_mut()
            .map(|r| {
                let was = (r.sleeping, r.linvel, r.angvel);
                (r.sleeping, r.linvel, r.angvel) = (true, Vector::ZERO, Vector::ZERO);
                was
            })
            .collect();
        let mut solids = Vec::new();
        for k in 0..self.solids.len() {
            let s = &mut self.solids[k];
            if s.removed || !matches!(s.kind, SolidKind::Kinematic | SolidKind::Dynamic) {
                continue;
            }
            solids.push((k, s.linvel, s.angvel));
            (s.linvel, s.angvel) = (Vector::ZERO, Vector::ZERO);
            self.place_solid(k);
        }
        Held { rigids, solids }
    }

    /// Gives the bodies [`Self::hold_bodies`] held their sleep and velocities back.
    fn release_bodies(&mut self, held: Held) {
        for (r, (sleeping, linvel, angvel)) in self.rigids.iter_mut().zip(held.rigids) {
            (r.sleeping, r.linvel, r.angvel) = (sleeping, linvel, angvel);
        }
        for (k, linvel, angvel) in held.solids {
            (self.solids[k].linvel, self.solids[k].angvel) = (linvel, angvel);
            self.place_solid(k);
        }
    }
}

/// Bodies held still while water settles: each rigid's sleep flag and velocities, each
/// moving solid's velocities.
struct Held {
    rigids: Vec<(bool, Vector, Vector)>,
    solids: Vec<(usize, Vector, Vector)>,
}
