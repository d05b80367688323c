//! Connected regions of carriers: a lock-free union–find whose result does not depend on the
//! order of the unions (links always point from a larger to a smaller index, so every
//! region's root is its smallest carrier and concurrent unions cannot make cycles).

use rayon::prelude::*;
use std::sync::atomic::{AtomicU32, Ordering};

/// A union–find over `n` carriers, safe to join from several threads.
pub(crate) struct Regions {
    parent: Vec<AtomicU32>,
}

impl Regions {
    /// Every carrier its own region.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            parent: (0..n as u32).map(AtomicU32::new).collect(),
        }
    }

    /// Root of `a` (path halving by compare-and-swap).
    fn find(&self, mut a: u32) -> u32 {
        let parent = &self.parent;
        loop {
            let p = parent[a as usize].load(Ordering::Relaxed);
            if p == a {
                return a;
            }
            let g = parent[p as usize].load(Ordering::Relaxed);
            if g != p {
                let _ =
                    parent[a as usize].compare_exchange(p, g, Ordering::Relaxed, Ordering::Relaxed);
            }
            a = g;
        }
    }

    /// Joins the regions of `a` and `b`.
    pub(crate) fn union(&self, a: u32, b: u32) {
        let (mut a, mut b) = (a, b);
        loop {
            a = self.find(a);
            b = self.find(b);
            if a == b {
                return;
            }
            let (hi, lo) = if a > b { (a, b) } else { (b, a) };
            if self.parent[hi as usize]
                .compare_exchange(hi, lo, Ordering::Relaxed, Ordering::Relaxed)
                .is_ok()
            {
                return;
            }
        }
    }

    /// Every carrier's root: the smallest index in its region.
    pub(crate) fn roots(&self) -> Vec<u32> {
        (0..self.parent.len() as u32)
            .into_par_iter()
            .map(|i| self.find(i))
            .collect()
    }
}
