//! Scene files: a whole run as data (RON, or JSON), parsed with serde and turned into a ready
//! [`Scene`] by [`SceneFile::build`].
//!
//! A scene file names the fluid parameters, open tanks and static boxes (fluid-only walls),
//! rapier bodies with their colliders (shape, pose, velocity, density or mass, friction, and
//! whether and with which slip each couples to the fluid), fluid blocks, emitters and sinks,
//! what to measure, how long to run and which frames to write. Every built-in scene is such a
//! description ([`crate::scenes::spec_by_name`]) and ships as a file in `assets/scenes/`.
//!
//! Errors name the file, the line and the field ([`FluidError::Scene`]): syntax and type
//! errors through the parser's position and the field path, inconsistent values (a negative
//! radius, a block inside a wall, a hull of coplanar points) through the path of the value
//! that caused them, located in the text.
//!
//! ```
//! use staggered_fluid::scene_file::SceneFile;
//! let text = r#"(
//!     name: "tiny_tank",
//!     dt: 0.004,
//!     seconds: 0.02,
//!     params: (spacing: 0.05),
//!     tanks: [(min: (0, 0, 0), max: (0.5, 0.5, 0.5), slip: FreeSlip)],
//!     fluid: [(min: (0, 0, 0), max: (0.5, 0.25, 0.5))],
//! )"#;
//! let spec = SceneFile::parse(text, "tiny_tank.ron").unwrap();
//! let mut scene = spec.build().unwrap();
//! let report = scene.run(0.02, |_, _| {}).unwrap();
//! assert_eq!(report.n_fluid, 10 * 5 * 10);
//!
//! let bad = text.replace("spacing: 0.05", "spacing: -0.05");
//! let err = SceneFile::parse(&bad, "tiny_tank.ron").unwrap_err().to_string();
//! assert!(err.starts_with("tiny_tank.ron:5:"), "{err}");
//! assert!(err.contains("params.spacing"), "{err}");
//! ```

use crate::emitter::{Emitter, Sink};
use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::params::FluidParams;
use crate::scenes::{Probe, Scene};
use crate::solver::staggered::Slip;
use crate::world::FluidWorld;
use rapier3d::dynamics::{LockedAxes, RigidBodyBuilder, RigidBodyHandle};
use rapier3d::geometry::{ColliderBuilder, ColliderHandle};
use rapier3d::pipeline::PhysicsWorld;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A whole run described as data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Scene name (reports and output files use it).
    pub name: String,
    /// Free text: what the scene shows and where it comes from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// Gravity, m/s² (y up).
    #[serde(default = "down")]
    pub gravity: [f32; 3],
    /// Step length, s (also rapier's step when the scene has bodies; the fluid substeps inside
    /// it as its CFL and body-force limits require).
    pub dt: f32,
    /// Default duration, s.
    pub seconds: f32,
    /// Fluid parameters; missing fields take [`FluidParams::default`].
    #[serde(default)]
    pub params: FluidParams,
    /// Open-topped tanks (fluid walls; optionally rapier colliders too).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tanks: Vec<TankSpec>,
    /// Static boxes seen by the fluid only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub walls: Vec<WallSpec>,
    /// Rapier bodies and their colliders.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<BodySpec>,
    /// Blocks of fluid at rest or moving.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fluid: Vec<BlockSpec>,
    /// Inflow emitters (taps).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub emitters: Vec<EmitterSpec>,
    /// Outflow sinks: fluid entering them is removed and counted.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sinks: Vec<SinkSpec>,
    /// What the run measures.
    #[serde(default)]
    pub probe: ProbeSpec,
    /// What `run --output DIR` writes.
    #[serde(default)]
    pub output: OutputSpec,
}

fn down() -> [f32; 3] {
    [0.0, -crate::scenes::G, 0.0]
}

/// An open-topped tank whose inner space is `[min, max]` ([`FluidWorld::add_open_tank`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TankSpec {
    /// Inner lower corner, m.
    pub min: [f32; 3],
    /// Inner upper corner, m (the rim is at `max.y`).
    pub max: [f32; 3],
    /// Slip condition of the walls.
    #[serde(default)]
    pub slip: Slip,
    /// Slip of the floor, if it differs from the walls'.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor_slip: Option<Slip>,
    /// Also add the tank to rapier as fixed cuboids, so bodies rest on its floor by contact.
    #[serde(default, skip_serializing_if = "is_false")]
    pub rapier: bool,
}

/// A static box seen by the fluid only ([`FluidWorld::add_static_box`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Its name in reports.
    pub name: String,
    /// Lower corner, m.
    pub min: [f32; 3],
    /// Upper corner, m.
    pub max: [f32; 3],
    /// Slip condition.
    #[serde(default)]
    pub slip: Slip,
}

/// How a rapier body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum BodyKind {
    /// Moved by gravity, contacts and the fluid.
    #[default]
    Dynamic,
    /// Never moves.
    Fixed,
    /// Scripted by its velocity (He 2012 §6): pushes the fluid, is not pushed back.
    KinematicVelocity,
}

/// A rapier body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Its name in reports.
    pub name: String,
    /// How it moves.
    #[serde(default)]
    pub kind: BodyKind,
    /// Position of the body frame, m.
    pub position: [f32; 3],
    /// Orientation as a rotation vector (axis × angle in radians).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotation: [f32; 3],
    /// Initial linear velocity, m/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub linvel: [f32; 3],
    /// Initial angular velocity, rad/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub angvel: [f32; 3],
    /// Translations locked along x, y, z.
    #[serde(default, skip_serializing_if = "is_unlocked")]
    pub lock_translation: [bool; 3],
    /// All rotations locked.
    #[serde(default, skip_serializing_if = "is_false")]
    pub lock_rotation: bool,
    /// Its pose, velocity and fluid force go into the report every step.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub track: bool,
    /// Its colliders.
    pub colliders: Vec<ColliderSpec>,
}

/// A collider shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeSpec {
    /// A sphere.
    Ball {
        /// Radius, m.
        radius: f32,
    },
    /// A box.
    Cuboid {
        /// Half extents, m.
        half_extents: [f32; 3],
    },
    /// A cylinder along y.
    Cylinder {
        /// Half height, m.
        half_height: f32,
        /// Radius, m.
        radius: f32,
    },
    /// A capsule along y.
    Capsule {
        /// Half height of the segment, m.
        half_height: f32,
        /// Radius, m.
        radius: f32,
    },
    /// The convex hull of points (body frame), m.
    ConvexHull {
        /// The points.
        points: Vec<[f32; 3]>,
    },
    /// The convex hull of `segments × (rings + 1)` points on an ellipsoid (a smooth stone).
    Ellipsoid {
        /// Semi-axes along x, y, z, m.
        semi_axes: [f32; 3],
        /// Points around the y axis.
        segments: u32,
        /// Latitude steps from pole to pole.
        rings: u32,
    },
}

/// A collider attached to a body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColliderSpec {
    /// Its shape.
    pub shape: ShapeSpec,
    /// Translation relative to the body frame, m.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub offset: [f32; 3],
    /// Density, kg/m³ (give this or `mass`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f32>,
    /// Mass, kg (give this or `density`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f32>,
    /// Rapier friction coefficient.
    #[serde(default = "half")]
    pub friction: f32,
    /// Rapier restitution coefficient.
    #[serde(default, skip_serializing_if = "is_zero1")]
    pub restitution: f32,
    /// Couple to the fluid with this slip condition (`None`: rapier only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub couple: Option<Slip>,
    /// Let fluid stick to it (turns the §5.2 no-stick inequality off for it).
    #[serde(default, skip_serializing_if = "is_false")]
    pub stick: bool,
}

/// A block of fluid on the lattice `min + (k + ½) Δx`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockSpec {
    /// Lower corner, m.
    pub min: [f32; 3],
    /// Upper corner, m.
    pub max: [f32; 3],
    /// Initial velocity, m/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub velocity: [f32; 3],
    /// Leave out the carriers that would lie inside coupled bodies (a body floating in it).
    #[serde(default, skip_serializing_if = "is_false")]
    pub around_bodies: bool,
}

/// Shape of an emitter's outlet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum OutletSpec {
    /// A disc.
    Disc {
        /// Radius, m.
        radius: f32,
    },
    /// A rectangle.
    Rectangle {
        /// Half sizes along the outlet's two in-plane axes, m.
        half_extents: [f32; 2],
    },
}

/// An inflow emitter: a tap that adds fluid through an outlet at a velocity.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EmitterSpec {
    /// Centre of the outlet, m.
    pub center: [f32; 3],
    /// Velocity of the emitted fluid, m/s; the outlet is perpendicular to it.
    pub velocity: [f32; 3],
    /// Outlet shape.
    pub outlet: OutletSpec,
    /// When it opens, s.
    #[serde(default, skip_serializing_if = "is_zero1")]
    pub start: f32,
    /// When it closes, s (`None`: never).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<f32>,
}

/// An outflow sink: fluid carriers inside `[min, max]` are removed (and counted) after each
/// step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SinkSpec {
    /// Lower corner, m.
    pub min: [f32; 3],
    /// Upper corner, m.
    pub max: [f32; 3],
}

/// What a scene measures while it runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub enum ProbeSpec {
    /// Fluid carriers found inside coupled bodies (plus the tracked bodies).
    #[default]
    Bodies,
    /// Dam-break surge front against Martin & Moyce 1952 (column of width `a`, height `2a`).
    DamBreak {
        /// Column width, m.
        a: f32,
    },
    /// Force on the first tank's floor against the fluid's weight.
    Hydrostatic {
        /// Fluid height, m.
        height: f32,
    },
    /// Velocity profile across a vertical channel `x ∈ [0, width]`.
    Channel {
        /// Plate gap, m.
        width: f32,
    },
    /// Water pouring on a sphere (He 2012 Fig. 13): how much of the water on it clings to its
    /// lower half.
    Tap {
        /// Sphere centre, m.
        center: [f32; 3],
        /// Sphere radius, m.
        radius: f32,
    },
}

/// What `run --output DIR` writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OutputSpec {
    /// Frames per simulated second.
    pub frame_rate: f32,
    /// VTK PolyData (`.vtp`, ParaView) point clouds.
    pub vtk: bool,
    /// PLY point clouds (Blender).
    pub ply: bool,
    /// PNG previews (particles coloured by speed, bodies outlined).
    pub png: bool,
    /// Water surface meshes (OBJ; needs the `surface` feature; costs time).
    pub surface: bool,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            frame_rate: 30.0,
            vtk: true,
            ply: true,
            png: true,
            surface: false,
        }
    }
}

fn yes() -> bool {
    true
}
fn half() -> f32 {
    0.5
}
fn is_false(b: &bool) -> bool {
    !*b
}
fn is_true(b: &bool) -> bool {
    *b
}
fn is_zero(v: &[f32; 3]) -> bool {
    *v == [0.0; 3]
}
fn is_zero1(v: &f32) -> bool {
    *v == 0.0
}
fn is_unlocked(v: &[bool; 3]) -> bool {
    *v == [false; 3]
}

fn v3(a: [f32; 3]) -> Vector {
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

fn field_err(field: impl Into<String>, message: impl Into<String>) -> FieldError {
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

fn check_box(field: &str, min: [f32; 3], max: [f32; 3]) -> std::result::Result<(), FieldError> {
    check_finite(format!("{field}.min"), &min)?;
    check_finite(format!("{field}.max"), &max)?;
    if (0..3).any(|k| max[k] <= min[k]) {
        return Err(field_err(
            format!("{field}.max"),
            format!("must exceed min {min:?} on every axis, got {max:?}"),
        ));
    }
    Ok(())
}

impl ShapeSpec {
    /// The rapier collider builder of this shape.
    fn builder(&self) -> std::result::Result<ColliderBuilder, String> {
        Ok(match self {
            ShapeSpec::Ball { radius } => ColliderBuilder::ball(*radius),
            ShapeSpec::Cuboid { half_extents: h } => ColliderBuilder::cuboid(h[0], h[1], h[2]),
            ShapeSpec::Cylinder {
                half_height,
                radius,
            } => ColliderBuilder::cylinder(*half_height, *radius),
            ShapeSpec::Capsule {
                half_height,
                radius,
            } => ColliderBuilder::capsule_y(*half_height, *radius),
            ShapeSpec::ConvexHull { points } => {
                let pts: Vec<Vector> = points.iter().map(|p| v3(*p)).collect();
                ColliderBuilder::convex_hull(&pts)
                    .ok_or("the points span no volume (coplanar or too few)")?
            }
            ShapeSpec::Ellipsoid { .. } => ColliderBuilder::convex_hull(&self.ellipsoid_points())
                .ok_or("the ellipsoid's points span no volume")?,
        })
    }

    /// Points of [`ShapeSpec::Ellipsoid`] (empty for other shapes).
    fn ellipsoid_points(&self) -> Vec<Vector> {
        let ShapeSpec::Ellipsoid {
            semi_axes: [a, b, c],
            segments,
            rings,
        } = *self
        else {
            return Vec::new();
        };
        let mut pts = Vec::new();
        for i in 0..segments {
            for j in 0..=rings {
                let (th, ph) = (
                    i as f32 * std::f32::consts::TAU / segments as f32,
                    j as f32 * std::f32::consts::PI / rings as f32,
                );
                pts.push(Vector::new(
                    a * ph.sin() * th.cos(),
                    b * ph.cos(),
                    c * ph.sin() * th.sin(),
                ));
            }
        }
        pts
    }

    fn validate(&self, f: &str) -> std::result::Result<(), FieldError> {
        match self {
            ShapeSpec::Ball { radius } => check_positive(format!("{f}.radius"), *radius)?,
            ShapeSpec::Cuboid { half_extents } => {
                for (k, h) in half_extents.iter().enumerate() {
                    check_positive(format!("{f}.half_extents[{k}]"), *h)?;
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
                check_positive(format!("{f}.half_height"), *half_height)?;
                check_positive(format!("{f}.radius"), *radius)?;
            }
            ShapeSpec::ConvexHull { points } => {
                for (k, p) in points.iter().enumerate() {
                    check_finite(format!("{f}.points[{k}]"), p)?;
                }
            }
            ShapeSpec::Ellipsoid {
                semi_axes,
                segments,
                rings,
            } => {
                for (k, h) in semi_axes.iter().enumerate() {
                    check_positive(format!("{f}.semi_axes[{k}]"), *h)?;
                }
                if !(3..=256).contains(segments) {
                    return Err(field_err(format!("{f}.segments"), "must be 3..=256"));
                }
                if !(2..=256).contains(rings) {
                    return Err(field_err(format!("{f}.rings"), "must be 2..=256"));
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
    /// Parses a scene from RON, or from JSON when `file` ends in `.json`; `file` names the
    /// source in error messages. The scene is also checked for values that are out of range
    /// or inconsistent ([`Self::validate`]).
    pub fn parse(text: &str, file: &str) -> Result<Self> {
        let json = file.ends_with(".json");
        let spec: SceneFile = if json {
            let de = &mut serde_json::Deserializer::from_str(text);
            serde_path_to_error::deserialize(de).map_err(|e| {
                let field = path_of(&e);
                let inner = e.into_inner();
                FluidError::Scene {
                    file: file.into(),
                    line: inner.line(),
                    column: inner.column(),
                    field,
                    message: strip_position(&inner.to_string()),
                }
            })?
        } else {
            let opts = ron::Options::default()
                .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
            let mut de = ron::Deserializer::from_str_with_options(text, &opts).map_err(|e| {
                FluidError::Scene {
                    file: file.into(),
                    line: e.span.start.line,
                    column: e.span.start.col,
                    field: String::new(),
                    message: e.code.to_string(),
                }
            })?;
            let spec = serde_path_to_error::deserialize(&mut de).map_err(|e| {
                let field = path_of(&e);
                let sp = de.span_error(e.into_inner());
                let (mut line, mut column) = (sp.span.start.line, sp.span.start.col);
                // the parser notices a missing field at the end of its struct: point at the start
                if matches!(sp.code, ron::Error::MissingStructField { .. }) {
                    if let Some(p) = crate::scene_locate::locate(text, &field) {
                        (line, column) = p;
                    }
                }
                FluidError::Scene {
                    file: file.into(),
                    line,
                    column,
                    field,
                    message: sp.code.to_string(),
                }
            })?;
            de.end().map_err(|code| {
                let sp = de.span_error(code);
                FluidError::Scene {
                    file: file.into(),
                    line: sp.span.start.line,
                    column: sp.span.start.col,
                    field: String::new(),
                    message: sp.code.to_string(),
                }
            })?;
            spec
        };
        spec.validate()
            .map_err(|e| located(text, file, &e.field, e.message))?;
        Ok(spec)
    }

    /// Reads and parses a scene file ([`Self::parse`]).
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| FluidError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses, validates and builds the scene (what `staggered-fluid check FILE` does), so
    /// errors that only building finds (fluid inside a wall, a body outside the domain) are
    /// located in the file too.
    pub fn check(text: &str, file: &str) -> Result<Scene> {
        let spec = Self::parse(text, file)?;
        spec.build_located()
            .map_err(|e| located(text, file, &e.field, e.message))
    }

    /// The scene as RON text (what the files in `assets/scenes/` hold).
    pub fn to_ron(&self) -> String {
        let cfg = ron::ser::PrettyConfig::new()
            .depth_limit(4)
            .separate_tuple_members(false)
            .struct_names(false)
            .extensions(ron::extensions::Extensions::IMPLICIT_SOME);
        ron::ser::to_string_pretty(self, cfg).expect("scene files always serialise")
    }

    /// Checks values a type cannot: positive sizes and densities, finite vectors, ordered box
    /// corners, valid fluid parameters, one of density or mass per collider, some fluid.
    pub fn validate(&self) -> std::result::Result<(), FieldError> {
        check_positive("dt".into(), self.dt)?;
        check_positive("seconds".into(), self.seconds)?;
        check_finite("gravity".into(), &self.gravity)?;
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
            check_finite(format!("fluid[{k}].velocity"), &b.velocity)?;
        }
        for (k, s) in self.sinks.iter().enumerate() {
            check_box(&format!("sinks[{k}]"), s.min, s.max)?;
        }
        for (k, e) in self.emitters.iter().enumerate() {
            let f = format!("emitters[{k}]");
            check_finite(format!("{f}.center"), &e.center)?;
            check_finite(format!("{f}.velocity"), &e.velocity)?;
            if v3(e.velocity).length() <= 0.0 {
                return Err(field_err(format!("{f}.velocity"), "must not be zero"));
            }
            match &e.outlet {
                OutletSpec::Disc { radius } => {
                    check_positive(format!("{f}.outlet.radius"), *radius)?
                }
                OutletSpec::Rectangle { half_extents } => {
                    for (i, h) in half_extents.iter().enumerate() {
                        check_positive(format!("{f}.outlet.half_extents[{i}]"), *h)?;
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
            for (name, v) in [
                ("position", b.position),
                ("rotation", b.rotation),
                ("linvel", b.linvel),
                ("angvel", b.angvel),
            ] {
                check_finite(format!("{f}.{name}"), &v)?;
            }
            if b.colliders.is_empty() {
                return Err(field_err(
                    format!("{f}.colliders"),
                    "a body needs a collider",
                ));
            }
            for (c, col) in b.colliders.iter().enumerate() {
                let fc = format!("{f}.colliders[{c}]");
                col.shape.validate(&format!("{fc}.shape"))?;
                check_finite(format!("{fc}.offset"), &col.offset)?;
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

    /// Builds the scene: the rapier world (if it has bodies or rapier tanks), the fluid world,
    /// emitters and sinks.
    pub fn build(&self) -> Result<Scene> {
        self.validate().map_err(|e| FluidError::Scene {
            file: self.name.clone(),
            line: 0,
            column: 0,
            field: e.field,
            message: e.message,
        })?;
        self.build_located().map_err(|e| FluidError::Scene {
            file: self.name.clone(),
            line: 0,
            column: 0,
            field: e.field,
            message: e.message,
        })
    }

    /// [`Self::build`] with errors tied to the field that caused them.
    fn build_located(&self) -> std::result::Result<Scene, FieldError> {
        let at = |field: String| move |e: FluidError| field_err(field, e.to_string());
        let gravity = v3(self.gravity);
        let needs_rapier = !self.bodies.is_empty() || self.tanks.iter().any(|t| t.rapier);
        let mut physics = needs_rapier.then(|| {
            let mut p = PhysicsWorld::new();
            p.integration_parameters.dt = self.dt;
            p.gravity = gravity;
            p
        });
        if let Some(ph) = physics.as_mut() {
            for t in self.tanks.iter().filter(|t| t.rapier) {
                rapier_tank(ph, v3(t.min), v3(t.max));
            }
        }
        // rapier bodies first (their handles), coupled to the fluid after the walls
        let mut colliders: Vec<(String, ColliderHandle, &ColliderSpec)> = Vec::new();
        let mut tracked: Vec<(String, RigidBodyHandle)> = Vec::new();
        for (k, b) in self.bodies.iter().enumerate() {
            let ph = physics.as_mut().expect("rapier world for bodies");
            let builder = match b.kind {
                BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
                BodyKind::Fixed => RigidBodyBuilder::fixed(),
                BodyKind::KinematicVelocity => RigidBodyBuilder::kinematic_velocity_based(),
            };
            let mut locks = LockedAxes::empty();
            for (axis, flag) in [
                LockedAxes::TRANSLATION_LOCKED_X,
                LockedAxes::TRANSLATION_LOCKED_Y,
                LockedAxes::TRANSLATION_LOCKED_Z,
            ]
            .into_iter()
            .enumerate()
            {
                if b.lock_translation[axis] {
                    locks |= flag;
                }
            }
            if b.lock_rotation {
                locks |= LockedAxes::ROTATION_LOCKED;
            }
            let mut builder = builder.translation(v3(b.position));
            if b.rotation != [0.0; 3] {
                builder = builder.rotation(v3(b.rotation));
            }
            if b.linvel != [0.0; 3] {
                builder = builder.linvel(v3(b.linvel));
            }
            if b.angvel != [0.0; 3] {
                builder = builder.angvel(v3(b.angvel));
            }
            if !locks.is_empty() {
                builder = builder.locked_axes(locks);
            }
            let handle = ph.bodies.insert(builder);
            for (c, col) in b.colliders.iter().enumerate() {
                let field = format!("bodies[{k}].colliders[{c}]");
                let mut cb = col
                    .shape
                    .builder()
                    .map_err(|m| field_err(format!("{field}.shape"), m))?;
                if col.offset != [0.0; 3] {
                    cb = cb.translation(v3(col.offset));
                }
                if let Some(d) = col.density {
                    cb = cb.density(d);
                }
                if let Some(m) = col.mass {
                    cb = cb.mass(m);
                }
                cb = cb.friction(col.friction).restitution(col.restitution);
                let ch = ph.colliders.insert_with_parent(cb, handle, &mut ph.bodies);
                colliders.push((field, ch, col));
            }
            if b.track {
                tracked.push((b.name.clone(), handle));
            }
        }
        let params = self.params.clone();
        let mut world = FluidWorld::new(params).map_err(at("params".into()))?;
        let mut floors = Vec::new();
        for (k, t) in self.tanks.iter().enumerate() {
            let h = world
                .add_open_tank(v3(t.min), v3(t.max), t.slip)
                .map_err(at(format!("tanks[{k}]")))?;
            if let Some(s) = t.floor_slip {
                world.set_slip(h[0], s);
            }
            floors.push(h[0]);
        }
        for (k, w) in self.walls.iter().enumerate() {
            world
                .add_static_box(&w.name, v3(w.min), v3(w.max), w.slip)
                .map_err(at(format!("walls[{k}]")))?;
        }
        for (field, ch, col) in &colliders {
            let Some(slip) = col.couple else { continue };
            let ph = physics.as_ref().expect("rapier world for bodies");
            let s = world
                .couple_collider(&ph.bodies, &ph.colliders, *ch, slip)
                .map_err(at(format!("{field}.couple")))?;
            if col.stick {
                world.set_sticky(s, true);
            }
        }
        for (k, b) in self.fluid.iter().enumerate() {
            let r = match (b.around_bodies, physics.as_ref()) {
                (true, Some(ph)) => {
                    world.add_block_around(v3(b.min), v3(b.max), v3(b.velocity), &ph.colliders)
                }
                _ => world.add_block(v3(b.min), v3(b.max), v3(b.velocity)),
            };
            r.map_err(at(format!("fluid[{k}]")))?;
        }
        let probe = match self.probe {
            ProbeSpec::Bodies => Probe::Bodies,
            ProbeSpec::DamBreak { a } => Probe::DamBreak { a },
            ProbeSpec::Hydrostatic { height } => Probe::Hydrostatic {
                floor: floors[0],
                height,
            },
            ProbeSpec::Channel { width } => Probe::Channel { width },
            ProbeSpec::Tap { center, radius } => Probe::Tap {
                center: v3(center),
                radius,
            },
        };
        let emitters: Vec<Emitter> = self
            .emitters
            .iter()
            .map(|e| Emitter::new(e, self.params.spacing))
            .collect();
        // the automatic domain is fixed at the first step: it must reach the outlets of
        // emitters that open later
        for (k, e) in emitters.iter().enumerate() {
            // an outlet inside a wall or body would fail at its first layer: say so now
            world
                .check_free(&e.layer)
                .map_err(at(format!("emitters[{k}].center")))?;
            for p in &e.layer {
                world.include_in_domain(*p, *p);
            }
        }
        let sinks = self
            .sinks
            .iter()
            .map(|s| Sink {
                min: v3(s.min),
                max: v3(s.max),
            })
            .collect();
        Ok(Scene {
            name: self.name.clone(),
            world,
            gravity,
            dt: self.dt,
            seconds: self.seconds,
            probe,
            physics,
            tracked,
            emitters,
            sinks,
            spec: self.clone(),
        })
    }
}

/// Fixed rapier cuboids 5 cm thick around the inner box `[lo, hi]` (floor and four walls), so
/// rapier bodies rest on the tank the fluid sees.
fn rapier_tank(physics: &mut PhysicsWorld, lo: Vector, hi: Vector) {
    let t = 0.05;
    let c = (lo + hi) * 0.5;
    let half = (hi - lo) * 0.5;
    let yc = lo.y + half.y;
    for (centre, h) in [
        (
            Vector::new(c.x, lo.y - t, c.z),
            Vector::new(half.x + 2.0 * t, t, half.z + 2.0 * t),
        ),
        (
            Vector::new(lo.x - t, yc, c.z),
            Vector::new(t, half.y, half.z + 2.0 * t),
        ),
        (
            Vector::new(hi.x + t, yc, c.z),
            Vector::new(t, half.y, half.z + 2.0 * t),
        ),
        (
            Vector::new(c.x, yc, lo.z - t),
            Vector::new(half.x + 2.0 * t, half.y, t),
        ),
        (
            Vector::new(c.x, yc, hi.z + t),
            Vector::new(half.x + 2.0 * t, half.y, t),
        ),
    ] {
        physics
            .colliders
            .insert(ColliderBuilder::cuboid(h.x, h.y, h.z).translation(centre));
    }
}

/// The field path of a parse error (empty where the parser was between fields).
fn path_of<E>(e: &serde_path_to_error::Error<E>) -> String {
    let p = e.path().to_string();
    if p == "?" || p == "." {
        String::new()
    } else {
        p
    }
}

/// serde_json appends " at line L column C" to its messages; the error names them separately.
fn strip_position(msg: &str) -> String {
    match msg.rfind(" at line ") {
        Some(k) => msg[..k].to_string(),
        None => msg.to_string(),
    }
}

/// A [`FluidError::Scene`] for `field`, located in `text` (line 0 if the field is not found).
fn located(text: &str, file: &str, field: &str, message: String) -> FluidError {
    let (line, column) = crate::scene_locate::locate(text, field).unwrap_or((0, 0));
    FluidError::Scene {
        file: file.into(),
        line,
        column,
        field: field.into(),
        message,
    }
}
