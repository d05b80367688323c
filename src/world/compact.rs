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
        fn retain<T>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            v.retain(|_| *k.next().unwrap_or(&true));
        }
        let c = &mut self.solid;
        retain(&mut c.body, keep);
        retain(&mut c.x, keep);
        retain(&mut c.n, keep);
        retain(&mut c.u, keep);
        retain(&mut c.volume, keep);
        retain(&mut c.depth, keep);
        retain(&mut c.f, keep);
        self.solids_dirty = true;
    }
}
