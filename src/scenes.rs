//! Built-in scenes with their own measurements: the dam break against Martin & Moyce 1952, the
//! hydrostatic tank, and the gravity-driven channel used to check slip conditions.

use crate::emitter::{Emitter, Sink};
use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::metrics::{StageTimes, StepReport};
use crate::params::FluidParams;
use crate::scene_file::{
    BlockSpec, BodyKind, BodySpec, ColliderSpec, EmitterSpec, OutletSpec, OutputSpec, ProbeSpec,
    SceneFile, ShapeSpec, SinkSpec, TankSpec, WallSpec,
};
use crate::solver::staggered::Slip;
use crate::world::{FluidWorld, SolidHandle};
use rapier3d::dynamics::RigidBodyHandle;
use rapier3d::pipeline::PhysicsWorld;
use serde::Serialize;
use std::time::Instant;

/// Martin & Moyce 1952 surge-front table (n² = 2): `(T, Z)` with `T = t√(2g/a)`, `Z = x/a`.
pub fn martin_moyce_front() -> Vec<(f64, f64)> {
    read_table(include_str!(
        "../assets/martin_moyce_1952_n2_2_front_table.csv"
    ))
}

/// Standard gravity (y up), m/s².
pub const G: f32 = 9.81;

/// Names of the built-in scenes.
pub const NAMES: &[&str] = &[
    "dam_break",
    "hydrostatic",
    "channel",
    "five_balls",
    "stone",
    "stone_no_slip",
    "pillars",
    "wedge",
    "wedge_zhao",
    "tap",
    "tap_sticky",
];

/// What a scene measures while it runs.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub enum Probe {
    /// Dam break of a column of width `a` (height 2a): surge front over time.
    DamBreak {
        /// Column width, m.
        a: f32,
    },
    /// Still tank: vertical force on the floor.
    Hydrostatic {
        /// The floor.
        floor: SolidHandle,
        /// Fluid height, m.
        height: f32,
    },
    /// Vertical channel between two plates `x ∈ [0, width]`: velocity profile across it.
    Channel {
        /// Plate gap, m.
        width: f32,
    },
    /// Rapier bodies in water: fluid carriers found inside any coupled body (after the step).
    Bodies,
    /// Water pouring on a sphere (He 2012 Fig. 13): share of the fluid touching the sphere
    /// that lies on its lower half.
    Tap {
        /// Sphere centre, m.
        center: Vector,
        /// Sphere radius, m.
        radius: f32,
    },
}

/// A ready-to-run scene.
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// The world.
    pub world: FluidWorld,
    /// Gravity.
    pub gravity: Vector,
    /// Step length, s.
    pub dt: f32,
    /// Default duration, s.
    pub seconds: f32,
    /// What to measure.
    pub probe: Probe,
    /// The rapier world of a coupled scene (stepped with the fluid).
    pub physics: Option<PhysicsWorld>,
    /// Named rapier bodies whose pose and fluid force go into the report.
    pub tracked: Vec<(String, RigidBodyHandle)>,
    /// Inflow emitters, run before each step.
    pub emitters: Vec<Emitter>,
    /// Outflow sinks, drained after each step.
    pub sinks: Vec<Sink>,
    /// The description it was built from.
    pub spec: SceneFile,
}

fn tank(min: [f32; 3], max: [f32; 3], slip: Slip) -> TankSpec {
    TankSpec {
        min,
        max,
        slip,
        floor_slip: None,
        rapier: false,
    }
}

/// A no-slip tank `[0, max]` that is a rapier collider set too, so bodies rest on its floor.
fn body_tank(max: [f32; 3]) -> TankSpec {
    TankSpec {
        rapier: true,
        ..tank([0.0; 3], max, Slip::NoSlip)
    }
}

fn block(min: [f32; 3], max: [f32; 3]) -> BlockSpec {
    BlockSpec {
        min,
        max,
        velocity: [0.0; 3],
        around_bodies: false,
    }
}

fn wall(name: &str, min: Vector, max: Vector, slip: Slip) -> WallSpec {
    WallSpec {
        name: name.into(),
        min: min.into(),
        max: max.into(),
        slip,
    }
}

/// A scene description with nothing in it but its name, step, duration and parameters (at
/// spacing `spacing`).
fn base(
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
        params: FluidParams { spacing, ..params },
        tanks: Vec::new(),
        walls: Vec::new(),
        bodies: Vec::new(),
        fluid: Vec::new(),
        emitters: Vec::new(),
        sinks: Vec::new(),
        probe: ProbeSpec::Bodies,
        output: OutputSpec::default(),
    }
}

fn body(name: &str, kind: BodyKind, position: [f32; 3], colliders: Vec<ColliderSpec>) -> BodySpec {
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

fn collider(shape: ShapeSpec, density: Option<f32>, couple: Option<Slip>) -> ColliderSpec {
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

/// Dam break after Martin & Moyce 1952 in a quasi-3-D slab with free-slip walls: column of width
/// `a` and height `2a` at `x ∈ [0, a]` in a tank `5a` long, `layers` particles thick in z.
pub fn dam_break_spec(a: f32, spacing: f32, layers: usize, params: FluidParams) -> SceneFile {
    let w = layers as f32 * spacing;
    let dt = (0.4 * spacing / (2.0 * (2.0 * G * 2.0 * a).sqrt())).min(2e-3);
    let mut s = base(
        "dam_break",
        "Martin & Moyce 1952 dam break (n² = 2) in a quasi-3-D slab: no-slip floor, free-slip walls",
        dt,
        3.3 / (2.0 * G / a).sqrt(),
        spacing,
        params,
    );
    // the floor is a real wall (no slip, Eq. 26); the side walls bound a slice of a wide
    // channel (free slip). With a free-slip floor the front ran 8–14 % ahead of the experiment.
    s.tanks.push(TankSpec {
        floor_slip: Some(Slip::NoSlip),
        ..tank([0.0; 3], [5.0 * a, 3.0 * a, w], Slip::FreeSlip)
    });
    s.fluid.push(block([0.0; 3], [a, 2.0 * a, w]));
    s.probe = ProbeSpec::DamBreak { a };
    s
}

/// [`dam_break_spec`] built.
pub fn dam_break(a: f32, spacing: f32, layers: usize, params: FluidParams) -> Result<Scene> {
    dam_break_spec(a, spacing, layers, params).build()
}

/// Still water of depth `height` in an open tank `side × side` with no-slip walls.
pub fn hydrostatic_spec(side: f32, height: f32, spacing: f32, params: FluidParams) -> SceneFile {
    let mut s = base(
        "hydrostatic",
        "still water in an open tank: floor force against the weight, spurious speeds",
        2e-3,
        2.0,
        spacing,
        params,
    );
    // a real tank: no-slip walls. With free-slip walls a slow circulation sinks along the
    // vertical edges (0.18 m/s after 2 s, ARCHITECTURE.md).
    s.tanks
        .push(tank([0.0; 3], [side, height * 1.5, side], Slip::NoSlip));
    s.fluid.push(block([0.0; 3], [side, height, side]));
    s.probe = ProbeSpec::Hydrostatic { height };
    s
}

/// [`hydrostatic_spec`] built.
pub fn hydrostatic(side: f32, height: f32, spacing: f32, params: FluidParams) -> Result<Scene> {
    hydrostatic_spec(side, height, spacing, params).build()
}

/// A fluid column falling under gravity between two vertical plates `x ∈ [0, width]` with the
/// given slip, `layers` particles thick in z between free-slip plates, kinematic viscosity `nu`.
pub fn channel_spec(
    width: f32,
    spacing: f32,
    layers: usize,
    slip: Slip,
    nu: f32,
    params: FluidParams,
) -> SceneFile {
    let params = FluidParams {
        spacing,
        viscosity: nu,
        ..params
    };
    // plates thicker than two supports, so every reachable carrier's normal faces the fluid
    let t = 2.0 * params.support_radius() + spacing;
    let (len, col) = (40.0 * width, 2.0 * width);
    // plates reach well above the column, so no carrier near the fluid faces up
    let top = col + 2.0 * t;
    let d = layers as f32 * spacing;
    let mut s = base(
        "channel",
        "a column falling between two plates: the velocity profile shows the slip condition",
        1e-3,
        0.5,
        spacing,
        params,
    );
    s.walls = vec![
        wall(
            "plate -x",
            Vector::new(-t, -len, -t),
            Vector::new(0.0, top, d + t),
            slip,
        ),
        wall(
            "plate +x",
            Vector::new(width, -len, -t),
            Vector::new(width + t, top, d + t),
            slip,
        ),
        wall(
            "side -z",
            Vector::new(0.0, -len, -t),
            Vector::new(width, top, 0.0),
            Slip::FreeSlip,
        ),
        wall(
            "side +z",
            Vector::new(0.0, -len, d),
            Vector::new(width, top, d + t),
            Slip::FreeSlip,
        ),
    ];
    s.fluid.push(block([0.0; 3], [width, col, d]));
    s.probe = ProbeSpec::Channel { width };
    s
}

/// [`channel_spec`] built.
pub fn channel(
    width: f32,
    spacing: f32,
    layers: usize,
    slip: Slip,
    nu: f32,
    params: FluidParams,
) -> Result<Scene> {
    channel_spec(width, spacing, layers, slip, nu, params).build()
}

/// The description of a built-in scene by name at its default size (`spacing` overrides the
/// resolution), on base parameters `p` (the scene sets the spacing).
pub fn spec_by_name(name: &str, spacing: Option<f32>, p: FluidParams) -> Result<SceneFile> {
    Ok(match name {
        // 30 carriers across by default (where the smoothed front is within 10 % of Martin &
        // Moyce), in a 20 mm slab at any spacing
        "dam_break" => {
            let dx = spacing.unwrap_or(0.1 / 30.0);
            dam_break_spec(0.1, dx, ((0.02 / dx).round() as usize).max(4), p)
        }
        "hydrostatic" => hydrostatic_spec(0.4, 0.3, spacing.unwrap_or(0.02), p),
        "channel" => channel_spec(0.1, spacing.unwrap_or(0.01), 3, Slip::NoSlip, 0.02, p),
        "five_balls" => five_balls_spec(spacing.unwrap_or(0.02), p),
        "stone" => stone_spec(spacing.unwrap_or(0.02), 30.0, Slip::FreeSlip, p),
        "stone_no_slip" => stone_spec(spacing.unwrap_or(0.02), 30.0, Slip::NoSlip, p),
        "pillars" => pillars_spec(spacing.unwrap_or(0.02), p),
        "wedge" => wedge_spec(YETTOU_2006, spacing.unwrap_or(0.02), 4, p)?,
        "wedge_zhao" => SceneFile {
            name: "wedge_zhao".into(),
            ..wedge_spec(ZHAO_1996, spacing.unwrap_or(0.01), 4, p)?
        },
        "tap" => tap_spec(spacing.unwrap_or(0.01), false, p),
        "tap_sticky" => tap_spec(spacing.unwrap_or(0.01), true, p),
        _ => return Err(FluidError::UnknownScene(name.into(), NAMES.join(", "))),
    })
}

/// Builds a built-in scene by name at its default size (`spacing` overrides the resolution).
pub fn by_name(name: &str, spacing: Option<f32>) -> Result<Scene> {
    by_name_with(name, spacing, FluidParams::default())
}

/// Like [`by_name`] with explicit base parameters (the scene sets the spacing).
pub fn by_name_with(name: &str, spacing: Option<f32>, p: FluidParams) -> Result<Scene> {
    spec_by_name(name, spacing, p)?.build()
}

/// He 2012 Fig. 15 at a size that runs here: five balls (radius 3Δx... here 0.06 m at the
/// default spacing) of density 550, 775, 1000, 1225 and 1450 kg/m³ dropped from 0.12 m above
/// a tank of water 0.3 m deep. The tank is a fixed rapier collider set (balls rest on its floor
/// by rapier contact) and, for the fluid, an open tank with no-slip walls; balls are free-slip.
pub fn five_balls_spec(spacing: f32, params: FluidParams) -> SceneFile {
    let (w, d, depth, r) = (1.0f32, 0.3f32, 0.3f32, 0.06f32);
    let mut s = base(
        "five_balls",
        "He 2012 Fig. 15: balls of density 550–1450 kg/m³ dropped into water; drafts against Archimedes",
        1.0 / 240.0,
        2.0,
        spacing,
        params,
    );
    s.tanks.push(body_tank([w, 2.0 * depth, d]));
    for (k, rho) in [550.0f32, 775.0, 1000.0, 1225.0, 1450.0]
        .into_iter()
        .enumerate()
    {
        s.bodies.push(body(
            &format!("ball {rho}"),
            BodyKind::Dynamic,
            [0.1 + 0.2 * k as f32, depth + r + 0.06, 0.5 * d],
            vec![ColliderSpec {
                friction: 0.3,
                ..collider(
                    ShapeSpec::Ball { radius: r },
                    Some(rho),
                    Some(Slip::FreeSlip),
                )
            }],
        ));
    }
    s.fluid.push(block([0.0; 3], [w, depth, d]));
    s
}

/// [`five_balls_spec`] built.
pub fn five_balls(spacing: f32, params: FluidParams) -> Result<Scene> {
    five_balls_spec(spacing, params).build()
}

/// A symmetric wedge dropped into still water, free to move vertically only (quasi-2-D: a slab
/// `layers` carriers thick between free-slip walls, the wedge spanning it, its mass
/// `mass_per_length` times the slab thickness). t = 0 is the apex touching the surface.
#[derive(Debug, Clone, Copy)]
pub struct WedgeDrop {
    /// Deadrise angle β, degrees.
    pub deadrise: f32,
    /// Breadth of the wedge's top, m.
    pub breadth: f32,
    /// Mass per metre of wedge length, kg/m.
    pub mass_per_length: f32,
    /// Downward entry speed, m/s.
    pub speed: f32,
    /// Tank width, m.
    pub width: f32,
    /// Water depth, m.
    pub depth: f32,
}

impl WedgeDrop {
    /// Height of the wedge's top above its apex, `breadth/2 · tan β`.
    pub fn rise(&self) -> f32 {
        0.5 * self.breadth * self.deadrise.to_radians().tan()
    }

    /// Corners of the wedge prism `thickness` long along z, apex at the origin.
    ///
    /// ```
    /// let hull = staggered_fluid::scenes::YETTOU_2006.hull(0.1);
    /// assert_eq!(hull[0], staggered_fluid::math::Vector::ZERO);
    /// assert_eq!(hull[5].z, 0.1);
    /// ```
    pub fn hull(&self, thickness: f32) -> [Vector; 6] {
        let (h, rise, d) = (0.5 * self.breadth, self.rise(), thickness);
        [
            Vector::new(0.0, 0.0, 0.0),
            Vector::new(-h, rise, 0.0),
            Vector::new(h, rise, 0.0),
            Vector::new(0.0, 0.0, d),
            Vector::new(-h, rise, d),
            Vector::new(h, rise, d),
        ]
    }

    /// Volume of the prism `thickness` long.
    pub fn volume(&self, thickness: f32) -> f32 {
        0.5 * self.breadth * self.rise() * thickness
    }
}

/// Yettou et al. 2006 (the data in `assets/`): 25°, 1.2 m, 94 kg/m, 5.05 m/s, water 1.1 m deep
/// in a tank 2.5 m wide.
pub const YETTOU_2006: WedgeDrop = WedgeDrop {
    deadrise: 25.0,
    breadth: 1.2,
    mass_per_length: 94.0,
    speed: 5.05,
    width: 2.5,
    depth: 1.1,
};

/// Zhao, Faltinsen & Aarsnes 1996 as He 2012 §7.2 sets it up: 30°, 0.5 m, 6.15 m/s, water 1 m
/// deep and 2 m wide, mass 141 kg as printed there (much of the literature quotes 241 kg; no
/// digitised measurement is available here).
pub const ZHAO_1996: WedgeDrop = WedgeDrop {
    deadrise: 30.0,
    breadth: 0.5,
    mass_per_length: 141.0,
    speed: 6.15,
    width: 2.0,
    depth: 1.0,
};

/// The Yettou et al. 2006 wedge drop (issue 4) as a scene; see [`wedge`].
pub fn wedge_yettou(spacing: f32, layers: usize, params: FluidParams) -> Result<Scene> {
    wedge(YETTOU_2006, spacing, layers, params)
}

/// A wedge drop (see [`WedgeDrop`]) at spacing `spacing`, `layers` carriers thick. Tracked
/// body: `"wedge"`; 40 ms by default.
pub fn wedge_spec(
    drop: WedgeDrop,
    spacing: f32,
    layers: usize,
    params: FluidParams,
) -> Result<SceneFile> {
    let WedgeDrop {
        mass_per_length,
        speed,
        width: w,
        depth,
        ..
    } = drop;
    let d = layers as f32 * spacing;
    let rise = drop.rise();
    let mut s = base(
        "wedge",
        "a wedge dropped into still water (Yettou et al. 2006), free to move vertically only",
        1e-3,
        0.04,
        spacing,
        params,
    );
    s.tanks
        .push(tank([0.0; 3], [w, depth + rise + 0.1, d], Slip::FreeSlip));
    let mut b = body(
        "wedge",
        BodyKind::Dynamic,
        [0.5 * w, depth, 0.0],
        vec![collider(
            ShapeSpec::ConvexHull {
                points: drop.hull(d).iter().map(|p| (*p).into()).collect(),
            },
            Some(mass_per_length * d / drop.volume(d)),
            Some(Slip::FreeSlip),
        )],
    );
    b.linvel = [0.0, -speed, 0.0];
    b.lock_translation = [true, false, true];
    b.lock_rotation = true;
    s.bodies.push(b);
    s.fluid.push(BlockSpec {
        around_bodies: true,
        ..block([0.0; 3], [w, depth, d])
    });
    Ok(s)
}

/// [`wedge_spec`] built.
pub fn wedge(drop: WedgeDrop, spacing: f32, layers: usize, params: FluidParams) -> Result<Scene> {
    wedge_spec(drop, spacing, layers, params)?.build()
}

/// Yettou et al. 2006 measured downward velocity `(t s, v m/s)` over 0–40 ms (digitised from
/// Sun et al. 2015; see `assets/wedge_yettou2006_velocity_exp.csv` for the citation).
pub fn yettou_velocity() -> Vec<(f64, f64)> {
    read_table(include_str!("../assets/wedge_yettou2006_velocity_exp.csv"))
        .into_iter()
        .map(|(t, v)| (t * 1e-3, v))
        .collect()
}

/// Von Kármán (`wagner = false`) or Wagner momentum model of a wedge entry with gravity and
/// no buoyancy, per unit length: `(m + ρ π c²/2) V = m V0 + m g t`, `c = k ζ / tan β` with
/// `k = 1` (von Kármán) or `π/2` (Wagner), ζ the penetration. Integrated with step `dt` to
/// `t_end`; returns `(t, V)` samples. The measured velocity should lie between the two.
pub fn wedge_momentum_model(drop: WedgeDrop, wagner: bool, t_end: f64, dt: f64) -> Vec<(f64, f64)> {
    let (m, v0, rho, beta) = (
        drop.mass_per_length as f64,
        drop.speed as f64,
        1000.0f64,
        (drop.deadrise as f64).to_radians(),
    );
    let k = if wagner {
        std::f64::consts::FRAC_PI_2
    } else {
        1.0
    };
    let vel = |z: f64, t: f64| {
        let c = k * z / beta.tan();
        (m * v0 + m * G as f64 * t) / (m + rho * std::f64::consts::PI * c * c / 2.0)
    };
    let (mut t, mut zeta, mut v) = (0.0f64, 0.0f64, v0);
    let mut out = vec![(0.0, v0)];
    while t < t_end {
        // midpoint in ζ
        let zm = zeta + 0.5 * dt * v;
        let vm = vel(zm, t + 0.5 * dt);
        zeta += dt * vm;
        t += dt;
        v = vel(zeta, t);
        out.push((t, v));
    }
    out
}

/// `(x, y)` rows of a CSV with `#` comments and one header line.
fn read_table(text: &str) -> Vec<(f64, f64)> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut it = l.split(',').map(|s| s.trim().parse::<f64>());
            Some((it.next()?.ok()?, it.next()?.ok()?))
        })
        .collect()
}

/// He 2012 Fig. 14 at a size that runs here: an elliptical stone (a convex hull of points on an
/// ellipsoid with semi-axes 0.1 × 0.04 × 0.06 m, 2000 kg/m³) dropped flat at 1.5 m/s into water
/// 0.3 m deep, spinning at `spin` rad/s about its long axis, with the given slip condition. The
/// paper's observation: under free slip the spin survives, under no slip the water stops it.
pub fn stone_spec(spacing: f32, spin: f32, slip: Slip, params: FluidParams) -> SceneFile {
    let (w, d, depth) = (0.6f32, 0.4f32, 0.3f32);
    let mut s = base(
        if slip == Slip::NoSlip {
            "stone_no_slip"
        } else {
            "stone"
        },
        "He 2012 Fig. 14: a spinning flat stone dropped into water; free slip keeps the spin",
        1.0 / 240.0,
        1.0,
        spacing,
        params,
    );
    s.tanks.push(body_tank([w, 2.0 * depth, d]));
    let mut b = body(
        "stone",
        BodyKind::Dynamic,
        [0.5 * w, depth + 0.08, 0.5 * d],
        vec![collider(
            ShapeSpec::Ellipsoid {
                semi_axes: [0.1, 0.04, 0.06],
                segments: 12,
                rings: 8,
            },
            Some(2000.0),
            Some(slip),
        )],
    );
    b.linvel = [0.0, -1.5, 0.0];
    b.angvel = [spin, 0.0, 0.0];
    s.bodies.push(b);
    s.fluid.push(block([0.0; 3], [w, depth, d]));
    s
}

/// [`stone_spec`] built.
pub fn stone(spacing: f32, spin: f32, slip: Slip, params: FluidParams) -> Result<Scene> {
    stone_spec(spacing, spin, slip, params).build()
}

/// He 2012 Fig. 1 (right) at a size that runs here: a dam break (column 0.2 × 0.4 m) around
/// three scripted pillars (cylinders of radius 0.04 m) spinning at ±10 rad/s with no-slip
/// walls, in a tank 1 m long and 0.3 m wide.
pub fn pillars_spec(spacing: f32, params: FluidParams) -> SceneFile {
    let (w, d, h) = (1.0f32, 0.3f32, 0.4f32);
    let mut s = base(
        "pillars",
        "He 2012 Fig. 1: a dam break around three scripted spinning pillars",
        1.0 / 240.0,
        1.5,
        spacing,
        params,
    );
    s.tanks.push(tank([0.0; 3], [w, 1.5 * h, d], Slip::NoSlip));
    for (k, (x, z, spin)) in [
        (0.45f32, 0.1f32, 10.0f32),
        (0.45, 0.2, -10.0),
        (0.65, 0.15, 10.0),
    ]
    .into_iter()
    .enumerate()
    {
        let mut b = body(
            &format!("pillar {k}"),
            BodyKind::KinematicVelocity,
            [x, 0.5 * h, z],
            vec![collider(
                ShapeSpec::Cylinder {
                    half_height: 0.5 * h,
                    radius: 0.04,
                },
                None,
                Some(Slip::NoSlip),
            )],
        );
        b.angvel = [0.0, spin, 0.0];
        s.bodies.push(b);
    }
    s.fluid.push(block([0.0; 3], [0.2, h, d]));
    s
}

/// [`pillars_spec`] built.
pub fn pillars(spacing: f32, params: FluidParams) -> Result<Scene> {
    pillars_spec(spacing, params).build()
}

/// He 2012 Fig. 13 at a size that runs here: tap water (a disc of radius 2.5Δx, 0.025 m at
/// the default spacing, 1 m/s downward) pouring on a fixed free-slip sphere of radius 0.06 m,
/// with the §5.2 no-stick inequality on (`sticky = false`: the stream leaves the sphere and
/// splashes off) or off for the sphere (`sticky = true`: the water wraps around it and drips
/// from its bottom). A sink along the floor removes the water that reaches it. (With a
/// no-slip sphere the first layer cannot slide at this resolution and the water piles up on
/// top in both variants.)
pub fn tap_spec(spacing: f32, sticky: bool, params: FluidParams) -> SceneFile {
    let (w, h, r) = (0.4f32, 0.5f32, 0.06f32);
    let mut s = base(
        if sticky { "tap_sticky" } else { "tap" },
        "He 2012 Fig. 13: tap water pouring on a sphere, with (tap) and without (tap_sticky) the no-stick inequality",
        2e-3,
        1.0,
        spacing,
        FluidParams {
            no_stick: true,
            ..params
        },
    );
    s.tanks.push(tank([0.0; 3], [w, h, w], Slip::NoSlip));
    let mut sphere = body(
        "sphere",
        BodyKind::Fixed,
        [0.5 * w, 0.25, 0.5 * w],
        vec![collider(
            ShapeSpec::Ball { radius: r },
            None,
            Some(Slip::FreeSlip),
        )],
    );
    sphere.colliders[0].stick = sticky;
    sphere.track = false;
    s.bodies.push(sphere);
    // the stream lands just off the sphere's top, so it runs down one side
    s.emitters.push(EmitterSpec {
        center: [0.5 * w + 0.3 * r, h - 0.05, 0.5 * w],
        velocity: [0.0, -1.0, 0.0],
        outlet: OutletSpec::Disc {
            radius: 2.5 * spacing,
        },
        start: 0.0,
        stop: None,
    });
    s.sinks.push(SinkSpec {
        min: [0.0, 0.0, 0.0],
        max: [w, 0.06, w],
    });
    s.probe = ProbeSpec::Tap {
        center: [0.5 * w, 0.25, 0.5 * w],
        radius: r,
    };
    s
}

/// Fluid carriers within 1.5 Δx of a sphere's surface: `(below its centre, all)`.
pub fn wetting(world: &FluidWorld, center: Vector, radius: f32) -> (usize, usize) {
    let reach = radius + 1.5 * world.params().spacing;
    let near: Vec<Vector> = world
        .fluid()
        .x
        .iter()
        .filter(|p| (**p - center).length() <= reach)
        .copied()
        .collect();
    let below = near.iter().filter(|p| p.y < center.y).count();
    (below, near.len())
}

/// Fluid carriers inside any coupled solid (exact shape test; 0 when the coupling holds).
pub fn carriers_inside_solids(world: &FluidWorld) -> usize {
    let solids: Vec<_> = world
        .solids()
        .iter()
        .filter(|s| !s.removed && s.kind != crate::world::SolidKind::Static)
        .collect();
    world
        .fluid()
        .x
        .iter()
        .filter(|x| solids.iter().any(|s| s.shape.contains_point(&s.pose, **x)))
        .count()
}

/// Surge front of a dam break: largest x of fluid carriers that have at least 4 neighbours
/// (so detached droplets do not count), plus half a spacing.
pub fn surge_front(world: &FluidWorld) -> f32 {
    let f = world.fluid();
    let x =
        f.x.iter()
            .zip(&f.neighbors)
            .filter(|(_, &n)| n >= 4)
            .map(|(p, _)| p.x)
            .fold(f32::NEG_INFINITY, f32::max);
    x + 0.5 * world.params().spacing
}

/// Mean vertical velocity of fluid carriers in bins across `x ∈ [0, width]`, near the vertical
/// middle of the column (`bins` entries, m/s; NaN for empty bins).
pub fn channel_profile(world: &FluidWorld, width: f32, bins: usize) -> Vec<f32> {
    let f = world.fluid();
    let ys: Vec<f32> = f.x.iter().map(|p| p.y).collect();
    let (ymin, ymax) = ys
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    let (lo, hi) = (ymin + 0.3 * (ymax - ymin), ymin + 0.7 * (ymax - ymin));
    let mut sum = vec![0.0f64; bins];
    let mut cnt = vec![0usize; bins];
    for (p, v) in f.x.iter().zip(&f.v) {
        if p.y < lo || p.y > hi || p.x < 0.0 || p.x >= width {
            continue;
        }
        let b = ((p.x / width) * bins as f32) as usize;
        sum[b.min(bins - 1)] += v.y as f64;
        cnt[b.min(bins - 1)] += 1;
    }
    sum.iter()
        .zip(&cnt)
        .map(|(s, &c)| {
            if c > 0 {
                (*s / c as f64) as f32
            } else {
                f32::NAN
            }
        })
        .collect()
}

/// One sample of a scene's own measurement.
#[derive(Debug, Clone, Serialize)]
pub struct Sample {
    /// Simulated time, s.
    pub t: f64,
    /// Measured quantity (front position in m, floor force in N, or centre-line speed in m/s).
    pub value: f64,
    /// Its non-dimensional form (Z = x/a; force/weight; speed/√(g·width)).
    pub normalized: f64,
}

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
    /// Simulated seconds.
    pub simulated_seconds: f64,
    /// Wall-clock seconds.
    pub wall_seconds: f64,
    /// Wall seconds per simulated second.
    pub wall_per_simulated_second: f64,
    /// Seconds per stage, summed over the run.
    pub stage_seconds: StageTimes,
    /// Mean E (Eq. 29) over steps.
    pub mean_error: f64,
    /// Largest E over steps.
    pub max_error: f64,
    /// Mean PCG iterations per step.
    pub mean_pcg_iterations: f64,
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
    /// Samples of the metric.
    pub metric: Vec<Sample>,
    /// Scene-specific comparison (e.g. front error against Martin & Moyce).
    pub comparison: serde_json::Value,
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

    /// The scene's metric right now.
    pub fn sample(&self) -> Sample {
        let t = self.world.time();
        match self.probe {
            Probe::DamBreak { a } => {
                let x = surge_front(&self.world) as f64;
                Sample {
                    t,
                    value: x,
                    normalized: x / a as f64,
                }
            }
            Probe::Hydrostatic { floor, .. } => {
                let f = self.world.solid(floor).map(|s| -s.force.y).unwrap_or(0.0) as f64;
                let weight = self.world.fluid_mass() * G as f64;
                Sample {
                    t,
                    value: f,
                    normalized: f / weight,
                }
            }
            Probe::Channel { width } => {
                let prof = channel_profile(&self.world, width, 9);
                let c = -prof[4] as f64;
                Sample {
                    t,
                    value: c,
                    normalized: c / (G as f64 * width as f64).sqrt(),
                }
            }
            Probe::Tap { center, radius } => {
                let (below, near) = wetting(&self.world, center, radius);
                Sample {
                    t,
                    value: below as f64,
                    normalized: below as f64 / near.max(1) as f64,
                }
            }
            Probe::Bodies => {
                let n = carriers_inside_solids(&self.world) as f64;
                Sample {
                    t,
                    value: n,
                    normalized: n / self.world.fluid().len().max(1) as f64,
                }
            }
        }
    }

    /// Name of the metric.
    pub fn metric_name(&self) -> &'static str {
        match self.probe {
            Probe::DamBreak { .. } => "surge front x (m); normalized Z = x/a",
            Probe::Hydrostatic { .. } => "vertical floor force (N); normalized by fluid weight",
            Probe::Channel { .. } => "centre-line downward speed (m/s); normalized by sqrt(g w)",
            Probe::Bodies => "fluid carriers inside bodies; normalized by the fluid count",
            Probe::Tap { .. } => {
                "fluid carriers on the sphere's lower half; normalized by all on the sphere"
            }
        }
    }

    /// Runs for `seconds`, calling `each` after every step; returns the run summary.
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
        let steps = (seconds / self.dt as f64).round().max(1.0) as u64;
        let start = Instant::now();
        let mut stages = StageTimes::default();
        let (mut esum, mut emax, mut iters, mut removed) = (0.0, 0.0f64, 0u64, 0u64);
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
        let mut log = Vec::with_capacity(steps as usize);
        for _ in 0..steps {
            for e in self.emitters.iter_mut() {
                emitted += e.emit(&mut self.world, self.dt)?;
            }
            let rep = match self.physics.as_mut() {
                Some(ph) => self.world.step_physics_world(ph)?.clone(),
                None => self.world.step(self.gravity, self.dt)?.clone(),
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
            particle_steps += rep.n_fluid as f64 * rep.substeps as f64;
            metric.push(self.sample());
            log.push(StepLog {
                t: rep.time,
                error: rep.error,
                pcg_iterations: rep.pcg_iterations,
                n_fluid: rep.n_fluid,
                substeps: rep.substeps,
            });
            each(self, &rep)?;
        }
        let wall = start.elapsed().as_secs_f64();
        let comparison = self.compare(&metric);
        Ok(RunReport {
            scene: self.name.clone(),
            n_fluid: self.world.fluid().len(),
            n_solid: self.world.solid_carriers().len(),
            steps,
            dt: self.dt as f64,
            simulated_seconds: self.world.time(),
            wall_seconds: wall,
            wall_per_simulated_second: wall / self.world.time().max(1e-12),
            stage_seconds: stages,
            mean_error: esum / steps as f64,
            max_error: emax,
            mean_pcg_iterations: iters as f64 / steps as f64,
            us_per_particle_step: 1e6 * stages.total() / particle_steps.max(1.0),
            removed_outside: removed,
            emitted,
            sunk,
            steps_log: log,
            metric_name: self.metric_name().into(),
            metric,
            comparison,
            bodies,
        })
    }

    fn compare(&self, metric: &[Sample]) -> serde_json::Value {
        match self.probe {
            Probe::DamBreak { a } => {
                let scale = (2.0 * G as f64 / a as f64).sqrt();
                let rows: Vec<serde_json::Value> = martin_moyce_front()
                    .into_iter()
                    .filter_map(|(tt, z)| {
                        let z_sim = interpolate(metric, tt / scale)?;
                        Some(
                            serde_json::json!({"T": tt, "Z_reference": z, "Z_simulated": z_sim,
                            "relative_error": (z_sim - z) / z}),
                        )
                    })
                    .collect();
                serde_json::json!({"reference": "Martin & Moyce 1952, n^2 = 2 (Table 2)", "front": rows})
            }
            Probe::Hydrostatic { height, .. } => {
                let t_end = metric.last().map(|s| s.t).unwrap_or(0.0);
                let tail: Vec<f64> = metric
                    .iter()
                    .filter(|s| s.t >= t_end - 0.2)
                    .map(|s| s.normalized)
                    .collect();
                let mean = tail.iter().sum::<f64>() / tail.len().max(1) as f64;
                serde_json::json!({"floor_force_over_weight_last_0.2s": mean,
                    "max_speed_over_sqrt_gH": self.world.last_report().max_speed as f64 / (G as f64 * height as f64).sqrt()})
            }
            Probe::Channel { width } => {
                serde_json::json!({"profile_m_per_s": channel_profile(&self.world, width, 9)})
            }
            Probe::Bodies => {
                let worst = metric.iter().map(|s| s.value).fold(0.0, f64::max);
                serde_json::json!({"most_carriers_inside_bodies_at_a_step_end": worst})
            }
            Probe::Tap { .. } => {
                let t_end = metric.last().map(|s| s.t).unwrap_or(0.0);
                let tail: Vec<f64> = metric
                    .iter()
                    .filter(|s| s.t >= 0.5 * t_end)
                    .map(|s| s.normalized)
                    .collect();
                serde_json::json!({"lower_half_share_of_wetting_fluid_second_half": tail.iter().sum::<f64>() / tail.len().max(1) as f64})
            }
        }
    }
}

/// Linear interpolation of the normalized metric at time `t` (None outside the samples).
fn interpolate(s: &[Sample], t: f64) -> Option<f64> {
    let k = s.windows(2).position(|w| w[0].t <= t && t <= w[1].t)?;
    let (a, b) = (&s[k], &s[k + 1]);
    let f = if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    };
    Some(a.normalized + f * (b.normalized - a.normalized))
}
