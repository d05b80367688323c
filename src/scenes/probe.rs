//! What a scene measures while it runs, and its comparison with a reference: the dam-break front
//! against Martin & Moyce 1952, the floor force of a still tank, a channel's profile, fluid
//! found inside bodies, the tap's wetting.

use super::{Scene, G};
use crate::math::Vector;
use crate::world::{FluidWorld, SolidHandle};
use serde::Serialize;

/// Martin & Moyce 1952 surge-front table (n² = 2): `(T, Z)` with `T = t√(2g/a)`, `Z = x/a`.
pub fn martin_moyce_front() -> Vec<(f64, f64)> {
    read_table(include_str!(
        "../../assets/martin_moyce_1952_n2_2_front_table.csv"
    ))
}

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

/// `(x, y)` rows of a CSV with `#` comments and one header line.
pub(crate) fn read_table(text: &str) -> Vec<(f64, f64)> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let mut it = l.split(',').map(|s| s.trim().parse::<f64>());
            Some((it.next()?.ok()?, it.next()?.ok()?))
        })
        .collect()
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

impl Scene {
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

    pub(crate) fn compare(&self, metric: &[Sample]) -> serde_json::Value {
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
