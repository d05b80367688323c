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
    }
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
    /// Incompressibility error E (Eq. 29, fraction) after the solve, worst substep.
    pub error: f64,
    /// E before the solve (of the warm start), worst substep.
    pub initial_error: f64,
    /// Whether every solve reached the tolerance.
    pub converged: bool,
    /// Mean relative density deviation |ρ−ρ̄|/ρ̄ of inner carriers after the density constraint.
    pub density_deviation: f64,
    /// Largest fluid speed at the end of the step, m/s.
    pub max_speed: f32,
    /// Fluid carriers removed this step because they left the domain.
    pub removed_outside: u64,
    /// Fluid carriers found inside a solid and moved back to its surface (summed over
    /// substeps).
    pub penetrations_corrected: u64,
    /// Coupled solids dropped because their rapier collider or body was removed.
    pub solids_dropped: u64,
    /// Seconds per stage, summed over substeps.
    pub stages: StageTimes,
}
