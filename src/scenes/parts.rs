//! Small builders of scene-description parts, shared by the built-in scenes.

use super::spec::{
    BlockSpec, BodyKind, BodySpec, ColliderSpec, OutputSpec, ProbeSpec, SceneFile, ShapeSpec,
    TankSpec, WallSpec,
};
use super::G;
use crate::math::Vector;
use crate::params::FluidParams;
use crate::solver::staggered::Slip;

pub(crate) fn tank(min: [f32; 3], max: [f32; 3], slip: Slip) -> TankSpec {
    TankSpec {
        min,
        max,
        slip,
        floor_slip: None,
        rapier: false,
    }
}

/// A no-slip tank `[0, max]` that is a rapier collider set too, so bodies rest on its floor.
pub(crate) fn body_tank(max: [f32; 3]) -> TankSpec {
    TankSpec {
        rapier: true,
        ..tank([0.0; 3], max, Slip::NoSlip)
    }
}

pub(crate) fn block(min: [f32; 3], max: [f32; 3]) -> BlockSpec {
    BlockSpec {
        min,
        max,
        velocity: [0.0; 3],
        around_bodies: false,
    }
}

pub(crate) fn wall(name: &str, min: Vector, max: Vector, slip: Slip) -> WallSpec {
    WallSpec {
        name: name.into(),
        min: min.into(),
        max: max.into(),
        slip,
        heat: None,
    }
}

/// A scene description with nothing in it but its name, step, duration and parameters (at
/// spacing `spacing`).
pub(crate) fn base(
    name: &str,
    description: &str,
    dt: f32,
    seconds: f32,
    spacing: f32,
    params: FluidParams,
) -> SceneFile {
    SceneFile {
        name: name.into(),
        description: description.into(),
        gravity: [0.0, -G, 0.0],
        dt,
        seconds,
        settle: None,
        params: FluidParams { spacing, ..params },
        heat: None,
        tanks: Vec::new(),
        walls: Vec::new(),
        bodies: Vec::new(),
        deformables: Vec::new(),
        cloths: Vec::new(),
        fluid: Vec::new(),
        emitters: Vec::new(),
        sinks: Vec::new(),
        probe: ProbeSpec::Bodies,
        output: OutputSpec::default(),
    }
}

pub(crate) fn body(
    name: &str,
    kind: BodyKind,
    position: [f32; 3],
    colliders: Vec<ColliderSpec>,
) -> BodySpec {
    BodySpec {
        name: name.into(),
        kind,
        position,
        rotation: [0.0; 3],
        linvel: [0.0; 3],
        angvel: [0.0; 3],
        lock_translation: [false; 3],
        lock_rotation: false,
        track: true,
        colliders,
    }
}

pub(crate) fn collider(
    shape: ShapeSpec,
    density: Option<f32>,
    couple: Option<Slip>,
) -> ColliderSpec {
    ColliderSpec {
        shape,
        offset: [0.0; 3],
        density,
        mass: None,
        friction: 0.5,
        restitution: 0.0,
        couple,
        stick: false,
    }
}
