//! He 2012 Algorithm 1, one stage per module:
//! [`forces`] (body + generalized viscous force, Eq. 24) → prediction → [`density`]
//! (Algorithm 2, Eqs. 22–23) → [`surface`] (Eq. 25) → [`projection`] (staggered particles,
//! wall conditions, Eq. 13 assembly, remap Eq. 19) → [`pcg`] (SSOR-preconditioned CG).

pub mod contact;
pub mod density;
pub mod forces;
pub mod pcg;
pub mod projection;
pub mod staggered;
pub mod surface;
pub mod velocity;
pub mod weights;

use crate::kernel::CubicSpline;
use crate::math::Vector;
use crate::neighbors::NeighborLists;
use rayon::prelude::*;
use staggered::{Share, Slip};

/// Rows per parallel work item; a fixed size keeps reductions independent of the thread count.
pub(crate) const ROWS: usize = 1024;

/// Per-solid data every stage needs.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BodyView {
    /// The solid's share in its staggered particles (static: a fluid carrier's; dynamic: the
    /// whole body's mass over its fluid-neighbour count, §4.1).
    pub share: Share,
    /// Wall viscosity μ^s.
    pub viscosity: f32,
    pub slip: Slip,
    pub stick: bool,
    /// Centre of mass (torque reference, Eq. 21).
    pub com: Vector,
    /// Index of the moving dynamic body it belongs to, `u32::MAX` if none (its velocity is then
    /// fixed during the velocity constraint).
    pub rigid: u32,
}

/// Read-only view of everything a stage needs.
pub(crate) struct Ctx<'a> {
    pub kernel: CubicSpline,
    /// Fluid carrier mass.
    pub mass: f32,
    pub rest_density: f32,
    /// Lattice normalisation of the density sum (see [`CubicSpline::lattice_sum`]).
    pub kernel_norm: f32,
    pub viscosity: f32,
    pub lists: &'a NeighborLists,
    pub solid_x: &'a [Vector],
    pub solid_n: &'a [Vector],
    /// Relative volume of each solid carrier (see `SolidCarriers::volume`).
    pub solid_volume: &'a [f32],
    pub solid_u: &'a [Vector],
    pub solid_body: &'a [u32],
    pub bodies: &'a [BodyView],
}

impl Ctx<'_> {
    /// Number of fluid carriers the lists were built for.
    #[inline]
    pub fn n_fluid(&self) -> usize {
        self.lists.offsets.len() - 1
    }
}

/// Impulses on solid carriers, `(solid carrier index, impulse N·s)`, in a fixed order. Summed
/// per carrier and then per body (Eq. 21) by [`crate::FluidWorld`].
pub(crate) type Impulses = Vec<(u32, Vector)>;

/// Per-chunk impulse collector.
pub(crate) struct Acc(pub Impulses);

impl Acc {
    /// Impulse `j` on solid carrier `s`.
    #[inline]
    pub fn add(&mut self, s: usize, j: Vector) {
        self.0.push((s as u32, j));
    }
}

/// Runs `f(i, &mut out[i], acc)` over all rows in parallel and returns the impulses on solid
/// carriers, concatenated in row order (deterministic whatever the thread count).
pub(crate) fn for_rows<T: Send>(
    out: &mut [T],
    f: impl Fn(usize, &mut T, &mut Acc) + Sync,
) -> Impulses {
    let parts: Vec<Acc> = out
        .par_chunks_mut(ROWS)
        .enumerate()
        .map(|(c, chunk)| {
            let mut acc = Acc(Vec::new());
            for (k, o) in chunk.iter_mut().enumerate() {
                f(c * ROWS + k, o, &mut acc);
            }
            acc
        })
        .collect();
    let mut total = Vec::with_capacity(parts.iter().map(|p| p.0.len()).sum());
    for p in parts {
        total.extend(p.0);
    }
    total
}

/// Splits per-slot data into one mutable slice per block of [`ROWS`] rows.
pub(crate) fn row_blocks<'a, T>(offsets: &[u32], mut data: &'a mut [T]) -> Vec<&'a mut [T]> {
    let n = offsets.len() - 1;
    let mut out = Vec::with_capacity(n.div_ceil(ROWS));
    let mut start = 0usize;
    while start < n {
        let end = (start + ROWS).min(n);
        let len = (offsets[end] - offsets[start]) as usize;
        let (a, b) = data.split_at_mut(len);
        out.push(a);
        data = b;
        start = end;
    }
    out
}

/// Deterministic parallel sum (fixed chunking).
pub(crate) fn det_sum(n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
    let parts: Vec<f64> = (0..n.div_ceil(ROWS))
        .into_par_iter()
        .map(|c| (c * ROWS..((c + 1) * ROWS).min(n)).map(&f).sum::<f64>())
        .collect();
    parts.iter().sum()
}
