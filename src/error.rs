//! The crate's error type: every user-triggerable failure is a value, never a panic.

use thiserror::Error;

/// Everything that can go wrong when building or stepping a [`crate::FluidWorld`].
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FluidError {
    /// A physical parameter that must be strictly positive and finite was not.
    #[error("parameter `{name}` must be finite and > 0, got {}", show_value(*value))]
    NonPositive {
        /// Parameter name as it appears in [`crate::FluidParams`] or the call.
        name: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A parameter was outside its documented range.
    #[error("parameter `{name}` = {} is outside its valid range {range}", show_value(*value))]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// Human-readable valid range.
        range: &'static str,
    },
    /// A position, velocity or pose contained NaN or infinity.
    #[error("non-finite value in {what}")]
    NonFinite {
        /// What contained the value (e.g. "fluid particle 12 position").
        what: String,
    },
    /// The world holds no fluid carrier, so there is nothing to step.
    #[error("the fluid is empty: add a block or particles before stepping")]
    EmptyFluid,
    /// Every fluid carrier has left the domain (or been removed): the water is gone.
    #[error(
        "all the fluid has left the domain ({removed} carriers removed outside it): the run \
         erupted or drained (check dt, gravity, viscosity and sinks)"
    )]
    FluidLost {
        /// Carriers removed outside the domain over the run.
        removed: u64,
    },
    /// A step tripped a failure guard ([`crate::FluidParams::on_failure`]): fluid lost, a
    /// speed or energy bound, or the substep cap. The world holds the state the step reached.
    #[error("step {step} (t = {time:.4} s) failed: {what}")]
    StepFailed {
        /// Index of the step (1-based, as [`crate::StepReport::step`]).
        step: u64,
        /// Simulated time at its end, s.
        time: f64,
        /// What happened, where, and which parameter bounds it.
        what: String,
    },
    /// A fluid block request produced no particle (box smaller than one spacing).
    #[error("fluid block {mins:?}..{maxs:?} holds no particle at spacing {spacing}")]
    EmptyBlock {
        /// Lower corner.
        mins: [f32; 3],
        /// Upper corner.
        maxs: [f32; 3],
        /// Particle spacing.
        spacing: f32,
    },
    /// Fluid carriers were placed inside a solid.
    #[error("{count} fluid particle(s) lie inside solid `{solid}` (first at {first:?})")]
    FluidOverlapsSolid {
        /// Name of the solid.
        solid: String,
        /// Number of fluid particles inside it.
        count: usize,
        /// Position of the first one.
        first: [f32; 3],
    },
    /// A particle or solid lies outside the simulation domain.
    #[error("{what} lies outside the simulation domain {mins:?}..{maxs:?}")]
    OutsideDomain {
        /// What was outside.
        what: String,
        /// Domain lower corner.
        mins: [f32; 3],
        /// Domain upper corner.
        maxs: [f32; 3],
    },
    /// A request would create more particles or grid cells than the crate accepts.
    #[error("{what}: {} exceeds the limit of {limit}", show_count(*count))]
    TooMany {
        /// What was counted.
        what: &'static str,
        /// Requested count.
        count: u64,
        /// Accepted maximum.
        limit: u64,
    },
    /// [`FluidError::TooMany`] for one solid, named.
    #[error("{solid}: {what}: {} exceeds the limit of {limit}", show_count(*count))]
    TooManyIn {
        /// The solid (e.g. `collider 3`, or a scene body's name).
        solid: String,
        /// What was counted.
        what: &'static str,
        /// Requested count.
        count: u64,
        /// Accepted maximum.
        limit: u64,
    },
    /// A collider shape that cannot be sampled into solid carriers.
    #[error("unsupported shape `{shape}`: {why}")]
    UnsupportedShape {
        /// The shape's type name.
        shape: String,
        /// Why it cannot be used.
        why: String,
    },
    /// A shape whose size is zero, negative or non-finite.
    #[error("degenerate shape `{shape}`: {why}")]
    DegenerateShape {
        /// The shape's type name.
        shape: String,
        /// What is degenerate about it.
        why: String,
    },
    /// The simulation produced a non-finite value (a bug or an unstable setting).
    #[error("simulation diverged at step {step}: {what}")]
    Diverged {
        /// Step index at which it happened.
        step: u64,
        /// What became non-finite.
        what: String,
    },
    /// Parameter overrides that are not a JSON object of known `FluidParams` fields.
    #[error("bad parameter overrides: {0}")]
    BadParams(String),
    /// A rapier handle that does not name a live collider or body, or a body that cannot be
    /// coupled as it is.
    #[error("rapier coupling: {0}")]
    Coupling(String),
    /// An unknown built-in scene name.
    #[error("unknown scene `{0}` (known: {1})")]
    UnknownScene(String, String),
    /// A scene file that does not parse, or holds an inconsistent value. `line` is 1-based
    /// (0 when the scene was built from code, not text).
    #[error("{}", scene_message(file, *line, *column, field, message))]
    Scene {
        /// The file (or the scene's name).
        file: String,
        /// Line of the offending value.
        line: usize,
        /// Column of the offending value.
        column: usize,
        /// Path of the field, e.g. `bodies[1].colliders[0].shape.radius`.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// Input/output failure (reports, frames).
    #[error("i/o error on {path}: {message}")]
    Io {
        /// The path involved.
        path: String,
        /// The underlying error message.
        message: String,
    },
}

/// `file:line:column: field `x`: message`; no position for a scene built from code (line 0),
/// no field for a syntax error between fields.
fn scene_message(file: &str, line: usize, column: usize, field: &str, message: &str) -> String {
    let at = if line == 0 {
        format!("scene {file}: ")
    } else {
        format!("{file}:{line}:{column}: ")
    };
    let field = if field.is_empty() {
        String::new()
    } else {
        format!("field `{field}`: ")
    };
    format!("{at}{field}{message}")
}

/// A count as the errors print it: a saturated count (`u64::MAX`, from a size too large to
/// count) as "more than 1.8e19".
fn show_count(n: u64) -> String {
    if n == u64::MAX {
        "more than 1.8e19".into()
    } else {
        n.to_string()
    }
}

/// A value as the errors print it: very large or small magnitudes in scientific notation.
fn show_value(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// Shorthand result type.
pub type Result<T, E = FluidError> = std::result::Result<T, E>;

/// Checks that `value` is finite and strictly positive.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(FluidError::NonPositive { name, value })
    }
}
