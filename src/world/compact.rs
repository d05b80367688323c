//! Removing single solid carriers (a melting body's melted points) while every solid keeps a
//! contiguous range.

use super::FluidWorld;

impl FluidWorld {
    /// Keeps the solid carriers for which `keep` is true: the carrier arrays are compacted and
    /// every solid's range, body-frame copy and ambiguous-normal list follow. (Per-carrier
    /// arrays of deformable bodies are the caller's.)
    pub(crate) fn retain_solid_carriers(&mut self, keep: &[bool]) {
        // kept carriers before each slot
        let mut before = Vec::with_capacity(keep.len() + 1);
        before.push(0usize);
        for &k in keep {
            before.push(before.last().copied().unwrap_or(0) + k as usize);
        }
        for s in self.solids.iter_mut() {
            let r = s.range.clone();
            if !s.local.is_empty() {
                let mut k = keep[r.clone()].iter();
                s.local.retain(|_| *k.next().unwrap_or(&true));
            }
            s.two_sided = s
                .two_sided
                .iter()
                .filter(|&&t| keep[r.start + t as usize])
                .map(|&t| (before[r.start + t as usize] - before[r.start]) as u32)
                .collect();
            s.range = before[r.start]..before[r.end];
        }
        let c = &mut self.solid;
        retain_where(&mut c.body, keep);
        retain_where(&mut c.x, keep);
        retain_where(&mut c.n, keep);
        retain_where(&mut c.u, keep);
        retain_where(&mut c.volume, keep);
        retain_where(&mut c.depth, keep);
        retain_where(&mut c.f, keep);
        self.solids_dirty = true;
    }
}

/// Keeps the entries of `v` for which `keep` is true (entries past `keep`'s end stay).
pub(crate) fn retain_where<T>(v: &mut Vec<T>, keep: &[bool]) {
    let mut k = keep.iter();
    v.retain(|_| *k.next().unwrap_or(&true));
}
