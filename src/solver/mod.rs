//! The numerical loops of the stages of [`crate::step`]: [`forces`] (body and generalized
//! viscous force, Eq. 24; XSPH), [`density`] (Eq. 22, the generalized pressure force of
//! Eq. 23), [`staggered`] (staggered pairs, Eqs. 7–9), [`surface`] (Eq. 25), [`velocity`]
//! (the consistent velocity constraint and its wall conditions) and [`projection`] (Eq. 13
//! as printed, Eq. 19's remaps), [`system`] (the Poisson operator) and [`pcg`] (its Krylov
//! solve), [`contact`] (the penetration and Shao corrections).

pub mod contact;
pub mod density;
pub mod forces;
pub mod pcg;
pub mod projection;
pub mod regions;
pub mod staggered;
pub mod surface;
pub mod system;
pub mod velocity;
pub mod wall_support;
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
    /// A static solid (a tank wall, a static collider, a ground): it never moves.
    pub fixed: bool,
    /// A moving rigid shape's shell (dynamic or kinematic): Eq. 23's mirror is carried to its
    /// carriers hydrostatically ([`density::mirrored`]).
    pub carried: bool,
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
    /// Depth of each solid carrier below its surface (may be empty: a snapshot from before
    /// it was stored).
    pub solid_depth: &'a [f32],
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

/// Impulses on solid carriers, `(solid carrier index, impulse N·s)`, in a fixed order: one
/// part per block of rows, in row order (not concatenated, so they are held once). Summed per
/// carrier and then per body (Eq. 21) by [`crate::FluidWorld`]. Plus couples `(solid index,
/// angular impulse about its centre of mass)`, for pushes whose line of action does not pass
/// through the carrier they are booked on.
#[derive(Default)]
pub(crate) struct Impulses(Vec<Vec<(u32, Vector)>>, Vec<(u32, Vector)>);

impl Impulses {
    /// No impulse.
    pub fn new() -> Self {
        Self::default()
    }

    /// The couples, in row order.
    pub fn couples(&self) -> &[(u32, Vector)] {
        &self.1
    }

    /// `Σ c_k I_k` over `parts`, summed per solid carrier and per body (in carrier and body
    /// order, each sum in the parts' order), so that combining repeatedly keeps one entry
    /// per carrier instead of growing the lists.
    pub fn combine(parts: Vec<(f32, Impulses)>) -> Impulses {
        let mut carriers: Vec<Option<Vector>> = Vec::new();
        let mut couples: Vec<Option<Vector>> = Vec::new();
        let add = |sums: &mut Vec<Option<Vector>>, &(k, j): &(u32, Vector), c: f32| {
            let k = k as usize;
            if sums.len() <= k {
                sums.resize(k + 1, None);
            }
            *sums[k].get_or_insert(Vector::ZERO) += c * j;
        };
        for (c, imp) in &parts {
            imp.0
                .iter()
                .flatten()
                .for_each(|e| add(&mut carriers, e, *c));
            imp.1.iter().for_each(|e| add(&mut couples, e, *c));
        }
        let listed = |sums: Vec<Option<Vector>>| -> Vec<(u32, Vector)> {
            let entries = sums.into_iter().enumerate();
            entries.filter_map(|(k, j)| Some((k as u32, j?))).collect()
        };
        Impulses(vec![listed(carriers)], listed(couples))
    }
}

impl<'a> IntoIterator for &'a Impulses {
    type Item = &'a (u32, Vector);
    type IntoIter = std::iter::Flatten<std::slice::Iter<'a, Vec<(u32, Vector)>>>;
    fn into_iter(self) -> Self::IntoIter {
        self.0.iter().flatten()
    }
}

/// Per-chunk impulse collector.
#[derive(Default)]
pub(crate) struct Acc(pub Vec<(u32, Vector)>, Vec<(u32, Vector)>);

impl Acc {
    /// Impulse `j` on solid carrier `s`.
    #[inline]
    pub fn add(&mut self, s: usize, j: Vector) {
        self.0.push((s as u32, j));
    }

    /// Angular impulse `l` (about its centre of mass) on solid `b`.
    #[inline]
    pub fn add_couple(&mut self, b: u32, l: Vector) {
        self.1.push((b, l));
    }
}

/// Runs `f(i, &mut out[i], acc)` over all rows in parallel and returns the impulses on solid
/// carriers in row order (deterministic whatever the thread count).
pub(crate) fn for_rows<T: Send>(
    out: &mut [T],
    f: impl Fn(usize, &mut T, &mut Acc) + Sync,
) -> Impulses {
    for_rows2(out, &mut [] as &mut [()], |i, o, _, acc| f(i, o, acc))
}

/// [`for_rows`] writing a second output per row, `out2[i]` (`None` when `out2` is empty).
pub(crate) fn for_rows2<T: Send, U: Send>(
    out: &mut [T],
    out2: &mut [U],
    f: impl Fn(usize, &mut T, Option<&mut U>, &mut Acc) + Sync,
) -> Impulses {
    let blocks = out.len().div_ceil(ROWS);
    let second: Vec<Option<&mut [U]>> = if out2.is_empty() {
        (0..blocks).map(|_| None).collect()
    } else {
        out2.chunks_mut(ROWS).map(Some).collect()
    };
    let parts: Vec<Acc> = out
        .par_chunks_mut(ROWS)
        .zip(second)
        .enumerate()
        .map(|(c, (chunk, mut second))| {
            let mut acc = Acc::default();
            for (k, o) in chunk.iter_mut().enumerate() {
                let o2 = second.as_mut().map(|s| &mut s[k]);
                f(c * ROWS + k, o, o2, &mut acc);
            }
            // held until the stage's impulses are absorbed: without the growth slack
            acc.0.shrink_to_fit();
            acc
        })
        .collect();
    let mut couples = Vec::new();
    let carriers = parts
        .into_iter()
        .map(|p| {
            couples.extend(p.1);
            p.0
        })
        .collect();
    Impulses(carriers, couples)
}

/// Runs `f(i, acc)` over rows `0..n` in parallel, where few rows give a result: returns the
/// rows that did, with it, in row order, and the impulses (so no copy of the whole state is
/// made for a correction that touches a handful of carriers).
pub(crate) fn for_rows_sparse<R: Send>(
    n: usize,
    f: impl Fn(usize, &mut Acc) -> Option<R> + Sync,
) -> (Vec<(usize, R)>, Impulses) {
    let parts: Vec<(Vec<(usize, R)>, Acc)> = (0..n.div_ceil(ROWS))
        .into_par_iter()
        .map(|c| {
            let (mut found, mut acc) = (Vec::new(), Acc::default());
            for i in c * ROWS..((c + 1) * ROWS).min(n) {
                if let Some(r) = f(i, &mut acc) {
                    found.push((i, r));
                }
            }
            (found, acc)
        })
        .collect();
    let (mut found, mut imp) = (Vec::new(), Vec::with_capacity(parts.len()));
    let mut couples = Vec::new();
    for (f, a) in parts {
        found.extend(f);
        imp.push(a.0);
        couples.extend(a.1);
    }
    (found, Impulses(imp, couples))
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `combine` is the weighted sum per carrier and per body, one entry each, in index order.
    #[test]
    fn combined_impulses_are_the_weighted_sum_one_entry_per_carrier() {
        let v = |x: f32| Vector::new(x, -2.0 * x, 0.5 * x);
        let a = Impulses(
            vec![vec![(3, v(1.0)), (1, v(2.0))], vec![(3, v(4.0))]],
            vec![(0, v(1.0))],
        );
        let b = Impulses(vec![vec![(1, v(8.0)), (5, v(16.0))]], vec![(2, v(3.0))]);
        let c = Impulses::combine(vec![(0.25, a), (0.5, b)]);
        let got: Vec<(u32, Vector)> = (&c).into_iter().copied().collect();
        let want = [(1, v(0.5 + 4.0)), (3, v(1.25)), (5, v(8.0))];
        assert_eq!(got.len(), want.len());
        for ((k, j), (wk, wj)) in got.iter().zip(want) {
            assert_eq!(*k, wk);
            assert!((*j - wj).length() < 1e-6, "carrier {k}: {j} against {wj}");
        }
        let couples = c.couples();
        assert_eq!(couples.len(), 2);
        assert_eq!((couples[0].0, couples[1].0), (0, 2));
        assert!((couples[0].1 - v(0.25)).length() < 1e-6);
        assert!((couples[1].1 - v(1.5)).length() < 1e-6);
    }
}
