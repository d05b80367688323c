//! Reading a scene file (RON or JSON, errors located at file:line:column and the field) and
//! building it into a ready [`Scene`]: the rapier world, the fluid world, emitters and sinks.

use super::locate::locate;
use super::probe::Probe;
use super::spec::{BodyKind, ColliderSpec, ProbeSpec, SceneFile, ShapeSpec};
use super::validate::{field_err, v3, FieldError};
use super::Scene;
use crate::emitter::{Emitter, Sink};
use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::world::FluidWorld;
use rapier3d::dynamics::{LockedAxes, RigidBodyBuilder, RigidBodyHandle};
use rapier3d::geometry::{ColliderBuilder, ColliderHandle};
use rapier3d::pipeline::PhysicsWorld;
use std::path::Path;

impl ShapeSpec {
    /// The rapier collider builder of this shape.
    pub(crate) fn builder(&self) -> std::result::Result<ColliderBuilder, String> {
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
            ShapeSpec::TriMesh { vertices, indices } => {
                let v: Vec<Vector> = vertices.iter().map(|p| v3(*p)).collect();
                let flags = rapier3d::parry::shape::TriMeshFlags::ORIENTED;
                ColliderBuilder::trimesh_with_flags(v, indices.clone(), flags)
                    .map_err(|e| format!("not a triangle mesh: {e}"))?
            }
            ShapeSpec::Compound { parts } => {
                let mut shapes = Vec::with_capacity(parts.len());
                for (k, p) in parts.iter().enumerate() {
                    if matches!(p.shape, ShapeSpec::Compound { .. }) {
                        return Err(format!("part {k} is a compound: parts must be simple"));
                    }
                    let pose = crate::math::Pose::from_translation(v3(p.offset));
                    shapes.push((pose, p.shape.builder()?.shape));
                }
                if shapes.is_empty() {
                    return Err("a compound needs at least one part".into());
                }
                ColliderBuilder::compound(shapes)
            }
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
                    if let Some(p) = locate(text, &field) {
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

    /// The same scene with every real number at six significant digits: what the scene means
    /// (f32 arithmetic leaves noise such as `0.42000002` for 0.6 × 0.7 that a file would
    /// print). The built-in scenes are rounded so, and their files print them exactly.
    ///
    /// ```
    /// use staggered_fluid::scenes::SceneFile;
    /// let text = r#"(name: "t", dt: 0.0041666668, seconds: 0.42000002,
    ///     fluid: [(min: (0, 0, 0), max: (0.2, 0.2, 0.2))])"#;
    /// let s = SceneFile::parse(text, "t.ron").unwrap().rounded();
    /// assert_eq!((s.dt, s.seconds), (0.00416667, 0.42));
    /// ```
    pub fn rounded(&self) -> SceneFile {
        fn walk(v: &mut serde_json::Value) {
            match v {
                serde_json::Value::Number(n) if n.is_f64() => {
                    if let Some(x) = n.as_f64() {
                        let r: f64 = format!("{:.5e}", x as f32).parse().unwrap_or(x);
                        if let Some(m) = serde_json::Number::from_f64(r) {
                            *n = m;
                        }
                    }
                }
                serde_json::Value::Array(a) => a.iter_mut().for_each(walk),
                serde_json::Value::Object(o) => o.values_mut().for_each(walk),
                _ => {}
            }
        }
        let Ok(mut v) = serde_json::to_value(self) else {
            return self.clone();
        };
        walk(&mut v);
        serde_json::from_value(v).unwrap_or_else(|_| self.clone())
    }

    /// The scene as RON text (what the files in `assets/scenes/` hold): parameters only where
    /// they differ from the defaults.
    pub fn to_ron(&self) -> String {
        let cfg = ron::ser::PrettyConfig::new()
            .depth_limit(4)
            .separate_tuple_members(false)
            .struct_names(false)
            .extensions(ron::extensions::Extensions::IMPLICIT_SOME);
        ron::ser::to_string_pretty(self, cfg).expect("scene files always serialise")
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
        let params = self.params.clone();
        let mut world = FluidWorld::new(params).map_err(at("params".into()))?;
        if let Some(heat) = self.heat {
            world.set_fluid_heat(heat).map_err(at("heat".into()))?;
        }
        // tanks first (a rapier tank's colliders before the bodies'), bodies coupled after
        let mut floors = Vec::new();
        for (k, t) in self.tanks.iter().enumerate() {
            let walls = match physics.as_mut().filter(|_| t.rapier) {
                Some(ph) => world
                    .add_rapier_tank(&mut ph.colliders, v3(t.min), v3(t.max), t.slip)
                    .map(|tank| tank.walls),
                None => world.add_open_tank(v3(t.min), v3(t.max), t.slip),
            }
            .map_err(at(format!("tanks[{k}]")))?;
            if let Some(s) = t.floor_slip {
                world.set_slip(walls[0], s);
            }
            floors.push(walls[0]);
        }
        let RapierBodies { colliders, tracked } = match physics.as_mut() {
            Some(ph) => self.add_rapier_bodies(ph)?,
            None => RapierBodies::default(),
        };
        for (k, w) in self.walls.iter().enumerate() {
            let h = world
                .add_static_box(&w.name, v3(w.min), v3(w.max), w.slip)
                .map_err(at(format!("walls[{k}]")))?;
            if w.heat.is_some() {
                world
                    .set_heat_source(h, w.heat)
                    .map_err(at(format!("walls[{k}].heat")))?;
            }
        }
        for (field, name, ch, col) in &colliders {
            let Some(slip) = col.couple else { continue };
            let ph = physics.as_ref().expect("rapier world for bodies");
            let s = world
                .couple_collider_named(&ph.bodies, &ph.colliders, *ch, slip, name.clone())
                .map_err(at(format!("{field}.couple")))?;
            if col.stick {
                world.set_sticky(s, true);
            }
        }
        for (k, d) in self.deformables.iter().enumerate() {
            let f = format!("deformables[{k}]");
            let shape = d
                .shape
                .builder()
                .map_err(|m| field_err(format!("{f}.shape"), m))?
                .shape;
            let rotation = crate::math::Rotation::from_scaled_axis(v3(d.rotation));
            let pose = crate::math::Pose::from_parts(v3(d.position), rotation);
            let h = world
                .add_deformable(d.name.clone(), shape, pose, d.material)
                .map_err(at(f.clone()))?;
            if let Some(y) = d.pin_below {
                world
                    .pin_deformable(h, |p| p.y < y)
                    .map_err(at(format!("{f}.pin_below")))?;
            }
            world
                .set_deformable_velocity(h, v3(d.linvel), v3(d.angvel))
                .map_err(at(f))?;
        }
        for (k, c) in self.cloths.iter().enumerate() {
            let f = format!("cloths[{k}]");
            let rotation = crate::math::Rotation::from_scaled_axis(v3(c.rotation));
            let pose = crate::math::Pose::from_parts(v3(c.position), rotation);
            let h = world
                .add_cloth(c.name.clone(), pose, c.size, c.material)
                .map_err(at(f.clone()))?;
            if c.pin_edges {
                // the points within half a spacing of an edge (local frame)
                let edge = [0, 1].map(|j| 0.5 * c.size[j] - 0.5 * self.params.spacing);
                world
                    .pin_deformable(h, |p| {
                        let l = pose.inverse_transform_point(p);
                        l.x.abs() > edge[0] || l.z.abs() > edge[1]
                    })
                    .map_err(at(format!("{f}.pin_edges")))?;
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
            .enumerate()
            .map(|(k, e)| {
                Emitter::new(e, self.params.spacing).map_err(at(format!("emitters[{k}]")))
            })
            .collect::<std::result::Result<_, _>>()?;
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
            settled: None,
        })
    }

    /// Adds the scene's bodies and their colliders to rapier.
    fn add_rapier_bodies(
        &self,
        ph: &mut PhysicsWorld,
    ) -> std::result::Result<RapierBodies<'_>, FieldError> {
        let mut colliders: Vec<(String, String, ColliderHandle, &ColliderSpec)> = Vec::new();
        let mut tracked: Vec<(String, RigidBodyHandle)> = Vec::new();
        for (k, b) in self.bodies.iter().enumerate() {
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
                // errors and reports name the body as the file does
                let name = if b.colliders.len() > 1 {
                    format!("{} (collider {c})", b.name)
                } else {
                    b.name.clone()
                };
                colliders.push((field, name, ch, col));
            }
            if b.track {
                tracked.push((b.name.clone(), handle));
            }
        }
        Ok(RapierBodies { colliders, tracked })
    }
}

/// The colliders a scene added to rapier (with the field path and spec of each) and its tracked
/// bodies.
#[derive(Default)]
struct RapierBodies<'a> {
    /// Field path, the body's name, handle and spec of each collider.
    colliders: Vec<(String, String, ColliderHandle, &'a ColliderSpec)>,
    tracked: Vec<(String, RigidBodyHandle)>,
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
    let (line, column) = locate(text, field).unwrap_or((0, 0));
    FluidError::Scene {
        file: file.into(),
        line,
        column,
        field: field.into(),
        message,
    }
}
