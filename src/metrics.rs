//! Per-step report (He 2012 §7): incompressibility error E (Eq. 29), PCG iterations, particle
//! counts and seconds per stage as in Table 3.

use serde::{Deserialize, Serialize};

/// Wall-clock seconds spent in each stage of a step (He 2012 Table 3 columns).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct StageTimes {
    /// Domain culling, sorting by cell and neighbour lists (t_neighbor).
    pub neighbors: f64,
    /// Body and viscous forces, prediction, density constraint (t_{p^d}).
    pub density: f64,
    /// Free-surface detection and isolated regions (t_surface).
    pub surface: f64,
    /// Staggered-particle creation: densities, counts N_i and shares (t_creating).
    pub staggered: f64,
    /// Assembly of Eq. 13 with the wall conditions (t_assemble).
    pub assembly: f64,
    /// PCG solve (t_solving).
    pub solve: f64,
    /// Remap, reductions and bookkeeping.
    pub other: f64,
    /// Deformable bodies (Shao §3.4): shape matching, placing their SBPs, sharing their
    /// impulses, heat exchange and melting.
    #[serde(default)]
    pub deformable: f64,
}

impl StageTimes {
    /// Sum of all stages.
    pub fn total(&self) -> f64 {
        self.neighbors
            + self.density
            + self.surface
            + self.staggered
            + self.assembly
            + self.solve
            + self.other
            + self.deformable
    }

    /// Adds `o` stage by stage.
    pub fn add(&mut self, o: &StageTimes) {
        self.neighbors += o.neighbors;
        self.density += o.density;
        self.surface += o.surface;
        self.staggered += o.staggered;
        self.assembly += o.assembly;
        self.solve += o.solve;
        self.other += o.other;
        self.deformable += o.deformable;
    }
}

fn yes() -> bool {
    true
}

/// What one call of [`crate::FluidWorld::step`] did.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct StepReport {
    /// Number of completed calls of `step` (this one included).
    pub step: u64,
    /// Simulated time at the end of the step, seconds.
    pub time: f64,
    /// Requested step length, seconds.
    pub dt: f64,
    /// Substeps the step was split into (CFL / viscosity limits).
    pub substeps: u32,
    /// Fluid carriers.
    pub n_fluid: usize,
    /// Solid carriers.
    pub n_solid: usize,
    /// Fluid carriers flagged as free surface (Eq. 25) in the last substep.
    pub n_surface: usize,
    /// Unknowns of the Poisson system in the last substep.
    pub n_unknown: usize,
    /// Directed neighbour pairs in the last substep.
    pub n_pairs: usize,
    /// PCG iterations, summed over substeps.
    pub pcg_iterations: u32,
    /// Density-constraint (or PCISPH) iterations, summed over substeps.
    #[serde(default)]
    pub density_iterations: u32,
    /// Iterations of the position-only drift correction summed over the substeps
    /// ([`crate::FluidParams::drift_iterations`]).
    #[serde(default)]
    pub drift_iterations: u32,
    /// Incompressibility error E (Eq. 29, fraction) after the solve, worst substep.
    pub error: f64,
    /// E before the solve (of the warm start), worst substep.
    pub initial_error: f64,
    /// Whether every solve reached the tolerance.
    pub converged: bool,
    /// Mean relative density deviation |ρ−ρ̄|/ρ̄ of the inner (non-surface) carriers at the end
    /// of the last substep (SPH density, Eq. 22).
    pub density_deviation: f64,
    /// Mean compression `max(ρ − ρ̄, 0)/ρ̄` of the inner carriers at the end of the step (SPH
    /// density), worst substep, as a fraction: what
    /// [`crate::FluidParams::density_mean_tolerance`] bounds. E measures the velocity's
    /// divergence; this measures the density itself.
    #[serde(default)]
    pub compression_mean: f64,
    /// Largest compression of any inner carrier at the end of a substep, fraction (what
    /// [`crate::FluidParams::density_max_tolerance`] bounds).
    #[serde(default)]
    pub compression_max: f64,
    /// Whether the end of every substep met [`crate::FluidParams::density_mean_tolerance`] and
    /// [`crate::FluidParams::density_max_tolerance`].
    #[serde(default = "yes")]
    pub density_converged: bool,
    /// Largest fluid speed at the end of the step, m/s.
    pub max_speed: f32,
    /// Fluid carriers removed this step because they left the domain.
    pub removed_outside: u64,
    /// Fluid carriers found inside a solid and moved back to its surface (summed over
    /// substeps).
    pub penetrations_corrected: u64,
    /// Fluid carriers that crossed a cloth within a substep, or ended inside it, and were put
    /// back on the side they came from (summed over substeps; see
    /// [`crate::FluidWorld::add_cloth`]).
    #[serde(default)]
    pub cloth_corrections: u64,
    /// Faces of dynamic bodies resting on a wall with no water between them that took the
    /// water column's pressure (summed over substeps; see `step/sealed.rs`).
    #[serde(default)]
    pub sealed_faces: u64,
    /// Coupled solids dropped because their rapier collider or body was removed.
    pub solids_dropped: u64,
    /// Lattice points of melting bodies that turned into water this step ([`crate::deform`]).
    #[serde(default)]
    pub melted: u64,
    /// Fluid carriers made from melted lattice points this step.
    #[serde(default)]
    pub melt_carriers: u64,
    /// Jacobi sweeps of this step's heat exchange (Eq. 20; 0 without heat).
    #[serde(default)]
    pub heat_sweeps: u32,
    /// Seconds per stage, summed over substeps.
    pub stages: StageTimes,
    /// Mechanical energy the step added (J): kinetic plus potential under gravity, of the
    /// fluid and the dynamic bodies, end minus start, the carriers removed outside the domain
    /// counted at removal. Negative when the step dissipated (what the constraints do).
    #[serde(default)]
    pub energy_gain: f64,
    /// Failure guards tripped with [`crate::OnFailure::Warn`] (empty otherwise: with
    /// [`crate::OnFailure::Error`] the step returns the failure instead).
    #[serde(default)]
    pub warnings: Vec<String>,
}

/// Far-field water level (y up): the median, over the vertical columns of width `dx` whose
/// centre lies farther than `keep_out` (horizontally) from every point of `avoid`, of the
/// highest of `points` in the column, plus `dx / 2` (a carrier stands for a cube of side Δx).
/// The median ignores the few columns that hold a droplet. `None` when no column qualifies.
///
/// Whole columns are kept or dropped by their centre: testing each point instead keeps the
/// deep carriers of a column cut by the circle and reads the level far too low.
///
/// ```
/// use staggered_fluid::metrics::waterline;
/// use staggered_fluid::math::Vector;
/// // a 10 × 5 × 10 block of carriers at Δx = 0.1, its top row at y = 0.45: level 0.5
/// let dx = 0.1f32;
/// let mut x = Vec::new();
/// for i in 0..10 {
///     for j in 0..5 {
///         for k in 0..10 {
///             x.push(Vector::new(i as f32 + 0.5, j as f32 + 0.5, k as f32 + 0.5) * dx);
///         }
///     }
/// }
/// // a body at the block's centre: its columns are left out
/// let level = waterline(x.iter().copied(), &[Vector::new(0.5, 0.6, 0.5)], 0.2, dx).unwrap();
/// assert!((level - 0.5).abs() < 1e-6);
/// assert!(waterline(x.iter().copied(), &[Vector::new(0.5, 0.6, 0.5)], 2.0, dx).is_none());
/// ```
pub fn waterline(
    points: impl IntoIterator<Item = crate::math::Vector>,
    avoid: &[crate::math::Vector],
    keep_out: f32,
    dx: f32,
) -> Option<f32> {
    let mut tops = std::collections::HashMap::new();
    for x in points {
        let key = ((x.x / dx).floor() as i64, (x.z / dx).floor() as i64);
        let (cx, cz) = ((key.0 as f32 + 0.5) * dx, (key.1 as f32 + 0.5) * dx);
        if avoid.iter().all(|c| (cx - c.x).hypot(cz - c.z) > keep_out) {
            let top = tops.entry(key).or_insert(f32::NEG_INFINITY);
            *top = top.max(x.y);
        }
    }
    let mut ys: Vec<f32> = tops.into_values().collect();
    ys.sort_by(f32::total_cmp);
    ys.get(ys.len() / 2).map(|y| y + 0.5 * dx)
}

/// Archimedes' draft `h` of a floating sphere of radius `r` and relative density `s` (body
/// over fluid density, `0 ≤ s ≤ 1`): the submerged cap `π h² (3r − h)/3` holds `s` times the
/// sphere's volume (bisection on `h ∈ [0, 2r]`).
///
/// ```
/// use staggered_fluid::metrics::sphere_draft;
/// assert!((sphere_draft(0.06, 0.5) - 0.06).abs() < 1e-12); // half density: half submerged
/// assert!((sphere_draft(0.06, 0.55) * 1e3 - 64.0).abs() < 0.05);
/// ```
pub fn sphere_draft(r: f64, s: f64) -> f64 {
    let target = s * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let (mut lo, mut hi) = (0.0, 2.0 * r);
    for _ in 0..60 {
        let h = 0.5 * (lo + hi);
        if std::f64::consts::PI * h * h * (3.0 * r - h) / 3.0 < target {
            lo = h;
        } else {
            hi = h;
        }
    }
    0.5 * (lo + hi)
}

/// A least-squares line `p = ρ_eff g (zero − y)` through pressure samples against height.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HydrostaticFit {
    /// `−dp/dy`, Pa/m: ρ̄g (9 810 for water) in water at rest.
    pub gradient: f64,
    /// Height where the fitted pressure is zero, m: the free surface, where the water ends.
    pub zero_level: f64,
    /// Samples fitted.
    pub samples: usize,
}

/// Fits `p = a + b y` to `(height, pressure)` samples (e.g. the inner carriers' `p^d + p^v`
/// away from walls and bodies); `None` with fewer than two distinct heights or a flat
/// pressure.
///
/// ```
/// use staggered_fluid::metrics::hydrostatic_fit;
/// let f = hydrostatic_fit((0..10).map(|k| (0.1 * k as f64, 9810.0 * (2.0 - 0.1 * k as f64)))).unwrap();
/// assert!((f.gradient - 9810.0).abs() < 1e-6 && (f.zero_level - 2.0).abs() < 1e-9);
/// ```
pub fn hydrostatic_fit(samples: impl IntoIterator<Item = (f64, f64)>) -> Option<HydrostaticFit> {
    let (mut n, mut sy, mut sp, mut syy, mut syp) = (0usize, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (y, p) in samples {
        n += 1;
        sy += y;
        sp += p;
        syy += y * y;
        syp += y * p;
    }
    let m = n as f64;
    let det = m * syy - sy * sy;
    if n < 2 || det.abs() <= f64::EPSILON * m * syy.abs() {
        return None;
    }
    let b = (m * syp - sy * sp) / det;
    let a = (sp - b * sy) / m;
    (b != 0.0).then(|| HydrostaticFit {
        gradient: -b,
        zero_level: -a / b,
        samples: n,
    })
}
