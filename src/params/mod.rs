//! Simulation parameters (He 2012 §7): spacing, support radius, densities, viscosity, solver
//! tolerances. Every tolerance states its unit in its doc.

#[cfg(feature = "scenes")]
use crate::error::{FluidError, Result};
use serde::{Deserialize, Serialize};

pub use crate::choices::{Krylov, Preconditioner, Remap, Solver};

mod validate;

/// Global parameters of a [`crate::FluidWorld`].
///
/// ```
/// use staggered_fluid::FluidParams;
/// let p = FluidParams { spacing: 0.02, ..Default::default() };
/// assert!(p.validate().is_ok());
/// assert!(FluidParams { spacing: 0.0, ..p }.validate().is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FluidParams {
    /// Particle spacing Δx in metres; fluid carriers have mass `rest_density · Δx³`.
    pub spacing: f32,
    /// Kernel support radius as a multiple of the spacing (2.0 ⇒ about 26 neighbours).
    pub support_factor: f32,
    /// Rest density ρ̄ of the fluid in kg/m³.
    pub rest_density: f32,
    /// Kinematic viscosity ν of the fluid in m²/s (Eq. 24).
    pub viscosity: f32,
    /// Target incompressibility error E (Eq. 29) of the velocity-constraint solve, as a
    /// fraction (0.01 = 1 %).
    pub density_error_tolerance: f32,
    /// Relative residual reduction `‖r‖₂/‖b‖₂` the PCG solve must also reach. E (Eq. 29) is a
    /// mean over all inner carriers, so a violation confined to a thin layer (fluid landing on a
    /// floor) can sit far below the E tolerance; this second criterion makes the projection act.
    /// Default 0.1 (0.05 until the XSPH default). With the default conjugate residuals: 11.9
    /// iterations at 154k carriers, still tank's largest speed after 2 s 0.84 / 1.25 / 2.02 % of
    /// √(gH) at Δt 1.5 / 2 / 2.5 ms (0.2: 7.3 iterations, 1.05 / 1.29 / 1.94 %), dam-break front
    /// −8.1…+7.9 % at both; E stays near 1e-6. With CG: 16.4 iterations, 1.00 / 1.14 / 2.58 %
    /// (0.05: 21.5 iterations; 0.2: 11.8 iterations, 1.07 / 1.62 / 2.54 %). The solve's vectors
    /// are stored in f32 (sums in f64), so below about 1e-6 the residual stops falling and the
    /// solve runs to [`Self::max_pcg_iterations`].
    pub relative_residual: f32,
    /// Maximum PCG iterations per solve.
    pub max_pcg_iterations: u32,
    /// Preconditioner of the PCG solve.
    pub preconditioner: Preconditioner,
    /// Krylov method of the velocity-constraint solve (default conjugate residuals).
    #[serde(default)]
    pub krylov: Krylov,
    /// SSOR relaxation ω (He 2012 uses 1.7).
    pub ssor_omega: f32,
    /// Rows per SSOR block (fixed, so results do not depend on the thread count).
    pub ssor_block: usize,
    /// Density-constraint iterations (Algorithm 2; the paper uses 3): the minimum.
    pub density_iterations: u32,
    /// Upper bound on density iterations per substep: after [`Self::density_iterations`] the
    /// loop goes on while the inner carriers miss [`Self::density_mean_tolerance`] or
    /// [`Self::density_max_tolerance`] (3 = the paper's fixed iterations).
    #[serde(default = "default_max_density_iterations")]
    pub max_density_iterations: u32,
    /// Iterations of the position-only drift correction that opens each staggered substep
    /// (default 0: off, He 2012 as printed): Algorithm 2's loop on the starting positions from
    /// zero pressure, moving positions only (no velocity, no body impulse, no memory; water
    /// beside deformable bodies left out) while the inner carriers miss the density
    /// tolerances, so compression a step leaves is shifted away instead of kicked (as Hu &
    /// Adams 2007 correct positions). With 3 the Yettou wedge is within 2.3 % (3.1 %) and a
    /// 10 kg/m³ cube spins half as fast, but a floating body loses part of its push (a 500
    /// kg/m³ box 0.3 % deeper) and the still tank's controller settles more slowly: off by
    /// default (`docs/experiments.md`, fourteenth session).
    #[serde(default = "default_drift_iterations")]
    pub drift_iterations: u32,
    /// Pressure memory of the density constraint, as the fraction per substep by which each
    /// carrier's remembered pressure moves toward the p^d it ended the substep with ([0, 1);
    /// 0 = He 2012 Algorithm 2 as printed, p^d rebuilt from zero every substep). Algorithm 2
    /// then starts from the remembered pressure instead of zero, so the hydrostatic load needs
    /// no standing compression to be carried: a 0.3 m still tank at 1/480 / 1/240 s settles
    /// 0.97 / 3.7 % compressed without it and within 0.01–0.04 % with the default 0.03
    /// (`examples/density_vs_dt.rs`). Above about 0.1 the memory overshoots at long steps.
    #[serde(default = "default_density_memory")]
    pub density_memory: f32,
    /// Target mean compression `mean(max(ρ − ρ̄, 0))/ρ̄` of the inner (non-surface) carriers at
    /// the end of a step, fraction (default 0.001 = 0.1 %): reported against in
    /// [`crate::StepReport::density_converged`], and a step that misses it (or
    /// [`Self::density_max_tolerance`]) makes the next steps take shorter substeps.
    #[serde(default = "default_density_mean_tolerance")]
    pub density_mean_tolerance: f32,
    /// Target largest compression of any inner carrier at the end of a step, fraction (default
    /// 0.01 = 1 %); see [`Self::density_mean_tolerance`].
    #[serde(default = "default_density_max_tolerance")]
    pub density_max_tolerance: f32,
    /// Free-surface pressure of the density constraint: a free-surface carrier's p^d is
    /// extrapolated from its inner neighbours' pressure and pressure gradient (where that is
    /// above its EOS value and below its neighbours'), so the surface layer carries its share of
    /// the pressure, as it would half a spacing below the water's end. Without it (`false`, as
    /// printed) the top layer has p = 0, sinks toward the layer beneath, and that layer carries
    /// about two layers' head: in a tank with floating cubes at 1/60 s the pressure reached
    /// zero 0.2–0.24Δx above the waterline (0.05–0.14Δx with it) and the waterline sat
    /// 0.08Δx below the level the fluid's volume gives (within 0.05Δx with it); drafts against
    /// the waterline: five balls −11 → −6 %, cubes 250/500/750 −17/−8/−8 → −13/−6/−6 %.
    #[serde(default = "yes")]
    pub surface_extrapolation: bool,
    /// Wall pressure of the density constraint at static walls (off by default): a carrier of
    /// a static solid (a tank wall, a static collider, a ground) takes the fluid carrier's
    /// pressure carried to it by the momentum balance, `p_s = p_i + ρ̄ (g − a_i)·(x_s − x_i)`
    /// (≥ 0; `a_i` the carrier's acceleration over the last substeps; Adami et al. 2012), and
    /// pushes along the pair like a fluid neighbour. A wall carrier stands for water only as
    /// far as its layer lies under the water beside it (a wall above the waterline borders air:
    /// counted as water it packed the surface water beside it and held the rest of the surface
    /// 5 mm under its pressure's level); ceilings always count. Moving bodies keep Eq. 23's
    /// mirror along their normal (along the pair, the wall pressure has a torque about a
    /// ball's centre: a ball spinning under free slip kept 0.58 of its spin after 1 s instead
    /// of 1.00).
    ///
    /// Off, a wall carrier repeats `p_i` and pushes along its normal: the water beside a
    /// vertical wall gets only part of the pressure gradient that holds it up, a still tank
    /// circulates down its vertical edges (4 cm/s over free-slip walls, largest speed 2.7 % of
    /// √(gH) over no-slip ones), and the five balls' far field carries a pressure gradient
    /// 3.8 % steeper than ρ̄g, which floats them 4.1 / 2.6 % high. On, the edges stand still
    /// (0.2 cm/s), the far field is hydrostatic within 0.6 %, and with
    /// [`Self::surface_rest_density`] too the five balls float within 1 % of Archimedes at
    /// 1/240 s and at rapier's 1/60 s. Not the default because over a free-slip wall the pair
    /// push carries 0.08 % of the water's weight as shear, the wedge brakes 1.7 % past
    /// Wagner's bound, a 10 kg/m³ ball in a no-slip tank rises more slowly and a still tank at
    /// rapier's 1/60 s takes longer to come back to few substeps (docs/experiments.md,
    /// twenty-second session).
    #[serde(default)]
    pub hydrostatic_walls: bool,
    /// A surface rest density in the density constraint (off by default): a free-surface
    /// carrier with an inner fluid neighbour compares its SPH density, which lacks its air
    /// side, with that of a flat rest surface's carrier as exposed as it is (`ρ̄ (1 − m
    /// min(Asy_i/a, 1))`, m ≈ 0.15 and a the flat surface carrier's Eq. 25 asymmetry, both
    /// from the kernel; the asymmetry counts the fluid and the wet solid neighbours). Against
    /// ρ̄ a surface carrier gets no pressure until packed some 15 % closer than the bulk, and
    /// after a splash the surface layer packs. Made for use with [`Self::hydrostatic_walls`]
    /// (alone it leaves the five balls' drafts 3–4 % short: the far field's steep gradient).
    #[serde(default)]
    pub surface_rest_density: bool,
    /// Water placed at rest starts with its hydrostatic pressure (on by default): carriers
    /// added with zero velocity (`add_block`, `add_particles`, the scenes' blocks) get the
    /// density constraint's pressure memory `ρ̄ |g|` times their depth in the column of water
    /// above them, if a solid carrier lies below that column (a block in mid-air keeps 0, as
    /// does water beside a deformable body, whose walls have not yet taken the load). From
    /// zero pressure a tank first falls onto its floor while the memory builds up (a 0.3 m
    /// still tank at rapier's 1/60 s: 1.49× its weight on the floor in the first frame, then
    /// 17–26 substeps a frame); started hydrostatic it carries its weight from the first
    /// frame, the still tank takes 126 substeps in its first 0.5 s at 1/60 s instead of 250,
    /// the five balls at 1/60 s 9.1 instead of 11.4 wall seconds per simulated second (their
    /// floating drafts over 1–2 s −3.1 / −2.9 % of Archimedes instead of −4.5 / −3.7 %, the
    /// same run otherwise; −4.5 / −4.0 % on the thirty-first session's defaults: the drafts
    /// move by about a point with the entry's substep pattern), and the still
    /// tank runs at 8× its step. What the zero start gave that this does not: the Yettou
    /// wedge's match to the measurement leaned on the zero start's rebound (2.9 % mean
    /// deviation from zero, 3.8 % started at rest; docs/experiments.md, twenty-sixth and
    /// thirtieth sessions). `false` starts every carrier's memory at zero (the paper's
    /// Algorithm 2 from p = 0).
    #[serde(default = "yes")]
    pub hydrostatic_start: bool,
    /// Walls that push the density constraint's water as the geometry says (on by default):
    /// the push along the shape's normal at the fluid carrier, and beside walls not square to
    /// gravity the gradient along gravity restored; `false`: Eq. 23 as printed (ARCHITECTURE.md).
    #[serde(default = "yes")]
    pub wall_support: bool,
    /// The density constraint's pressure force scaled at each inner carrier by `3 / tr M_i`,
    /// `M_i = Σ_j V_j (x_j − x_i)(x_j − x_i)ᵀ |∇W_ij| / r_ij` over its fluid and solid
    /// neighbours, so that a linear pressure field gives its own gradient whatever the
    /// carriers' arrangement (on by default; `false`: the symmetric SPH force as printed,
    /// whose still tank settled with its pressure rising 1.0064 ρ̄g with depth). Not in
    /// worlds with deformable bodies.
    #[serde(default = "yes")]
    pub pressure_scale: bool,
    /// Relaxation of the density-constraint pressure (fraction of the PCISPH stiffness, (0, 1]):
    /// a full-stiffness Jacobi-style update does not damp the highest-frequency density mode.
    pub density_relaxation: f32,
    /// Free-surface asymmetry threshold of Eq. 25, as a fraction of the support radius.
    pub surface_asymmetry: f32,
    /// Free-surface density threshold of Eq. 25, as a fraction of the rest density.
    pub surface_density: f32,
    /// Velocity remap rule after the projection.
    pub remap: Remap,
    /// §5.2 no-stick inequality for [`Remap::Consistent`], imposed as an active set (carriers
    /// leaving a wall under suction are released and the system solved again). Off by default:
    /// in a still tank it released about 1 100 of 6 000 carriers per step and doubled the
    /// largest speed, and it moved the dam-break front further from Martin & Moyce
    /// (ARCHITECTURE.md). The approximate-projection remaps always apply it.
    #[serde(default)]
    pub no_stick: bool,
    /// First-order correction `L_i` of the staggered divergence in [`Remap::Consistent`]
    /// (exact for linear velocity fields, so carriers beside walls get their full pressure
    /// support). On by default: dam-break front −2…+9 % of Martin & Moyce with it, −10…+7 %
    /// without; still-tank largest speed 3.1 % vs 4.0 % of √(gH).
    #[serde(default = "yes")]
    pub gradient_correction: bool,
    /// Pressure solver.
    #[serde(default)]
    pub solver: Solver,
    /// Upper bound on PCISPH iterations per substep ([`Solver::Pcisph`]).
    #[serde(default = "default_max_pcisph_iterations")]
    pub max_pcisph_iterations: u32,
    /// XSPH velocity smoothing ε after the velocity constraint (Monaghan 1989; 0 = off;
    /// default 0.1). The consistent projection conserves momentum exactly but, unlike the
    /// paper's Eq. 19 remap, never averages a carrier's velocity with its neighbours', so noise
    /// on free-surface carriers (Dirichlet p^v = 0, no velocity constraint) is not damped.
    /// Measured (still tank, largest speed at 2 s over √(gH)): 0 → 4.8 %, 0.05 → 1.7–2.1 % for
    /// Δt 1.5–2.2 ms, 0.1 → 1.6–2.0 % (1.1–1.5 % with [`Self::xsph_walls`]). The price is a
    /// numerical viscosity of order ε h |v|: the dam-break front against Martin & Moyce is
    /// −8.4…+8.0 % at 30 carriers across and −5.8…+9.1 % at 40 with ε = 0.1 (+0.3…+10.4 % and
    /// up to +11.8 % without), but falls 12 % behind at 20 across by T = 3.1 (−2.8…+6.9 %
    /// without).
    #[serde(default = "default_xsph")]
    pub xsph: f32,
    /// XSPH also averages with the velocity of solid neighbours, weighted by their relative
    /// volume: the whole relative velocity against no-slip walls, its normal part against
    /// others; the momentum it takes goes to the solid (default on). Measured on the still
    /// tank (largest speed after 2 s over √(gH), `xsph` 0.1): 1.38 / 1.26 / 1.10 / 1.29 / 1.53 /
    /// 2.10 / 1.96 % at Δt = 1 / 1.5 / 1.8 / 2 / 2.2 / 2.5 / 3 ms, against 1.64–1.98 % without
    /// the wall term and 4.8 % with no smoothing.
    #[serde(default = "yes")]
    pub xsph_walls: bool,
    /// Largest allowed CFL number `v_max·dt/Δx`; longer steps are split into substeps. The
    /// PCISPH solver never goes above `PCISPH_MAX_CFL` (0.1).
    pub max_cfl: f32,
    /// Body-force step limit: `Δt ≤ body_force_limit · √(Δx/|g|)`. A fluid at rest has no
    /// speed for the CFL limit to act on; at 0.15 and 0.2 (default; 9 ms at Δx 2 cm, two
    /// substeps of rapier's 1/60 s frame) a 1/60 s frame at Δx = 1 cm and water 20 carriers
    /// deep under floating cubes stay stable, at 0.25 the latter blew up (before the density
    /// loop relaxed only its spring). Longer steps are split into substeps. The PCISPH
    /// solver never goes above `PCISPH_BODY_FORCE_LIMIT` (0.05), a world with deformable
    /// bodies above 0.15.
    #[serde(default = "default_body_force_limit")]
    pub body_force_limit: f32,
    /// Largest stiffness `μ = 6.1 p Δt² / (ρ̄ Δx²)` of the staggered density loop's pressure
    /// spring (a carrier's oscillation about the middle of its neighbours under the bulk's
    /// pressure `p`): a substep limit, and the floor `1.5/(1 + μ)` of the share of the spring
    /// the predicted positions follow, so that the iterations halve the spring's error each
    /// (default 4: a 0.3 m deep tank at Δx 2 cm takes about 8.3 ms substeps, two to rapier's
    /// 1/60 s frame). Only the spring is relaxed, not the pressure's increment, so the
    /// density's own error still falls at the unrelaxed rate; with the whole force relaxed
    /// (before the thirty-seventh session) μ ≤ 2 was needed to meet the default tolerances.
    /// A world with deformable bodies takes at most 2.
    #[serde(default = "default_max_loop_spring")]
    pub max_loop_spring: f32,
    /// Extra neighbour-search radius, as a fraction of the support radius, so that lists built
    /// at the start of a step stay valid while particles move during it.
    pub neighbor_skin: f32,
    /// Simulation domain `(mins, maxs)`; fluid carriers leaving it are removed and counted.
    /// `None`: the bounding box of all solids and fluid at the first step, grown by
    /// [`FluidParams::domain_margin`].
    pub domain: Option<([f32; 3], [f32; 3])>,
    /// Margin added around the automatic domain, in metres; along an axis where solids bound
    /// the fluid on both sides it is at most half the scene's extent there.
    pub domain_margin: f32,
    /// What a step does when a guard below trips: an error (default) or a warning in the
    /// report.
    #[serde(default)]
    pub on_failure: OnFailure,
    /// Largest fraction of the fluid that may leave the domain over a run (carriers removed
    /// outside it over every carrier the world has held; sinks do not count). Default 0.01.
    #[serde(default = "default_max_lost_fraction")]
    pub max_lost_fraction: f32,
    /// Largest fluid speed a step may end with, m/s. Default 100 (a fall of 500 m).
    #[serde(default = "default_max_speed")]
    pub max_speed: f32,
    /// Largest mechanical energy (kinetic, plus potential under gravity, of the fluid and the
    /// dynamic bodies) one step may add, as a fraction of `KE + M |g| Δx` at its start (`M`
    /// the fluid's mass: a spacing of fall is the scale of what the constraints exchange).
    /// Work done by kinematic solids and emitters is not a gain. Default 1.
    #[serde(default = "default_max_energy_gain")]
    pub max_energy_gain: f32,
}

fn default_max_lost_fraction() -> f32 {
    0.01
}
fn default_max_speed() -> f32 {
    100.0
}
fn default_max_energy_gain() -> f32 {
    1.0
}

impl Default for FluidParams {
    fn default() -> Self {
        Self {
            spacing: 0.02,
            support_factor: 2.0,
            rest_density: 1000.0,
            viscosity: 1.0e-6,
            density_error_tolerance: 0.01,
            relative_residual: 0.1,
            max_pcg_iterations: 200,
            preconditioner: Preconditioner::Jacobi,
            krylov: Krylov::ConjugateResidual,
            ssor_omega: 1.7,
            ssor_block: 2048,
            density_iterations: 3,
            max_density_iterations: default_max_density_iterations(),
            drift_iterations: default_drift_iterations(),
            density_memory: default_density_memory(),
            density_mean_tolerance: default_density_mean_tolerance(),
            density_max_tolerance: default_density_max_tolerance(),
            surface_extrapolation: true,
            hydrostatic_walls: false,
            surface_rest_density: false,
            hydrostatic_start: true,
            wall_support: true,
            pressure_scale: true,
            density_relaxation: 0.5,
            surface_asymmetry: 0.05,
            surface_density: 0.9,
            remap: Remap::Consistent,
            no_stick: false,
            gradient_correction: true,
            solver: Solver::Staggered,
            max_pcisph_iterations: default_max_pcisph_iterations(),
            xsph: default_xsph(),
            xsph_walls: true,
            max_cfl: 0.4,
            body_force_limit: default_body_force_limit(),
            max_loop_spring: default_max_loop_spring(),
            neighbor_skin: 0.1,
            domain: None,
            domain_margin: 0.1,
            on_failure: OnFailure::Error,
            max_lost_fraction: default_max_lost_fraction(),
            max_speed: default_max_speed(),
            max_energy_gain: default_max_energy_gain(),
        }
    }
}

fn default_max_pcisph_iterations() -> u32 {
    100
}

fn default_xsph() -> f32 {
    0.1
}

fn yes() -> bool {
    true
}

/// Calls `$m!` with every field of [`FluidParams`] (one list, so the serialiser of changed
/// fields cannot miss one; a test checks it against serde's names).
macro_rules! with_fields {
    ($m:ident) => {
        $m!(
            spacing,
            support_factor,
            rest_density,
            viscosity,
            density_error_tolerance,
            relative_residual,
            max_pcg_iterations,
            preconditioner,
            krylov,
            ssor_omega,
            ssor_block,
            density_iterations,
            max_density_iterations,
            drift_iterations,
            density_memory,
            density_mean_tolerance,
            density_max_tolerance,
            surface_extrapolation,
            hydrostatic_walls,
            surface_rest_density,
            hydrostatic_start,
            wall_support,
            pressure_scale,
            density_relaxation,
            surface_asymmetry,
            surface_density,
            remap,
            no_stick,
            gradient_correction,
            solver,
            max_pcisph_iterations,
            xsph,
            xsph_walls,
            max_cfl,
            body_force_limit,
            max_loop_spring,
            neighbor_skin,
            domain,
            domain_margin,
            on_failure,
            max_lost_fraction,
            max_speed,
            max_energy_gain
        )
    };
}

/// Serialises only the fields of `p` that differ from [`FluidParams::default`] (a scene file
/// names what it changes; missing fields read back as the defaults).
#[cfg(feature = "scenes")]
pub(crate) fn serialize_changed<S: serde::Serializer>(
    p: &FluidParams,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeStruct;
    let d = FluidParams::default();
    macro_rules! changed {
        ($($f:ident),*) => {{
            let n = 0 $(+ (p.$f != d.$f) as usize)*;
            let mut st = s.serialize_struct("FluidParams", n)?;
            $(
                if p.$f != d.$f {
                    st.serialize_field(stringify!($f), &p.$f)?;
                }
            )*
            st.end()
        }};
    }
    with_fields!(changed)
}

pub(crate) use crate::limits::check_count;
pub use crate::limits::{
    OnFailure, MAX_CELLS, MAX_ITERATIONS, MAX_LENGTH, MAX_PARTICLES, MAX_SPEED,
    MIN_BODY_DENSITY_RATIO, MIN_BODY_DENSITY_RATIO_NO_SLIP,
};

impl FluidParams {
    /// Whether every field has its default value.
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// The names of the fields that differ from the defaults.
    ///
    /// ```
    /// use staggered_fluid::FluidParams;
    /// let p = FluidParams { spacing: 0.01, xsph: 0.0, ..Default::default() };
    /// assert_eq!(p.changed_fields(), ["spacing", "xsph"]);
    /// ```
    pub fn changed_fields(&self) -> Vec<&'static str> {
        let d = Self::default();
        let mut out = Vec::new();
        macro_rules! names {
            ($($f:ident),*) => {
                $(
                    if self.$f != d.$f {
                        out.push(stringify!($f));
                    }
                )*
            };
        }
        with_fields!(names);
        out
    }

    /// [`Self::with_json_overrides`] with the JSON object in the environment variable `var`,
    /// or these parameters unchanged when it is not set (for diagnostics and examples:
    /// `PARAMS='{"density_iterations": 5}' cargo run --example …`). Needs the `scenes`
    /// feature (on by default).
    #[cfg(feature = "scenes")]
    pub fn with_env_overrides(&self, var: &str) -> Result<FluidParams> {
        match std::env::var(var) {
            Ok(json) => self.with_json_overrides(&json),
            Err(_) => Ok(self.clone()),
        }
    }

    /// These parameters with the fields of the JSON object `json` replaced, validated.
    ///
    /// ```
    /// use staggered_fluid::FluidParams;
    /// let p = FluidParams::default().with_json_overrides(r#"{"spacing": 0.01}"#).unwrap();
    /// assert_eq!(p.spacing, 0.01);
    /// assert!(FluidParams::default().with_json_overrides(r#"{"spacing": -1}"#).is_err());
    /// assert!(FluidParams::default().with_json_overrides("[1]").is_err());
    /// ```
    #[cfg(feature = "scenes")]
    pub fn with_json_overrides(&self, json: &str) -> Result<FluidParams> {
        let bad = |e: String| FluidError::BadParams(e);
        let mut v = serde_json::to_value(self).map_err(|e| bad(e.to_string()))?;
        let o: serde_json::Value = serde_json::from_str(json).map_err(|e| bad(e.to_string()))?;
        let o = o
            .as_object()
            .ok_or_else(|| bad(format!("expected a JSON object, got `{json}`")))?;
        for (k, x) in o {
            if v.get(k).is_none() {
                return Err(bad(format!("unknown field `{k}`")));
            }
            v[k] = x.clone();
        }
        let p: FluidParams = serde_json::from_value(v).map_err(|e| bad(e.to_string()))?;
        p.validate()?;
        Ok(p)
    }

    /// Support radius `h` of the kernel in metres.
    pub fn support_radius(&self) -> f32 {
        self.spacing * self.support_factor
    }

    /// Mass of one fluid carrier, `ρ̄ Δx³`.
    pub fn particle_mass(&self) -> f32 {
        self.rest_density * self.spacing.powi(3)
    }
}

fn default_body_force_limit() -> f32 {
    0.2
}

fn default_max_loop_spring() -> f32 {
    4.0
}

fn default_density_mean_tolerance() -> f32 {
    0.001
}
fn default_density_max_tolerance() -> f32 {
    0.01
}
fn default_density_memory() -> f32 {
    0.03
}
fn default_drift_iterations() -> u32 {
    0
}
fn default_max_density_iterations() -> u32 {
    // iterations beyond `density_iterations` run only while the tolerances are missed; past
    // this the step's substeps are raised instead (FluidWorld::adapt_density_substeps)
    8
}
