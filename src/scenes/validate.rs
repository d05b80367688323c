//! Checks of a scene description that its types cannot express: positive sizes and densities,
//! finite vectors, ordered box corners, valid parameters, one of density or mass per collider.

use super::spec::{BodyKind, ProbeSpec, SceneFile, ShapeSpec};
use crate::emitter::OutletSpec;
use crate::error::FluidError;
use crate::math::Vector;
use crate::params::{MAX_LENGTH, MAX_SPEED};
use crate::world::{settle_steps, MAX_SETTLE_STEPS};

/// Upper bound on a scene's gravity, m/s².
pub const MAX_GRAVITY: f32 = 1.0e3;

/// Upper bound on the steps of one scene run (`seconds / dt`).
pub const MAX_STEPS: f64 = 1.0e8;

pub(crate) fn v3(a: [f32; 3]) -> Vector {
    Vector::new(a[0], a[1], a[2])
}

/// An error tied to a field of the scene (its path), before it is located in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldError {
    /// Path of the field, e.g. `bodies[1].colliders[0].shape.radius`.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

pub(crate) fn field_err(field: impl Into<String>, message: impl Into<String>) -> FieldError {
    FieldError {
        field: field.into(),
        message: message.into(),
    }
}

fn check_positive(field: String, v: f32) -> std::result::Result<(), FieldError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(field_err(field, format!("must be finite and > 0, got {v}")))
    }
}

fn check_finite(field: String, v: &[f32]) -> std::result::Result<(), FieldError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(field_err(field, format!("must be finite, got {v:?}")))
    }
}

/// A length: finite, > 0 and at most [`MAX_LENGTH`].
fn check_length(field: String, v: f32) -> std::result::Result<(), FieldError> {
    check_positive(field.clone(), v)?;
    if v > MAX_LENGTH {
        return Err(field_err(
            field,
            format!("{v:e} m exceeds the largest length the crate handles, {MAX_LENGTH:e} m"),
        ));
    }
    Ok(())
}

/// A point: finite, every coordinate within ±[`MAX_LENGTH`].
fn check_position(field: String, v: &[f32]) -> std::result::Result<(), FieldError> {
    check_finite(field.clone(), v)?;
    if v.iter().any(|x| x.abs() > MAX_LENGTH) {
        return Err(field_err(
            field,
            format!(
                "[{}] lies beyond ±{MAX_LENGTH:e} m, where f32 positions lose the spacing",
                v.iter()
                    .map(|x| format!("{x:e}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    Ok(())
}

/// A velocity (m/s, or rad/s): finite, magnitude at most [`MAX_SPEED`].
fn check_speed(field: String, v: &[f32]) -> std::result::Result<(), FieldError> {
    check_finite(field.clone(), v)?;
    let m = v.iter().map(|x| (*x as f64).powi(2)).sum::<f64>().sqrt();
    if m > MAX_SPEED as f64 {
        return Err(field_err(
            field,
            format!("magnitude {m:.3e} exceeds the largest accepted, {MAX_SPEED:e} (m/s, rad/s)"),
        ));
    }
    Ok(())
}

/// A body's `position`, `rotation`, `linvel` and `angvel` fields under `f`.
fn check_placement(
    f: &str,
    position: [f32; 3],
    rotation: [f32; 3],
    linvel: [f32; 3],
    angvel: [f32; 3],
) -> std::result::Result<(), FieldError> {
    check_position(format!("{f}.position"), &position)?;
    check_finite(format!("{f}.rotation"), &rotation)?;
    check_speed(format!("{f}.linvel"), &linvel)?;
    check_speed(format!("{f}.angvel"), &angvel)
}

fn check_box(field: &str, min: [f32; 3], max: [f32; 3]) -> std::result::Result<(), FieldError> {
    check_position(format!("{field}.min"), &min)?;
    check_position(format!("{field}.max"), &max)?;
    if (0..3).any(|k| max[k] <= min[k]) {
        return Err(field_err(
            format!("{field}.max"),
            format!("must exceed min {min:?} on every axis, got {max:?}"),
        ));
    }
    Ok(())
}

impl ShapeSpec {
    fn validate(&self, f: &str) -> std::result::Result<(), FieldError> {
        match self {
            ShapeSpec::Ball { radius } => check_length(format!("{f}.radius"), *radius)?,
            ShapeSpec::Cuboid { half_extents } => {
                for (k, h) in half_extents.iter().enumerate() {
                    check_length(format!("{f}.half_extents[{k}]"), *h)?;
                }
            }
            ShapeSpec::Cylinder {
                half_height,
                radius,
            }
            | ShapeSpec::Capsule {
                half_height,
                radius,
            } => {
                check_length(format!("{f}.half_height"), *half_height)?;
                check_length(format!("{f}.radius"), *radius)?;
            }
            ShapeSpec::ConvexHull { points } => {
                for (k, p) in points.iter().enumerate() {
                    check_position(format!("{f}.points[{k}]"), p)?;
                }
            }
            ShapeSpec::Ellipsoid {
                semi_axes,
                segments,
                rings,
            } => {
                for (k, h) in semi_axes.iter().enumerate() {
                    check_length(format!("{f}.semi_axes[{k}]"), *h)?;
                }
                if !(3..=256).contains(segments) {
                    return Err(field_err(format!("{f}.segments"), "must be 3..=256"));
                }
                if !(2..=256).contains(rings) {
                    return Err(field_err(format!("{f}.rings"), "must be 2..=256"));
                }
            }
            ShapeSpec::TriMesh { vertices, indices } => {
                if vertices.len() > 1 << 20 || indices.len() > 1 << 20 {
                    return Err(field_err(
                        format!("{f}.indices"),
                        "at most 1 048 576 vertices and triangles",
                    ));
                }
                for (k, p) in vertices.iter().enumerate() {
                    check_position(format!("{f}.vertices[{k}]"), p)?;
                }
                if let Some(k) = indices
                    .iter()
                    .position(|t| t.iter().any(|&i| i as usize >= vertices.len()))
                {
                    return Err(field_err(
                        format!("{f}.indices[{k}]"),
                        "names a vertex that is not there",
                    ));
                }
            }
            ShapeSpec::Compound { parts } => {
                if parts.is_empty() || parts.len() > 256 {
                    return Err(field_err(format!("{f}.parts"), "must hold 1..=256 parts"));
                }
                for (k, p) in parts.iter().enumerate() {
                    let fp = format!("{f}.parts[{k}]");
                    check_position(format!("{fp}.offset"), &p.offset)?;
                    if matches!(p.shape, ShapeSpec::Compound { .. }) {
                        return Err(field_err(
                            format!("{fp}.shape"),
                            "a compound's parts cannot be compounds",
                        ));
                    }
                    p.shape.validate(&format!("{fp}.shape"))?;
                }
            }
        }
        let b = self.builder().map_err(|m| field_err(f, m))?;
        // a hull of coplanar points builds, but has no volume (and a body made of it no mass)
        let mass = b.shape.mass_properties(1.0).mass();
        if !(mass.is_finite() && mass > 0.0) {
            return Err(field_err(
                f,
                "the points span no volume (coplanar or too few)",
            ));
        }
        Ok(())
    }
}

impl SceneFile {
    /// The `settle` field: a positive duration of at most [`MAX_SETTLE_STEPS`] steps, in a
    /// scene [`crate::FluidWorld::settle`] can hold still (no deformable bodies, cloths or
    /// heat).
    fn validate_settle(&self, settle: f32) -> std::result::Result<(), FieldError> {
        check_positive("settle".into(), settle)?;
        let steps = settle_steps(settle, self.dt);
        if steps > MAX_SETTLE_STEPS {
            return Err(field_err(
                "settle",
                format!(
                    "settle / dt = {steps} steps exceeds the limit of {MAX_SETTLE_STEPS} \
                     settling steps"
                ),
            ));
        }
        let held = if !self.deformables.is_empty() {
            Some("deformable bodies")
        } else if !self.cloths.is_empty() {
            Some("cloths")
        } else if self.heat.is_some() || self.walls.iter().any(|w| w.heat.is_some()) {
            Some("heat")
        } else {
            None
        };
        match held {
            Some(what) => Err(field_err(
                "settle",
                format!("settling cannot hold {what} still; remove `settle` or the {what}"),
            )),
            None => Ok(()),
        }
    }

    /// Checks values a type cannot: positive sizes and densities, finite vectors, ordered box
    /// corners, valid fluid parameters, one of density or mass per collider, some fluid.
    pub fn validate(&self) -> std::result::Result<(), FieldError> {
        check_positive("dt".into(), self.dt)?;
        check_positive("seconds".into(), self.seconds)?;
        let steps = (self.seconds as f64 / self.dt as f64).round();
        if steps > MAX_STEPS {
            return Err(field_err(
                "seconds",
                format!(
                    "seconds / dt = {steps:.3e} steps exceeds the limit of {MAX_STEPS:e} per run"
                ),
            ));
        }
        if let Some(settle) = self.settle {
            self.validate_settle(settle)?;
        }
        check_finite("gravity".into(), &self.gravity)?;
        if v3(self.gravity).length() > MAX_GRAVITY {
            return Err(field_err(
                "gravity",
                format!(
                    "magnitude {:.3e} m/s² exceeds the largest accepted, {MAX_GRAVITY:e} m/s² \
                     (about 100 g)",
                    v3(self.gravity).length()
                ),
            ));
        }
        self.params.validate().map_err(|e| {
            let name = match &e {
                FluidError::NonPositive { name, .. } | FluidError::OutOfRange { name, .. } => {
                    format!("params.{name}")
                }
                _ => "params".into(),
            };
            field_err(name, e.to_string())
        })?;
        for (k, t) in self.tanks.iter().enumerate() {
            check_box(&format!("tanks[{k}]"), t.min, t.max)?;
        }
        for (k, w) in self.walls.iter().enumerate() {
            check_box(&format!("walls[{k}]"), w.min, w.max)?;
        }
        for (k, b) in self.fluid.iter().enumerate() {
            check_box(&format!("fluid[{k}]"), b.min, b.max)?;
            check_speed(format!("fluid[{k}].velocity"), &b.velocity)?;
        }
        for (k, s) in self.sinks.iter().enumerate() {
            check_box(&format!("sinks[{k}]"), s.min, s.max)?;
        }
        for (k, e) in self.emitters.iter().enumerate() {
            let f = format!("emitters[{k}]");
            check_position(format!("{f}.center"), &e.center)?;
            check_speed(format!("{f}.velocity"), &e.velocity)?;
            if v3(e.velocity).length() <= 0.0 {
                return Err(field_err(format!("{f}.velocity"), "must not be zero"));
            }
            match &e.outlet {
                OutletSpec::Disc { radius } => check_length(format!("{f}.outlet.radius"), *radius)?,
                OutletSpec::Rectangle { half_extents } => {
                    for (i, h) in half_extents.iter().enumerate() {
                        check_length(format!("{f}.outlet.half_extents[{i}]"), *h)?;
                    }
                }
            }
            if !(e.start.is_finite() && e.start >= 0.0) {
                return Err(field_err(format!("{f}.start"), "must be finite and ≥ 0"));
            }
            if let Some(stop) = e.stop {
                if !(stop.is_finite() && stop > e.start) {
                    return Err(field_err(
                        format!("{f}.stop"),
                        "must be finite and after start",
                    ));
                }
            }
        }
        if self.fluid.is_empty() && self.emitters.is_empty() {
            return Err(field_err(
                "fluid",
                "the scene has no fluid: give a `fluid` block or an `emitters` entry",
            ));
        }
        for (k, b) in self.bodies.iter().enumerate() {
            let f = format!("bodies[{k}]");
            check_placement(&f, b.position, b.rotation, b.linvel, b.angvel)?;
            if b.colliders.is_empty() {
                return Err(field_err(
                    format!("{f}.colliders"),
                    "a body needs a collider",
                ));
            }
            for (c, col) in b.colliders.iter().enumerate() {
                let fc = format!("{f}.colliders[{c}]");
                col.shape.validate(&format!("{fc}.shape"))?;
                check_position(format!("{fc}.offset"), &col.offset)?;
                match (col.density, col.mass) {
                    (Some(_), Some(_)) => {
                        return Err(field_err(
                            format!("{fc}.mass"),
                            "give either density or mass, not both",
                        ))
                    }
                    (Some(d), None) => check_positive(format!("{fc}.density"), d)?,
                    (None, Some(m)) => check_positive(format!("{fc}.mass"), m)?,
                    (None, None) if b.kind == BodyKind::Dynamic => {
                        return Err(field_err(
                            format!("{fc}.density"),
                            "a dynamic body's collider needs a density or a mass",
                        ))
                    }
                    (None, None) => {}
                }
                if !(col.friction.is_finite() && col.friction >= 0.0) {
                    return Err(field_err(
                        format!("{fc}.friction"),
                        "must be finite and ≥ 0",
                    ));
                }
                if !(col.restitution.is_finite() && (0.0..=1.0).contains(&col.restitution)) {
                    return Err(field_err(format!("{fc}.restitution"), "must be in [0, 1]"));
                }
            }
        }
        for (k, d) in self.deformables.iter().enumerate() {
            let f = format!("deformables[{k}]");
            check_placement(&f, d.position, d.rotation, d.linvel, d.angvel)?;
            d.shape.validate(&format!("{f}.shape"))?;
            if let Some(y) = d.pin_below {
                check_finite(format!("{f}.pin_below"), &[y])?;
            }
        }
        for (k, c) in self.cloths.iter().enumerate() {
            let f = format!("cloths[{k}]");
            check_placement(&f, c.position, c.rotation, [0.0; 3], [0.0; 3])?;
            for (j, side) in c.size.iter().enumerate() {
                check_positive(format!("{f}.size[{j}]"), *side)?;
            }
        }
        match self.probe {
            ProbeSpec::Bodies => {}
            ProbeSpec::DamBreak { a } => check_positive("probe.a".into(), a)?,
            ProbeSpec::Hydrostatic { height } => {
                check_positive("probe.height".into(), height)?;
                if self.tanks.is_empty() {
                    return Err(field_err(
                        "probe",
                        "Hydrostatic measures the first tank's floor: add a tank",
                    ));
                }
            }
            ProbeSpec::Channel { width } => check_positive("probe.width".into(), width)?,
            ProbeSpec::Tap { center, radius } => {
                check_finite("probe.center".into(), &center)?;
                check_positive("probe.radius".into(), radius)?;
            }
        }
        check_positive("output.frame_rate".into(), self.output.frame_rate)?;
        Ok(())
    }
}
