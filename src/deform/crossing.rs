//! Water kept on its side of a cloth (issue 23's cloth, issue 19's thin solids). A cloth is
//! one layer of points a spacing apart; the penetration correction keeps water out of a cell
//! around each point, but pushes a carrier out of that cell the shortest way — sideways,
//! into the sheet's plane between two points, or out of the far side once it is past the
//! point's middle — so water slipped through where the sheet slopes or moves (a 6³ column
//! dropped from 10Δx onto the soft sheet lost 35 of 216 carriers, an 8³ one from 20Δx 343
//! of 512). So after each substep every carrier beside a cloth is tested against the sheet as
//! triangles (two per grid cell) at the substep's start and end. One that crossed the
//! sheet's middle, or ended within half a spacing of it (inside the sheet, which is a spacing
//! thick to the water), is put half a spacing off the middle on the side it started from, and
//! loses its velocity into the sheet relative to it; that momentum goes to the sheet's points
//! under it (momentum is kept; a pinned point passes its share to what holds it). With no
//! carrier left inside the sheet, a carrier's side is never in doubt at the next substep.
//! Water may lie on both sides; a carrier beside the sheet's free edge has no side and is
//! left to the penetration correction.

use super::body::Deformable;
use crate::math::Vector;
use crate::world::FluidWorld;

/// The sheet's points on their grid: `at[k n₀ + i]` the IBP at grid node `(i, k)`.
struct Grid {
    n: [usize; 2],
    at: Vec<u32>,
    /// Each IBP's grid node.
    node: Vec<[usize; 2]>,
}

impl Grid {
    fn of(b: &Deformable) -> Grid {
        let (lo, hi) = b
            .cells
            .iter()
            .fold(([i32::MAX; 2], [i32::MIN; 2]), |(lo, hi), c| {
                (
                    [lo[0].min(c[0]), lo[1].min(c[2])],
                    [hi[0].max(c[0]), hi[1].max(c[2])],
                )
            });
        let n = [(hi[0] - lo[0] + 1) as usize, (hi[1] - lo[1] + 1) as usize];
        let mut at = vec![u32::MAX; n[0] * n[1]];
        let node: Vec<[usize; 2]> = b
            .cells
            .iter()
            .map(|c| [(c[0] - lo[0]) as usize, (c[2] - lo[1]) as usize])
            .collect();
        for (p, c) in node.iter().enumerate() {
            at[c[1] * n[0] + c[0]] = p as u32;
        }
        Grid { n, at, node }
    }

    fn get(&self, i: isize, k: isize) -> Option<u32> {
        if i < 0 || k < 0 || i as usize >= self.n[0] || k as usize >= self.n[1] {
            return None;
        }
        let p = self.at[k as usize * self.n[0] + i as usize];
        (p != u32::MAX).then_some(p)
    }

    /// Whether grid nodes all lie on one border line of the sheet.
    fn on_border(&self, nodes: &[[usize; 2]]) -> bool {
        let line = |f: &dyn Fn([usize; 2]) -> bool| nodes.iter().all(|&c| f(c));
        line(&|c| c[0] == 0)
            || line(&|c| c[0] + 1 == self.n[0])
            || line(&|c| c[1] == 0)
            || line(&|c| c[1] + 1 == self.n[1])
    }
}

/// Where a point meets the sheet: the nearest point `c` on its triangles, the sheet's
/// (pseudo-)normal there, the three points of the triangle it lies on with their weights, and
/// the point's side (`±1`, `0` when it lies beyond the sheet's border, round its edge).
struct Foot {
    c: Vector,
    n: Vector,
    corners: [u32; 3],
    /// The sheet's point nearest to it.
    nearest: u32,
    w: [f32; 3],
    dist: f32,
    /// The offset along `n`.
    along: f32,
    side: f32,
}

/// The nearest point of triangle `t` to `p` with its barycentric weights (Ericson 2005,
/// §5.1.5).
fn on_triangle(p: Vector, t: [Vector; 3]) -> (Vector, [f32; 3]) {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + ab * v, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + ac * w, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + (c - b) * w, [0.0, 1.0 - w, w]);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

/// Where `p` meets the sheet `x` (the IBPs' positions), searching from IBP `hint`: down the
/// grid to the nearest point, then over the (up to eight) triangles around it. A tie between
/// triangles (the nearest point on an edge or a point of the sheet) takes the normals' sum,
/// weighted by each triangle's angle there, so a point beside a fold gets its side right.
fn foot(p: Vector, x: &[Vector], g: &Grid, hint: u32) -> Option<Foot> {
    let mut node = g.node[hint as usize];
    let d2 = |q: u32| (x[q as usize] - p).length_squared();
    for _ in 0..4 * (g.n[0] + g.n[1]) {
        let here = d2(g.at[node[1] * g.n[0] + node[0]]);
        let mut best = (here, node);
        for (di, dk) in [
            (-1, -1),
            (0, -1),
            (1, -1),
            (-1, 0),
            (1, 0),
            (-1, 1),
            (0, 1),
            (1, 1),
        ] {
            let (i, k) = (node[0] as isize + di, node[1] as isize + dk);
            if let Some(q) = g.get(i, k) {
                let d = d2(q);
                if d < best.0 {
                    best = (d, [i as usize, k as usize]);
                }
            }
        }
        if best.1 == node {
            break;
        }
        node = best.1;
    }
    // the triangles of the four cells around the node: (a, b, d) and (a, d, c) of each cell
    // with corners a = (i, k), b = (i+1, k), c = (i, k+1), d = (i+1, k+1)
    let mut tris: Vec<([u32; 3], Vector, [f32; 3], f32)> = Vec::with_capacity(8);
    for (ci, ck) in [(-1isize, -1isize), (0, -1), (-1, 0), (0, 0)] {
        let (i, k) = (node[0] as isize + ci, node[1] as isize + ck);
        let (Some(a), Some(b), Some(c), Some(d)) = (
            g.get(i, k),
            g.get(i + 1, k),
            g.get(i, k + 1),
            g.get(i + 1, k + 1),
        ) else {
            continue;
        };
        for t in [[a, b, d], [a, d, c]] {
            let (q, w) = on_triangle(p, t.map(|v| x[v as usize]));
            tris.push((t, q, w, (q - p).length()));
        }
    }
    let &(corners, c, w, dist) = tris.iter().min_by(|a, b| a.3.total_cmp(&b.3))?;
    let tie = 1e-5 * (x[corners[0] as usize] - x[corners[1] as usize]).length() + 1e-7;
    let mut n = Vector::ZERO;
    for (t, q, tw, d) in &tris {
        if *d > dist + tie || (*q - c).length() > tie {
            continue;
        }
        let [a, b, cc] = t.map(|v| x[v as usize]);
        let normal = (b - a).cross(cc - a).normalize_or_zero();
        // the angle at the nearest point if it is one of the triangle's corners
        let angle = match tw.iter().position(|&v| v > 1.0 - 1e-6) {
            Some(0) => (b - a).angle_between(cc - a),
            Some(1) => (a - b).angle_between(cc - b),
            Some(2) => (a - cc).angle_between(b - cc),
            _ => 1.0,
        };
        n += normal * angle;
    }
    let n = n.try_normalize()?;
    let off = p - c;
    let along = off.dot(n);
    // round the border: the nearest point on the sheet's edge and the point beside it more
    // than along the normal
    let on: Vec<[usize; 2]> = corners
        .iter()
        .zip(w)
        .filter(|(_, w)| *w > 1e-6)
        .map(|(&q, _)| g.node[q as usize])
        .collect();
    let beyond = g.on_border(&on) && along.abs() < 0.7 * off.length();
    let side = if beyond || along == 0.0 {
        0.0
    } else {
        along.signum()
    };
    Some(Foot {
        c,
        n,
        corners,
        nearest: g.at[node[1] * g.n[0] + node[0]],
        w,
        dist,
        along,
        side,
    })
}

/// How far `p`, inside the cube of half-side `h` at `centre` turned by `r`, goes along the
/// unit direction `d` to leave it (`None` outside it).
fn exit_cell(
    p: Vector,
    d: Vector,
    centre: Vector,
    r: crate::math::Rotation,
    h: f32,
) -> Option<f32> {
    let inv = r.inverse();
    let (l, d) = (inv * (p - centre), inv * d);
    if l.abs().max_element() >= h {
        return None;
    }
    (0..3)
        .filter(|&a| d[a].abs() > 1e-6)
        .map(|a| (h * d[a].signum() - l[a]) / d[a])
        .min_by(f32::total_cmp)
}

/// A carrier to put back: its new position and velocity, and the impulse on each of the
/// sheet's three points under it.
type Crossing = (Vector, Vector, [(u32, Vector); 3]);

impl FluidWorld {
    /// Keeps, for [`Self::keep_water_off_cloths`], where the fluid carriers and each cloth's
    /// points are as the substep's stages begin (nothing without a cloth).
    pub(crate) fn mark_cloth_start(&mut self) {
        let sheets = &mut self.scratch.cloth_start;
        sheets.clear();
        if !self.deformables.iter().any(|b| b.cloth && !b.x.is_empty()) {
            self.scratch.x_start.clear();
            return;
        }
        self.scratch.x_start.clone_from(&self.fluid.x);
        sheets.extend(
            self.deformables
                .iter()
                .map(|b| if b.cloth { b.x.clone() } else { Vec::new() }),
        );
    }

    /// Puts back the carriers that crossed a cloth within the substep, and those that ended
    /// within half a spacing of its middle ([`self`] module's doc); returns how many.
    pub(crate) fn keep_water_off_cloths(&mut self) -> usize {
        let nf = self.fluid.len();
        if self.scratch.x_start.len() != nf || self.scratch.cloth_start.is_empty() {
            return 0;
        }
        let mut put_back = 0;
        for bi in 0..self.deformables.len() {
            let b = &self.deformables[bi];
            if !b.cloth || b.x.is_empty() || self.scratch.cloth_start[bi].len() != b.x.len() {
                continue;
            }
            let found = self.crossings(bi, &Grid::of(b));
            let first = self.solids[b.solids[0] as usize].range.start;
            // the IBP's SBP (a cloth's points are each its own)
            let mut sbp = vec![usize::MAX; b.x.len()];
            for k in 0..b.carriers.len() {
                if let Some(&(q, _)) = b.carriers.row(k).first() {
                    sbp[q as usize] = first + k;
                }
            }
            put_back += found.len();
            for (i, (x, v, imp)) in found {
                self.fluid.x[i] = x;
                self.fluid.v[i] = v;
                for (q, j) in imp {
                    let q = q as usize;
                    let b = &mut self.deformables[bi];
                    if !b.pinned[q] {
                        b.v[q] += j / b.mass;
                    }
                    if sbp[q] != usize::MAX {
                        self.book_on_solid(sbp[q], j);
                    }
                }
            }
        }
        put_back
    }

    /// The carriers beside cloth `bi` that crossed it within the substep or ended inside it,
    /// in carrier order, with where they go back to.
    fn crossings(&self, bi: usize, g: &Grid) -> Vec<(usize, Crossing)> {
        let b = &self.deformables[bi];
        let (x0s, x1s) = (&self.scratch.cloth_start[bi], &b.x);
        let nf = self.fluid.len();
        let first = self.solids[b.solids[0] as usize].range.start;
        let last = self.solids[*b.solids.last().unwrap() as usize].range.end;
        let reach = self.params.support_radius();
        let half = 0.5 * self.params.spacing;
        let out = half + 0.005 * reach;
        let m = self.particle_mass();
        let (fx0, fx, fv) = (&self.scratch.x_start, &self.fluid.x, &self.fluid.v);
        let lists = &self.lists;
        // the sheet's box over the substep, and every third point of its grid each way: a
        // carrier in that box with no sheet point among its neighbours (the lists are the
        // substep start's; a stretched or fast sheet reaches water that had none) starts
        // from the nearest of those (8 m/s water thrown at a soft membrane: 72 of 180
        // through without this)
        let (lo, hi) = crate::math::bounding_box(x0s);
        let (lo1, hi1) = crate::math::bounding_box(x1s);
        let (lo, hi) = (
            lo.min(lo1) - Vector::splat(reach),
            hi.max(hi1) + Vector::splat(reach),
        );
        let inside = |p: Vector| p.cmpge(lo).all() && p.cmple(hi).all();
        let coarse: Vec<u32> = (0..g.node.len() as u32)
            .filter(|&q| g.node[q as usize].iter().all(|c| c % 3 == 0))
            .collect();
        let nearest = |p: Vector, among: &mut dyn Iterator<Item = u32>| {
            among.min_by(|&a, &b| {
                let d = |r: u32| (x0s[r as usize] - p).length_squared();
                d(a).total_cmp(&d(b))
            })
        };
        let (found, _) = crate::solver::for_rows_sparse(nf, |i, _| {
            // the sheet's point nearest the carrier among its neighbours
            let mut beside = lists
                .row(i)
                .iter()
                .filter_map(|&j| {
                    let s = (j as usize).checked_sub(nf)?;
                    (first..last).contains(&s).then_some(s - first)
                })
                .filter_map(|k| b.carriers.row(k).first().map(|e| e.0));
            let hint = match nearest(fx0[i], &mut beside) {
                Some(q) => q,
                None if inside(fx0[i]) || inside(fx[i]) => {
                    nearest(fx0[i], &mut coarse.iter().copied())?
                }
                None => return None,
            };
            let f0 = foot(fx0[i], x0s, g, hint)?;
            let f1 = foot(fx[i], x1s, g, hint)?;
            if f0.dist > reach || f1.dist > reach || f1.side == 0.0 {
                return None;
            }
            let crossed = f0.side * f1.side < 0.0;
            if !crossed && f1.along.abs() >= out {
                return None;
            }
            let side = if f0.side != 0.0 { f0.side } else { f1.side };
            let ns = f1.n * side;
            let u: Vector = (0..3).map(|k| b.v[f1.corners[k] as usize] * f1.w[k]).sum();
            let vn = (fv[i] - u).dot(ns);
            let (v, j) = if vn < 0.0 {
                (fv[i] - ns * vn, ns * (m * vn))
            } else {
                (fv[i], Vector::ZERO)
            };
            let imp = [0, 1, 2].map(|k| (f1.corners[k], j * f1.w[k]));
            // half a spacing off the middle, and out of the cells the penetration
            // correction keeps clear around the points nearby (turned with them, they
            // reach further where the sheet bends)
            let mut to = f1.c + ns * out;
            for q in f1.corners.into_iter().chain([f1.nearest]) {
                let q = q as usize;
                if let Some(t) = exit_cell(to, ns, x1s[q], b.rotation[q], half) {
                    to += ns * (t + 0.005 * reach);
                }
            }
            Some((to, v, imp))
        });
        found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5 × 5 sheet a unit apart in x and z, its height `y(i, k)`.
    fn sheet(y: impl Fn(usize, usize) -> f32) -> (Vec<Vector>, Grid) {
        let n = [5, 5];
        let (mut x, mut node) = (Vec::new(), Vec::new());
        for k in 0..n[1] {
            for i in 0..n[0] {
                x.push(Vector::new(i as f32, y(i, k), k as f32));
                node.push([i, k]);
            }
        }
        let at = (0..x.len() as u32).collect();
        (x, Grid { n, at, node })
    }

    #[test]
    fn a_point_has_a_side_of_the_sheet_except_round_its_border() {
        let (x, g) = sheet(|_, _| 0.0);
        let side = |p: Vector| foot(p, &x, &g, 0).unwrap().side;
        let (above, below) = (
            side(Vector::new(2.3, 0.4, 1.6)),
            side(Vector::new(2.3, -0.4, 1.6)),
        );
        assert!(above != 0.0 && above == -below);
        // from a far hint, down the grid to the nearest point
        let f = foot(Vector::new(3.2, 0.5, 3.7), &x, &g, 0).unwrap();
        assert!((f.c - Vector::new(3.2, 0.0, 3.7)).length() < 1e-5 && (f.dist - 0.5).abs() < 1e-5);
        assert!((f.w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        // beside the edge (x > 4): no side; over the edge point itself, a side
        assert_eq!(side(Vector::new(4.8, 0.1, 2.0)), 0.0);
        assert_eq!(side(Vector::new(4.0, 0.4, 2.0)), above);
    }

    #[test]
    fn a_fold_keeps_each_side_apart() {
        // a ridge along x = 2: both slopes at 45°
        let (x, g) = sheet(|i, _| 2.0 - (i as f32 - 2.0).abs());
        let side = |p: Vector| foot(p, &x, &g, 12).unwrap().side;
        // over the ridge, inside its angle and under it
        let over = side(Vector::new(2.0, 2.5, 2.0));
        let under = side(Vector::new(2.0, 1.5, 2.0));
        assert!(over != 0.0 && over == -under);
        // over each slope, on the same side as over the ridge
        assert_eq!(side(Vector::new(1.2, 1.9, 2.0)), over);
        assert_eq!(side(Vector::new(2.8, 1.9, 2.0)), over);
        assert_eq!(side(Vector::new(1.5, 1.0, 2.0)), under);
    }

    #[test]
    fn the_nearest_point_of_a_triangle_and_its_weights() {
        let t = [Vector::ZERO, Vector::X, Vector::Z];
        let (q, w) = on_triangle(Vector::new(0.2, 1.0, 0.3), t);
        assert!((q - Vector::new(0.2, 0.0, 0.3)).length() < 1e-6);
        assert!((w[0] - 0.5).abs() < 1e-6 && (w[1] - 0.2).abs() < 1e-6);
        let (q, w) = on_triangle(Vector::new(-1.0, 0.5, -1.0), t);
        assert_eq!((q, w), (Vector::ZERO, [1.0, 0.0, 0.0]));
        let (q, _) = on_triangle(Vector::new(1.0, 0.0, 1.0), t);
        assert!((q - Vector::new(0.5, 0.0, 0.5)).length() < 1e-6);
    }
}
