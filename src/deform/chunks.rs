//! A deformable body's lattice in chunks of `CHUNK`³ points, each chunk's SBPs one solid.
//!
//! Within a substep a free body enters the fluid's stages as one rigid proxy (`substep.rs`);
//! a pinned body as one proxy per chunk free of pins (a dynamic body of its IBPs' mass and
//! inertia), so the velocity constraint moves each chunk implicitly, with the water it
//! pushes — the coupling rapier bodies get. With its chunks' motion explicit the walls of an
//! elastic box holding water, lighter than the water behind them, erupted in three frames (a
//! 5× denser box did not). Shape matching glues the chunks between substeps.

use super::lattice::{self, Rows};
use crate::math::Vector;
use crate::world::FluidWorld;
use std::collections::HashMap;

/// Lattice points along a chunk's edge.
pub(crate) const CHUNK: i32 = 4;

/// How a body's SBPs were split.
pub(crate) struct Split {
    pub solids: Vec<u32>,
    pub chunk: Vec<u32>,
    pub members: Rows<u32>,
    pub carriers: Rows<(u32, f32)>,
    pub sbp_rest: Vec<(Vector, Vector)>,
}

impl FluidWorld {
    /// Splits solid `k`, just sampled as a deformable body's SBPs, into one solid per chunk
    /// (`edge`³ points) of the IBP lattice (`rest`, lattice coordinates `cells`): each SBP goes to the chunk of
    /// the IBP it hangs on most, the carriers are reordered by chunk so each chunk's are
    /// contiguous, and each SBP is bound (Eqs. 19, 10) to the IBPs of its own chunk only, so
    /// that a chunk's proxy takes exactly the impulses its IBPs share.
    pub(crate) fn split_into_chunks(
        &mut self,
        k: usize,
        rest: &[Vector],
        cells: &[[i32; 3]],
        edge: i32,
    ) -> Split {
        let mut ids: HashMap<[i32; 3], u32> = HashMap::new();
        let ibp_chunk: Vec<u32> = cells
            .iter()
            .map(|c| {
                let key = c.map(|v| v.div_euclid(edge));
                let next = ids.len() as u32;
                *ids.entry(key).or_insert(next)
            })
            .collect();
        let local: Vec<(Vector, Vector)> = self.solids[k].local.clone();
        let points: Vec<Vector> = local.iter().map(|l| l.0).collect();
        let all = lattice::bind(&points, rest, &self.kernel);
        let sbp_chunk: Vec<u32> = (0..points.len())
            .map(|s| {
                let best = all.row(s).iter().max_by(|a, b| a.1.total_cmp(&b.1));
                ibp_chunk[best.map_or(0, |e| e.0 as usize)]
            })
            .collect();
        // carriers ordered by chunk (stable)
        let mut order: Vec<usize> = (0..points.len()).collect();
        order.sort_by_key(|&s| sbp_chunk[s]);
        let start = self.solids[k].range.start;
        self.permute_carriers(k, &order);
        // one solid per chunk that has SBPs, in carrier order
        let mut solids: Vec<u32> = Vec::new();
        let mut slot: HashMap<u32, u32> = HashMap::new();
        let mut bounds: Vec<usize> = Vec::new();
        for (pos, &s) in order.iter().enumerate() {
            if let std::collections::hash_map::Entry::Vacant(e) = slot.entry(sbp_chunk[s]) {
                e.insert(solids.len() as u32);
                solids.push(0);
                bounds.push(pos);
            }
        }
        bounds.push(order.len());
        let template = self.solids[k].clone();
        for c in 0..solids.len() {
            let r = start + bounds[c]..start + bounds[c + 1];
            let mut s = template.clone();
            s.local = local_of(&template, r.clone());
            s.two_sided = template
                .two_sided
                .iter()
                .filter(|&&t| r.contains(&(template.range.start + t as usize)))
                .map(|&t| t - (r.start - template.range.start) as u32)
                .collect();
            s.range = r.clone();
            let idx = if c == 0 {
                self.solids[k] = s;
                k
            } else {
                self.solids.push(s);
                self.solids.len() - 1
            };
            for i in r {
                self.solid.body[i] = idx as u32;
            }
            solids[c] = idx as u32;
        }
        let chunk: Vec<u32> = ibp_chunk
            .iter()
            .map(|c| slot.get(c).copied().unwrap_or(u32::MAX))
            .collect();
        let mut groups = vec![Vec::new(); solids.len()];
        for (i, &c) in chunk.iter().enumerate() {
            if c != u32::MAX {
                groups[c as usize].push(i as u32);
            }
        }
        // each SBP bound to the IBPs of its own chunk
        let sorted: Vec<(Vector, Vector)> = order.iter().map(|&s| local[s]).collect();
        let mut rows: Vec<Vec<(u32, f32)>> = Vec::with_capacity(order.len());
        for (c, group) in groups.iter().enumerate() {
            let own: Vec<Vector> = group.iter().map(|&d| rest[d as usize]).collect();
            let pts: Vec<Vector> = sorted[bounds[c]..bounds[c + 1]]
                .iter()
                .map(|l| l.0)
                .collect();
            let bound = lattice::bind(&pts, &own, &self.kernel);
            for p in 0..pts.len() {
                rows.push(
                    bound
                        .row(p)
                        .iter()
                        .map(|&(d, w)| (group[d as usize], w))
                        .collect(),
                );
            }
        }
        Split {
            solids,
            chunk,
            members: Rows::from_rows(groups),
            carriers: Rows::from_rows(rows),
            sbp_rest: sorted,
        }
    }

    /// Reorders solid `k`'s carriers (and its body-frame copy) so that position `p` of its
    /// range holds what position `order[p]` held.
    fn permute_carriers(&mut self, k: usize, order: &[usize]) {
        fn apply<T: Copy>(v: &mut [T], start: usize, order: &[usize]) {
            let old: Vec<T> = v[start..start + order.len()].to_vec();
            for (p, &o) in order.iter().enumerate() {
                v[start + p] = old[o];
            }
        }
        let s = &mut self.solids[k];
        let start = s.range.start;
        let c = &mut self.solid;
        apply(&mut c.x, start, order);
        apply(&mut c.n, start, order);
        apply(&mut c.u, start, order);
        apply(&mut c.f, start, order);
        apply(&mut c.volume, start, order);
        apply(&mut c.depth, start, order);
        apply(&mut s.local, 0, order);
        let mut inverse = vec![0u32; order.len()];
        for (p, &o) in order.iter().enumerate() {
            inverse[o] = p as u32;
        }
        for t in s.two_sided.iter_mut() {
            *t = inverse[*t as usize];
        }
    }
}

/// The body-frame copy of the carriers `r` of a solid.
fn local_of(s: &crate::world::Solid, r: std::ops::Range<usize>) -> Vec<(Vector, Vector)> {
    s.local[r.start - s.range.start..r.end - s.range.start].to_vec()
}
