//! The solver choices among [`crate::FluidParams`]' fields: which pressure solver, the Krylov
//! method and preconditioner of the velocity constraint, and the remap after it.

use serde::{Deserialize, Serialize};

/// Preconditioner of the conjugate-gradient solve of the velocity constraint (He 2012 §7.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Preconditioner {
    /// Block SSOR with ω = [`crate::FluidParams::ssor_omega`]: symmetric Gauss–Seidel sweeps inside
    /// fixed blocks of consecutive (cell-sorted) particles, so blocks run in parallel and the
    /// result does not depend on the thread count.
    BlockSsor,
    /// Plain diagonal (Jacobi) preconditioning: the default, because on 2 cores it reached the
    /// tolerance in half the wall time of block SSOR (BENCHMARKS.md).
    #[default]
    Jacobi,
    /// No preconditioning (plain CG), for comparison.
    None,
}

/// Krylov method of the velocity-constraint solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Krylov {
    /// Preconditioned conjugate residuals (Saad 2003, Alg. 6.20 with the preconditioner): the
    /// default. Same cost per iteration as CG (one operator application), but each iterate
    /// minimises the (preconditioned) residual, which is what the stopping rule
    /// ([`crate::FluidParams::relative_residual`]) measures; CG minimises the energy norm, and its
    /// residual rose and stalled on the way. 154k dam break: 11–12 iterations instead of 15–16.
    #[default]
    ConjugateResidual,
    /// Preconditioned conjugate gradients, as in He 2012 §7.1.
    ConjugateGradient,
}

/// Which pressure solver a [`crate::FluidWorld`] runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Solver {
    /// He et al. 2012: density constraint, then the velocity constraint (approximate
    /// projection on staggered particles, PCG) with wall conditions.
    #[default]
    Staggered,
    /// PCISPH (Solenthaler & Pajarola 2009) with Akinci-weighted boundary carriers and the
    /// velocity–position correction of Shao et al. 2014 (Eqs. 5–7, 11–17): the density
    /// iterations run until the mean compression is below
    /// [`crate::FluidParams::density_error_tolerance`], and no velocity constraint follows.
    Pcisph,
}

/// How carrier velocities are recovered from staggered velocities after the projection.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Remap {
    /// He 2012 Eq. 19 as printed: the mean of the staggered velocity changes. Not momentum
    /// conserving: the fluid–fluid staggered pairs create net momentum that no wall receives.
    Paper,
    /// Eq. 19 with the first-order direction correction `B_i⁻¹`, `B_i = (1/N_i) Σ n_ij n_ijᵀ`:
    /// each staggered particle only carries the pair-normal component of the pressure gradient,
    /// so in 3-D the plain mean recovers about one third of it; `B_i⁻¹` restores it. Not
    /// momentum conserving either.
    Corrected,
    /// Wall pairs as Eq. 19; the pressure part applied as the generalized pressure force of
    /// Eq. 23 with p^v (antisymmetric fluid pairs, mirrored wall pressure): conserves momentum
    /// exactly, but p^v solved from Eq. 13 overshoots where few fluid neighbours meet many wall
    /// carriers (tank edges), and a fluid at rest there goes unstable.
    Conservative,
    /// The default: the consistent projection (ARCHITECTURE.md, stages 6–8). The Poisson
    /// operator is `D M⁻¹ Dᵀ` built from Eq. 10's staggered divergence, and p^v acts through
    /// its exact adjoint. Momentum is conserved, walls feel the pressure, and the projection
    /// never adds kinetic energy. Eq. 13's compact matrix stays as the SSOR preconditioner.
    #[default]
    Consistent,
}
