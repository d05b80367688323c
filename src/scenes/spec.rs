//! The scene-file types: a whole run as data (RON or JSON), read and written with serde.

pub use crate::emitter::{EmitterSpec, OutletSpec};
use crate::params::FluidParams;
use crate::solver::staggered::Slip;
use serde::{Deserialize, Serialize};

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
    /// Seconds the water settles before the first run ([`crate::FluidWorld::settle`]):
    /// stepped at `dt` under `gravity` with every body held still, then its velocities
    /// cleared and the clock put back to zero, so a scene that starts from still water starts
    /// from the arrangement the scheme holds at rest rather than from the lattice. Emitters and
    /// sinks wait for the run. Not with deformable bodies, cloths or heat.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settle: Option<f32>,
    /// Fluid parameters; missing fields take [`FluidParams::default`] (and only the fields
    /// that differ from it are written).
    #[serde(
        default,
        skip_serializing_if = "FluidParams::is_default",
        serialize_with = "crate::params::serialize_changed"
    )]
    pub params: FluidParams,
    /// The fluid's heat (temperature, conductivity), for scenes that melt or heat
    /// ([`crate::FluidWorld::set_fluid_heat`]); without it a scene with a melting body or a
    /// heat source takes [`crate::FluidHeat::default`].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heat: Option<crate::heat::FluidHeat>,
    /// Open-topped tanks (fluid walls; optionally rapier colliders too).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tanks: Vec<TankSpec>,
    /// Static boxes seen by the fluid only.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub walls: Vec<WallSpec>,
    /// Rapier bodies and their colliders.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<BodySpec>,
    /// Deformable bodies (lattice shape matching, [`crate::FluidWorld::add_deformable`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub deformables: Vec<DeformableSpec>,
    /// Cloths ([`crate::FluidWorld::add_cloth`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub cloths: Vec<ClothSpec>,
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

/// An open-topped tank whose inner space is `[min, max]` ([`crate::FluidWorld::add_open_tank`]).
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

/// A static box seen by the fluid only ([`crate::FluidWorld::add_static_box`]).
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
    /// Held at a fixed temperature: a hot plate ([`crate::FluidWorld::set_heat_source`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heat: Option<crate::heat::HeatSource>,
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
    /// A closed triangle mesh (outward-facing triangles; built with
    /// `TriMeshFlags::ORIENTED`, so the fluid can tell its inside): a rabbit, a hull.
    TriMesh {
        /// Vertices, m.
        vertices: Vec<[f32; 3]>,
        /// Triangles as indices into `vertices`.
        indices: Vec<[u32; 3]>,
    },
    /// The union of parts, each a shape (not itself a compound) at an offset: a hollow box
    /// of slabs, a table.
    Compound {
        /// The parts.
        parts: Vec<PartSpec>,
    },
}

/// A part of a [`ShapeSpec::Compound`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartSpec {
    /// Its shape.
    pub shape: ShapeSpec,
    /// Its centre in the compound's frame, m.
    pub offset: [f32; 3],
}

/// A deformable body ([`crate::FluidWorld::add_deformable`]); fluid blocks must leave its
/// shape free.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeformableSpec {
    /// Its name in errors.
    pub name: String,
    /// Its rest shape (body frame).
    pub shape: ShapeSpec,
    /// Position of the body frame, m.
    pub position: [f32; 3],
    /// Orientation as a rotation vector (axis × angle in radians).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotation: [f32; 3],
    /// Initial velocity of its centre of mass, m/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub linvel: [f32; 3],
    /// Initial angular velocity, rad/s.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub angvel: [f32; 3],
    /// Density, stiffness α, region half-width w, slip, damping ζ (defaults for the rest).
    #[serde(default)]
    pub material: crate::deform::DeformableParams,
    /// Its lattice points below this height (world, m) are pinned.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pin_below: Option<f32>,
}

/// A cloth: a rectangle of one layer of points in the plane y = 0 of its pose.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClothSpec {
    /// Its name in errors.
    pub name: String,
    /// Its centre, m.
    pub position: [f32; 3],
    /// Orientation as a rotation vector (axis × angle in radians).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rotation: [f32; 3],
    /// Its sides along its local x and z, m.
    pub size: [f32; 2],
    /// Density (of a sheet one spacing thick), stiffness α, region half-width w, slip,
    /// damping ζ.
    #[serde(default)]
    pub material: crate::deform::DeformableParams,
    /// Whether the points along its four edges are pinned.
    #[serde(default)]
    pub pin_edges: bool,
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
