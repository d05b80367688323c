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

/// Fluid carriers inside any coupled solid (0 when the coupling holds): the exact shape of
/// rigid ones; for deformable bodies the lattice cells of their points as they lie now (what
/// is left of a melting one).
pub fn carriers_inside_solids(world: &FluidWorld) -> usize {
    use crate::world::SolidKind;
    let solids: Vec<_> = world
        .solids()
        .iter()
        .filter(|s| !s.removed && !matches!(s.kind, SolidKind::Static | SolidKind::Deformable))
        .collect();
    let dx = world.params().spacing;
    let x = &world.fluid().x;
    x.iter()
        .filter(|x| {
            solids
                .iter()
                .any(|s| crate::sampling::contains(s.shape.as_ref(), &s.pose, **x))
        })
        .count()
        + world
            .deformables()
            .iter()
            .filter(|b| !b.solids.is_empty())
            .map(|b| {
                let shape = &world.solids()[b.solids[0] as usize].shape;
                b.covered(x, dx, (!b.is_cells()).then(|| shape.as_ref())).0
            })
            .sum::<usize>()
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

    /// The metric's axis label: what [`Sample::value`] is, with its unit.
    pub fn metric_axis(&self) -> &'static str {
        match self.probe {
            Probe::DamBreak { .. } => "surge front x, m",
            Probe::Hydrostatic { .. } => "floor force, N",
            Probe::Channel { .. } => "centre-line downward speed, m/s",
            Probe::Bodies => "fluid carriers inside bodies",
            Probe::Tap { .. } => "carriers on the sphere's lower half",
        }
    }

    /// The metric of sample `s`, named and with its unit, for a per-frame line.
    pub fn metric_line(&self, s: &Sample) -> String {
        match self.probe {
            Probe::DamBreak { .. } => {
                format!("front {:.3} m (Z = x/a {:.2})", s.value, s.normalized)
            }
            Probe::Hydrostatic { .. } => {
                format!("floor {:.1} N ({:.4} of the weight)", s.value, s.normalized)
            }
            Probe::Channel { .. } => {
                format!("centre-line {:.3} m/s ({:.3} √(gw))", s.value, s.normalized)
            }
            Probe::Bodies => format!("carriers inside bodies {}", s.value),
            Probe::Tap { .. } => format!(
                "on the sphere's lower half {} ({:.1} %)",
                s.value,
                100.0 * s.normalized
            ),
        }
    }

    /// The run against the scene's reference: Martin & Moyce's front for a dam break, the floor
    /// force and the density for a still tank, Archimedes' drafts of the floating bodies.
    pub(crate) fn compare(&self, metric: &[Sample], drafts: &[Draft]) -> Comparison {
        match self.probe {
            Probe::DamBreak { a } => dam_break_comparison(metric, a),
            Probe::Hydrostatic { height, .. } => {
                let t_end = metric.last().map(|s| s.t).unwrap_or(0.0);
                let tail: Vec<f64> = metric
                    .iter()
                    .filter(|s| s.t >= t_end - 0.2)
                    .map(|s| s.normalized)
                    .collect();
                let mean = tail.iter().sum::<f64>() / tail.len().max(1) as f64;
                let rep = self.world.last_report();
                let vmax = rep.max_speed as f64 / (G as f64 * height as f64).sqrt();
                Comparison {
                    reference: "hydrostatics: the floor carries the water's weight, at rest density"
                        .into(),
                    columns: ["quantity", "simulated", "exact"].map(String::from).to_vec(),
                    rows: vec![
                        vec!["floor force / weight (last 0.2 s)".into(), format!("{mean:.4}"), "1".into()],
                        vec![
                            "mean compression of the inner carriers, %".into(),
                            format!("{:.3}", 100.0 * rep.compression_mean),
                            "0".into(),
                        ],
                        vec!["largest speed / √(gH)".into(), format!("{vmax:.4}"), "0".into()],
                    ],
                    verdict: format!(
                        "floor carries {mean:.3} of the weight (within {:.1} %); water {:.3} % compressed",
                        100.0 * (mean - 1.0).abs(),
                        100.0 * rep.compression_mean
                    ),
                    values: serde_json::json!({"floor_force_over_weight_last_0.2s": mean,
                        "mean_compression": rep.compression_mean,
                        "max_speed_over_sqrt_gH": vmax}),
                }
            }
            Probe::Channel { width } => {
                let prof = channel_profile(&self.world, width, 9);
                Comparison {
                    reference: "the velocity profile across the channel (no reference)".into(),
                    columns: ["x / width", "downward speed, m/s"]
                        .map(String::from)
                        .to_vec(),
                    rows: prof
                        .iter()
                        .enumerate()
                        .map(|(k, v)| {
                            vec![
                                format!("{:.2}", (k as f32 + 0.5) / 9.0),
                                format!("{:.4}", -v),
                            ]
                        })
                        .collect(),
                    verdict: format!("centre-line speed {:.3} m/s", -prof[4]),
                    values: serde_json::json!({"profile_m_per_s": prof}),
                }
            }
            Probe::Bodies => drafts_comparison(metric, drafts),
            Probe::Tap { .. } => {
                let t_end = metric.last().map(|s| s.t).unwrap_or(0.0);
                let tail: Vec<f64> = metric
                    .iter()
                    .filter(|s| s.t >= 0.5 * t_end)
                    .map(|s| s.normalized)
                    .collect();
                let share = tail.iter().sum::<f64>() / tail.len().max(1) as f64;
                Comparison {
                    reference: "He 2012 Fig. 13: water leaves a no-stick sphere, wraps a sticky one"
                        .into(),
                    columns: Vec::new(),
                    rows: Vec::new(),
                    verdict: format!(
                        "{:.1} % of the water on the sphere is on its lower half (second half of the run)",
                        100.0 * share
                    ),
                    values: serde_json::json!({"lower_half_share_of_wetting_fluid_second_half": share}),
                }
            }
        }
    }

    /// The tracked bodies that float (density below the fluid's) and whose draft Archimedes
    /// gives in closed form (a ball; an upright box), with their draft below the far-field
    /// waterline now. Empty for scenes without such bodies.
    pub(crate) fn drafts_now(&self) -> Vec<Draft> {
        let Some(ph) = &self.physics else {
            return Vec::new();
        };
        let rest = self.world.params().rest_density as f64;
        let mut out = Vec::new();
        let mut centres = Vec::new();
        let mut reach = 0.0f32;
        for (name, h) in &self.tracked {
            let Some(rb) = ph.bodies.get(*h) else {
                continue;
            };
            let [c] = rb.colliders() else { continue };
            let Some(co) = ph.colliders.get(*c) else {
                continue;
            };
            let shape = co.shape();
            let volume = shape.mass_properties(1.0).mass() as f64;
            let density = rb.mass() as f64 / volume.max(1e-12);
            if !rb.is_dynamic() || density >= 0.995 * rest {
                continue;
            }
            let up = rb.rotation() * crate::math::Vector::Y;
            let (archimedes, lowest) = if let Some(b) = shape.as_ball() {
                (
                    crate::metrics::sphere_draft(b.radius as f64, density / rest),
                    rb.translation().y - b.radius,
                )
            } else if let Some(c) = shape.as_cuboid().filter(|_| up.y > 0.999) {
                (
                    2.0 * c.half_extents.y as f64 * density / rest,
                    rb.translation().y - c.half_extents.y,
                )
            } else {
                continue;
            };
            let aabb = co.compute_aabb();
            reach = reach.max(0.5 * (aabb.maxs.x - aabb.mins.x).max(aabb.maxs.z - aabb.mins.z));
            centres.push(rb.translation());
            out.push(Draft {
                body: name.clone(),
                density,
                draft: lowest as f64,
                archimedes,
            });
        }
        let dx = self.world.params().spacing;
        let Some(level) = crate::metrics::waterline(
            self.world.fluid().x.iter().copied(),
            &centres,
            reach + 2.0 * dx,
            dx,
        ) else {
            return Vec::new();
        };
        for d in out.iter_mut() {
            d.draft = level as f64 - d.draft;
        }
        out
    }
}

/// A floating body's draft against Archimedes'.
#[derive(Debug, Clone, Serialize)]
pub struct Draft {
    /// The body's name in the scene.
    pub body: String,
    /// Its density, kg/m³.
    pub density: f64,
    /// Depth of its lowest point below the far-field waterline, m (mean over the samples).
    pub draft: f64,
    /// Archimedes' draft, m.
    pub archimedes: f64,
}

/// A run against its scene's reference, as a table and one line (`Display` prints both as
/// plain text).
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// What the run is compared with.
    pub reference: String,
    /// Column headers, with units.
    pub columns: Vec<String>,
    /// The table's rows, formatted.
    pub rows: Vec<Vec<String>>,
    /// The result against the reference, in one line.
    pub verdict: String,
    /// The same figures for programs.
    pub values: serde_json::Value,
}

impl std::fmt::Display for Comparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(f, "against {}:", self.reference)?;
        if !self.rows.is_empty() {
            writeln!(f, "{}", self.columns.join(" | "))?;
            for r in &self.rows {
                writeln!(f, "{}", r.join(" | "))?;
            }
        }
        write!(f, "result: {}", self.verdict)
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

/// A dam break's front against Martin & Moyce 1952 (column width `a`).
fn dam_break_comparison(metric: &[Sample], a: f32) -> Comparison {
    let scale = (2.0 * G as f64 / a as f64).sqrt();
    let mut rows = Vec::new();
    let mut json = Vec::new();
    let mut worst = 0.0f64;
    for (tt, z) in martin_moyce_front() {
        let Some(z_sim) = interpolate(metric, tt / scale) else {
            continue;
        };
        let err = (z_sim - z) / z;
        worst = worst.max(err.abs());
        rows.push(vec![
            format!("{tt:.2}"),
            format!("{:.3}", tt / scale),
            format!("{z:.2}"),
            format!("{z_sim:.2}"),
            format!("{:+.1}", 100.0 * err),
        ]);
        json.push(
            serde_json::json!({"T": tt, "Z_reference": z, "Z_simulated": z_sim,
            "relative_error": err}),
        );
    }
    Comparison {
        reference: "Martin & Moyce 1952, n² = 2 (Table 2)".into(),
        columns: [
            "T = t√(2g/a)",
            "t, s",
            "Z reference",
            "Z simulated",
            "error, %",
        ]
        .map(String::from)
        .to_vec(),
        verdict: if rows.is_empty() {
            "the run ended before Martin & Moyce's first tabulated time".into()
        } else {
            format!(
                "surge front within {:.1} % of Martin & Moyce at {} tabulated times",
                100.0 * worst,
                rows.len()
            )
        },
        rows,
        values: serde_json::json!({"front": json, "largest_relative_error": worst}),
    }
}

/// The floating bodies' drafts against Archimedes, and the most carriers found inside bodies.
fn drafts_comparison(metric: &[Sample], drafts: &[Draft]) -> Comparison {
    let worst = metric.iter().map(|s| s.value).fold(0.0, f64::max);
    let inside = format!(
        "{} fluid carriers inside a body at the end of a step, at most",
        worst
    );
    let rows: Vec<Vec<String>> = drafts
        .iter()
        .map(|d| {
            vec![
                d.body.clone(),
                format!("{:.0}", d.density),
                format!("{:.1}", 1e3 * d.draft),
                format!("{:.1}", 1e3 * d.archimedes),
                format!("{:+.1}", 100.0 * (d.draft / d.archimedes - 1.0)),
            ]
        })
        .collect();
    let verdict = if drafts.is_empty() {
        inside
    } else {
        let worst_draft = drafts
            .iter()
            .map(|d| (d.draft / d.archimedes - 1.0).abs())
            .fold(0.0, f64::max);
        format!(
            "floating bodies' drafts within {:.1} % of Archimedes (mean over the last quarter of the run); {inside}",
            100.0 * worst_draft
        )
    };
    Comparison {
        reference: "Archimedes: a floating body displaces its own mass of water".into(),
        columns: [
            "body",
            "density, kg/m³",
            "draft, mm",
            "Archimedes, mm",
            "error, %",
        ]
        .map(String::from)
        .to_vec(),
        rows,
        verdict,
        values: serde_json::json!({"most_carriers_inside_bodies_at_a_step_end": worst,
            "drafts": drafts}),
    }
}
