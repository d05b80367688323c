//! A wedge dropped into still water (Yettou et al. 2006; He 2012 §7.2 after Zhao & Faltinsen
//! 1996) and a momentum model of its entry to compare with.

use super::parts::{base, block, body, collider, tank};
use super::probe::read_table;
use super::spec::{BlockSpec, BodyKind, SceneFile, ShapeSpec};
use super::{Scene, G};
use crate::error::Result;
use crate::math::Vector;
use crate::params::FluidParams;
use crate::solver::staggered::Slip;

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
    Ok(s.rounded())
}

/// [`wedge_spec`] built.
pub fn wedge(drop: WedgeDrop, spacing: f32, layers: usize, params: FluidParams) -> Result<Scene> {
    wedge_spec(drop, spacing, layers, params)?.build()
}

/// Yettou et al. 2006 measured downward velocity `(t s, v m/s)` over 0–40 ms (digitised from
/// Sun et al. 2015; see `assets/wedge_yettou2006_velocity_exp.csv` for the citation).
pub fn yettou_velocity() -> Vec<(f64, f64)> {
    read_table(include_str!(
        "../../assets/wedge_yettou2006_velocity_exp.csv"
    ))
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
