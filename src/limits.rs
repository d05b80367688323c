//! The sizes the crate accepts and what a failing step does (issue 20): every count that sizes an allocation or a loop is
//! computed in `f64` and checked against these before anything is allocated. Re-exported from
//! [`crate::params`].

use crate::error::{FluidError, Result};
use serde::{Deserialize, Serialize};

/// What a step that trips one of the failure guards ([`crate::FluidParams::max_lost_fraction`],
/// [`crate::FluidParams::max_speed`], [`crate::FluidParams::max_energy_gain`], the substep cap) does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum OnFailure {
    /// Return [`crate::FluidError::StepFailed`] saying what happened (the world keeps the
    /// state the step reached, so it can be inspected or written out).
    #[default]
    Error,
    /// Finish the step and list the failure in [`crate::StepReport::warnings`] (a game that
    /// prefers water that misbehaves to water that stops).
    Warn,
}

/// Upper bound on fluid plus solid carriers one world accepts.
pub const MAX_PARTICLES: u64 = 50_000_000;
/// Upper bound on neighbour-grid cells.
pub const MAX_CELLS: u64 = 200_000_000;
/// Upper bound on any iteration count parameter (density, PCISPH and PCG iterations): more
/// would make one substep run for minutes without changing the result.
pub const MAX_ITERATIONS: u32 = 10_000;
/// Upper bound on any length a scene or a shape gives, m: beyond it `f32` positions cannot
/// resolve a centimetre spacing.
pub const MAX_LENGTH: f32 = 1.0e6;
/// The lightest dynamic body the coupling accepts under free slip, partial slip or the
/// boundary layer, as a fraction of the fluid's rest density (10 kg/m³ for water). Measured at
/// rapier's 1/60 s, Δx 2.5 cm, a ball of radius 2Δx and a cube of side 4Δx released under
/// water (`tests/extreme_bodies.rs`, `examples/probes/light_probe.rs`). Every stage shares a
/// body's impulse with the water beside it (`world/lumps.rs`): balls and cubes of 10 kg/m³
/// float calmly (a free-slip cube spins at most 7.7 rad/s, 6.9 when released after a second
/// held still). With the velocity constraint's reaction taken by the body alone a 10 kg/m³
/// free-slip cube spun up to 23–30 rad/s in its first frames, and the bound was 50 kg/m³.
/// Lighter cubes float jumping (5 and 3 kg/m³: 17–32 mm clear of the water, 0.26–0.40 m/s a
/// frame over the last 0.5 s). Lighter bodies are refused at coupling with this bound in the
/// message.
pub const MIN_BODY_DENSITY_RATIO: f32 = 0.01;
/// The same under no slip (10 kg/m³ for water), where the water beside a body follows its
/// whole motion and Eq. 26's exchange is shared with the body by mass (`κ = M/(M + m_c)`):
/// balls and cubes of 10 kg/m³ float calmly (spin under 3 rad/s; 8 before the velocity
/// constraint's reaction was shared with the water beside a body).
pub const MIN_BODY_DENSITY_RATIO_NO_SLIP: f32 = 0.01;
/// Upper bound on a speed given as input (emitters, blocks, bodies), m/s.
pub const MAX_SPEED: f32 = 1.0e3;

/// A count computed in `f64` (never wrapping) as an integer for [`crate::FluidError::TooMany`]:
/// saturates at `u64::MAX`, which the error prints as "more than 1.8e19".
pub(crate) fn count_u64(n: f64) -> u64 {
    if n.is_nan() {
        u64::MAX
    } else {
        n.max(0.0).min(u64::MAX as f64) as u64
    }
}

/// Checks a count computed in `f64` against `limit` before anything is allocated.
pub(crate) fn check_count(what: &'static str, n: f64, limit: u64) -> Result<u64> {
    let count = count_u64(n);
    if n.is_nan() || count > limit {
        Err(FluidError::TooMany { what, count, limit })
    } else {
        Ok(count)
    }
}
