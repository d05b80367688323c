//! Failure guards of a step (issue 20): fluid lost outside the domain, a speed bound, a
//! mechanical-energy gain, the substep cap. A tripped guard is an error
//! ([`FluidError::StepFailed`]) or, with [`OnFailure::Warn`], a line in
//! [`StepReport::warnings`]; a run that returns Ok is a run whose water is still there.

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::metrics::StepReport;
use crate::params::OnFailure;
use crate::solver::det_sum;
use crate::world::{FluidWorld, SolidKind};

/// Mechanical energy per unit mass of a carrier at `x` moving at `v` under gravity `g`.
#[inline]
pub(crate) fn carrier_energy(x: Vector, v: Vector, g: Vector) -> f64 {
    0.5 * v.length_squared() as f64 - g.dot(x) as f64
}

/// Kinetic and potential energy (under `g`), J, of points of mass `m` each at `x` moving at
/// `v` (deterministic sums).
fn point_energies(m: f32, x: &[Vector], v: &[Vector], g: Vector) -> (f64, f64) {
    let m = m as f64;
    (
        m * det_sum(x.len(), |i| 0.5 * v[i].length_squared() as f64),
        -m * det_sum(x.len(), |i| g.dot(x[i]) as f64),
    )
}

/// How long the kinetic energy of the fluid and the deformable bodies counts toward the energy
/// guard's scale, s.
const ENERGY_MEMORY: f64 = 0.25;

/// What a step cut to [`super::MAX_SUBSTEPS`] says.
pub(crate) fn cap_message(asked: f64, dt: f32) -> String {
    format!(
        "the step needs {asked:.0} substeps, over the cap of {}: dt {dt} s is too long for this \
         speed, spacing, gravity and viscosity (take shorter steps)",
        super::MAX_SUBSTEPS
    )
}

/// The step's energy account at its start.
pub(crate) struct EnergyStart {
    /// Mechanical energy of fluid and dynamic bodies, J.
    pub total: f64,
    /// The scale a gain is measured against: `KE + M |g| Δx`, J.
    pub scale: f64,
}

impl FluidWorld {
    /// Mechanical energy (under `g`) of the fluid, the dynamic bodies and the deformable
    /// bodies, J, and the kinetic (and elastic) energy of the fluid and the deformable bodies.
    fn mechanical_energy(&self, g: Vector) -> (f64, f64) {
        let (kinetic, potential) = point_energies(self.mass, &self.fluid.x, &self.fluid.v, g);
        let bodies: f64 = self
            .rigids
            .iter()
            .map(|r| {
                let mass = r.mprops.mass() as f64;
                let frame = r.rotation * r.mprops.principal_inertia_local_frame;
                let w = frame.inverse() * r.angvel;
                let i = r.mprops.principal_inertia();
                let rot = 0.5 * (i.x * w.x * w.x + i.y * w.y * w.y + i.z * w.z * w.z) as f64;
                mass * carrier_energy(r.com, r.linvel, g) + rot
            })
            .sum();
        let (soft, soft_kinetic) = self.deformable_energy(g);
        (kinetic + potential + bodies + soft, kinetic + soft_kinetic)
    }

    /// Mechanical energy (kinetic, potential under `g`, shape matching's elastic) of the
    /// deformable bodies, J, and its kinetic and elastic part: they are inside the account,
    /// so the work between them and the water is not excused as a driven wall's.
    fn deformable_energy(&self, g: Vector) -> (f64, f64) {
        let mut out = (0.0, 0.0);
        for b in &self.deformables {
            let (kinetic, potential) = point_energies(b.mass, &b.x, &b.v, g);
            out.0 += kinetic + potential + b.elastic_energy;
            out.1 += kinetic + b.elastic_energy;
        }
        out
    }

    /// The energy account at the start of a step of `dt` under gravity `g`.
    ///
    /// The scale a gain is measured against is `KE + M |g| Δx` with `KE` the largest kinetic
    /// energy of the last [`ENERGY_MEMORY`] seconds (decaying): a jet stopped by a plate
    /// stores its kinetic energy in compression for a few steps and gives part of it back,
    /// which is not an eruption (6.7 × the scale of that step, 0.3 × the recent one).
    pub(crate) fn energy_start(&mut self, g: Vector, dt: f32) -> EnergyStart {
        self.removed_energy = 0.0;
        self.added_energy = 0.0;
        self.step_gravity = g;
        let (total, kinetic) = self.mechanical_energy(g);
        let decay = (-(dt as f64) / ENERGY_MEMORY).exp();
        self.recent_kinetic = kinetic.max(self.recent_kinetic * decay);
        let weight = self.mass as f64 * self.fluid.len() as f64 * g.length() as f64;
        // (and at least the fluid moving at 1 mm/s: still water without gravity has a scale
        // of zero, and round-off alone "erupted")
        let floor = 0.5 * self.mass as f64 * self.fluid.len() as f64 * 1e-6;
        EnergyStart {
            total,
            scale: (self.recent_kinetic + weight * self.params.spacing as f64).max(floor),
        }
    }

    /// Work done on the fluid by kinematic solids over a step of `dt`, J (their carriers'
    /// force from the fluid is in `solid.f`).
    fn kinematic_work(&self, dt: f32) -> f64 {
        let driven = |k: SolidKind| k == SolidKind::Kinematic;
        if !self.solids.iter().any(|s| driven(s.kind)) {
            return 0.0;
        }
        (0..self.solid.len())
            .filter(|&i| driven(self.solids[self.solid.body[i] as usize].kind))
            .map(|i| -(self.solid.f[i].dot(self.solid.u[i]) as f64) * dt as f64)
            .sum()
    }

    /// Checks the step's guards; fills `rep.energy_gain` and, under [`OnFailure::Warn`],
    /// `rep.warnings`. `capped` is the substep count the limits asked for when the cap cut it.
    pub(crate) fn check_guards(
        &mut self,
        start: &EnergyStart,
        capped: Option<f64>,
        rep: &mut StepReport,
    ) -> Result<()> {
        let p = &self.params;
        let (end, _) = self.mechanical_energy(self.step_gravity);
        let gain = end + self.removed_energy
            - self.added_energy
            - start.total
            - self.kinematic_work(rep.dt as f32);
        rep.energy_gain = gain;
        let mut failures = Vec::new();
        let held = self.fluid.len() as u64 + self.removed_total;
        let lost = self.removed_total as f64 / held.max(1) as f64;
        if rep.removed_outside > 0 && lost > p.max_lost_fraction as f64 {
            failures.push(format!(
                "{} fluid carriers left the domain this step, {:.2} % of the fluid over the run \
                 (max_lost_fraction {:.2} %): the water erupted or flowed out of the domain",
                rep.removed_outside,
                100.0 * lost,
                100.0 * p.max_lost_fraction
            ));
        }
        if rep.max_speed > p.max_speed {
            let fl = &self.fluid;
            let at =
                fl.v.iter()
                    .position(|v| v.length() >= rep.max_speed)
                    .map(|i| fl.x[i])
                    .unwrap_or(Vector::ZERO);
            failures.push(format!(
                "a fluid carrier moves at {:.1} m/s (max_speed {} m/s), at [{:.3}, {:.3}, {:.3}]",
                rep.max_speed, p.max_speed, at.x, at.y, at.z
            ));
        }
        if gain > p.max_energy_gain as f64 * start.scale {
            failures.push(format!(
                "the step added {gain:.3e} J of mechanical energy, {:.1} × (KE + M|g|Δx) = {:.3e} J \
                 (max_energy_gain {}): an eruption, usually a step too long or too sudden",
                gain / start.scale,
                start.scale,
                p.max_energy_gain
            ));
        }
        if let Some(asked) = capped {
            failures.push(cap_message(asked, rep.dt as f32));
        }
        if failures.is_empty() {
            return Ok(());
        }
        match p.on_failure {
            OnFailure::Warn => {
                rep.warnings.extend(failures);
                Ok(())
            }
            OnFailure::Error => Err(FluidError::StepFailed {
                step: rep.step,
                time: rep.time,
                what: failures.join("; "),
            }),
        }
    }
}
