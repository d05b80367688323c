//! The lattice of a lattice-shape-matching body (Rivers & James 2007, Shao et al. 2014
//! §3.4.1): inner boundary particles (IBPs) on a lattice of the fluid spacing inside a shape,
//! the overlapping shape-matching region of each, and the weights that tie each surface
//! boundary particle (SBP: a solid carrier the fluid sees) to the IBPs around it.

use crate::error::{FluidError, Result};
use crate::kernel::CubicSpline;
use crate::limits::{check_count, MAX_PARTICLES};
use crate::math::Vector;
use crate::sampling::{axis, signed_distance, ShellSample};
use rapier3d::parry::shape::Shape;
use std::collections::HashMap;

/// Largest region half-width: a region holds up to (2w + 1)³ = 729 lattice points.
pub const MAX_HALF_WIDTH: u32 = 4;

/// The IBPs of a shape in its local frame: lattice points (spacing `dx`, centred in the
/// bounding box as the shell sampling's lattice is) inside the shape, with their integer
/// lattice coordinates. The lattice is counted before it is built.
pub(crate) fn inner_points(shape: &dyn Shape, dx: f32) -> Result<(Vec<Vector>, Vec<[i32; 3]>)> {
    let aabb = shape.compute_local_aabb();
    let (lo, hi) = (aabb.mins, aabb.maxs);
    let axes: [(f32, usize); 3] = std::array::from_fn(|k| axis(lo[k], hi[k], dx, None));
    let total = axes.iter().map(|a| a.1 as f64).product::<f64>();
    check_count("lattice points of a deformable body", total, MAX_PARTICLES)?;
    let (mut pts, mut cells) = (Vec::new(), Vec::new());
    for k in 0..axes[2].1 {
        for j in 0..axes[1].1 {
            for i in 0..axes[0].1 {
                let c = [i, j, k];
                let p = Vector::from_array(std::array::from_fn(|a| axes[a].0 + c[a] as f32 * dx));
                if signed_distance(shape, p) < 0.0 {
                    pts.push(p);
                    cells.push(c.map(|v| v as i32));
                }
            }
        }
    }
    if pts.is_empty() {
        return Err(FluidError::DegenerateShape {
            shape: format!("{:?}", shape.shape_type()),
            why: format!(
                "no lattice point of spacing {dx} inside it: a deformable body must be at \
                 least a spacing thick"
            ),
        });
    }
    Ok((pts, cells))
}

/// Carriers at the lattice points `rest` of `shape` (a melting body's SBPs: all of them), each
/// with the outward normal of the surface point nearest it and its depth.
pub(crate) fn samples(shape: &dyn Shape, rest: &[Vector]) -> Vec<ShellSample> {
    rest.iter()
        .map(|&p| {
            let (q, inside) = crate::sampling::project(shape, p);
            let d = q - p;
            let n = if inside { d } else { -d };
            ShellSample {
                x: p,
                n: n.try_normalize().unwrap_or(Vector::Y),
                phi: signed_distance(shape, p),
                two_sided: false,
            }
        })
        .collect()
}

/// Ties each SBP (rest positions `sbp`) to the IBP at the same lattice point, weight 1.
pub(crate) fn own_points(sbp: &[(Vector, Vector)], rest: &[Vector]) -> Rows<(u32, f32)> {
    let key = |p: Vector| p.to_array().map(f32::to_bits);
    let at: HashMap<[u32; 3], u32> = rest
        .iter()
        .enumerate()
        .map(|(d, p)| (key(*p), d as u32))
        .collect();
    Rows::from_rows(sbp.iter().map(|(p, _)| vec![(at[&key(*p)], 1.0)]))
}

/// The 27 lattice offsets of the cube around a point (itself included), x fastest.
pub(crate) fn cube_offsets() -> impl Iterator<Item = [i32; 3]> {
    (0..27).map(|k| [k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1])
}

/// The 26 lattice offsets of a point's one-ring (Shao §3.4.2), x fastest.
pub(crate) fn neighbour_offsets() -> impl Iterator<Item = [i32; 3]> {
    cube_offsets().filter(|o| *o != [0, 0, 0])
}

/// Lattice coordinates `c` moved by `o`.
pub(crate) fn shifted(c: [i32; 3], o: [i32; 3]) -> [i32; 3] {
    [c[0] + o[0], c[1] + o[1], c[2] + o[2]]
}

/// Each lattice point's one-ring neighbours present in `cells` (Shao §3.4.2).
pub(crate) fn one_rings(cells: &[[i32; 3]]) -> Vec<Vec<u32>> {
    let at: HashMap<[i32; 3], u32> = cells
        .iter()
        .enumerate()
        .map(|(i, c)| (*c, i as u32))
        .collect();
    cells
        .iter()
        .map(|c| {
            neighbour_offsets()
                .filter_map(|o| at.get(&shifted(*c, o)).copied())
                .collect()
        })
        .collect()
}

/// Lists in compressed rows: row `i` is `items[start[i]..start[i + 1]]`.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Rows<T> {
    pub start: Vec<u32>,
    pub items: Vec<T>,
}

impl<T> Rows<T> {
    pub fn row(&self, i: usize) -> &[T] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }

    pub fn len(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    pub fn from_rows(rows: impl IntoIterator<Item = Vec<T>>) -> Self {
        let mut out = Rows {
            start: vec![0],
            items: Vec::new(),
        };
        for r in rows {
            out.items.extend(r);
            out.start.push(out.items.len() as u32);
        }
        out
    }
}

/// The shape-matching region of each IBP: the IBPs reachable from it by at most `w` steps
/// between lattice neighbours (the 26 around a point; Shao §3.4.2's one-ring), itself
/// included. In a solid block that is the (2w + 1)³ cube around the point; across a gap of the
/// shape (two fingers of a hand) regions do not jump. Membership is symmetric.
pub(crate) fn regions(cells: &[[i32; 3]], w: u32) -> Rows<u32> {
    let index: HashMap<[i32; 3], u32> = cells
        .iter()
        .enumerate()
        .map(|(i, c)| (*c, i as u32))
        .collect();
    let ring = |c: [i32; 3]| {
        let index = &index;
        neighbour_offsets().filter_map(move |o| index.get(&shifted(c, o)).copied())
    };
    let mut seen = vec![u32::MAX; cells.len()];
    Rows::from_rows((0..cells.len()).map(|i| {
        let mut members = vec![i as u32];
        seen[i] = i as u32;
        let mut front = 0;
        for _ in 0..w {
            let end = members.len();
            for m in front..end {
                for n in ring(cells[members[m] as usize]) {
                    if seen[n as usize] != i as u32 {
                        seen[n as usize] = i as u32;
                        members.push(n);
                    }
                }
            }
            front = end;
        }
        members.sort_unstable();
        members
    }))
}

/// The weights tying each point of `points` (rest positions) to the IBPs at `rest`: the
/// kernel weights `W(|x⁰_s − x⁰_d|)` of the IBPs within the support, normalised to sum to
/// one (the nearest IBP alone where none is within it). One set of weights serves Eq. 19
/// (a point's position from its IBPs') and Eq. 10 (a point's force shared among its IBPs;
/// normalised per point, so the shares add up to the force: momentum is kept).
pub(crate) fn bind(points: &[Vector], rest: &[Vector], kernel: &CubicSpline) -> Rows<(u32, f32)> {
    let h = kernel.support();
    // a hash of the rest lattice by cells of the support's size
    let cell = |p: Vector| (p / h).floor().as_ivec3().to_array();
    let mut grid: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
    for (d, p) in rest.iter().enumerate() {
        grid.entry(cell(*p)).or_default().push(d as u32);
    }
    Rows::from_rows(points.iter().map(|&x| {
        let c = cell(x);
        let mut row: Vec<(u32, f32)> = Vec::new();
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let Some(ds) = grid.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                        continue;
                    };
                    for &d in ds {
                        let w = kernel.w((x - rest[d as usize]).length());
                        if w > 0.0 {
                            row.push((d, w));
                        }
                    }
                }
            }
        }
        if row.is_empty() {
            let nearest = (0..rest.len())
                .min_by(|&a, &b| {
                    (x - rest[a])
                        .length_squared()
                        .total_cmp(&(x - rest[b]).length_squared())
                })
                .unwrap_or(0);
            row.push((nearest as u32, 1.0));
        }
        row.sort_unstable_by_key(|e| e.0);
        let sum: f32 = row.iter().map(|e| e.1).sum();
        row.iter_mut().for_each(|e| e.1 /= sum);
        row
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::parry::shape::Cuboid;

    #[test]
    fn a_block_has_cubic_regions_and_partitions_of_unity() {
        let shape = Cuboid::new(Vector::new(0.05, 0.05, 0.05));
        let (pts, cells) = inner_points(&shape, 0.025).unwrap();
        assert_eq!(pts.len(), 64);
        let r = regions(&cells, 1);
        // a corner point's region is 2³, an inner point's 3³
        let sizes: Vec<usize> = (0..r.len()).map(|i| r.row(i).len()).collect();
        assert_eq!(*sizes.iter().min().unwrap(), 8);
        assert_eq!(*sizes.iter().max().unwrap(), 27);
        let k = CubicSpline::new(0.05);
        let b = bind(&pts, &pts, &k);
        for i in 0..b.len() {
            let s: f32 = b.row(i).iter().map(|e| e.1).sum();
            assert!((s - 1.0).abs() < 1e-6);
        }
    }
}
