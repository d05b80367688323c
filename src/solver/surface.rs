//! Free-surface detection (He 2012 §5.2, Eq. 25).

use super::Ctx;
use crate::math::Vector;
use rayon::prelude::*;

/// Eq. 25: a fluid carrier is on the free surface when its asymmetry
/// `Asy_i = |x_i − Σ_j x_j W̃_ij|` exceeds `asym·h` or its density is below `dens·ρ̄`.
/// Solid neighbours count, so walls do not create false surface. `asymmetry` holds
/// `Asy_i` per carrier, from [`super::density::density_count_asymmetry`].
pub(crate) fn detect(
    ctx: &Ctx,
    rho: &[f32],
    asymmetry: &[f32],
    asym: f32,
    dens: f32,
    surface: &mut [bool],
) {
    let h = ctx.kernel.support();
    let rho_min = dens * ctx.rest_density;
    surface
        .par_iter_mut()
        .zip(rho.par_iter().zip(asymmetry.par_iter()))
        .for_each(|(s, (&r, &a))| *s = r < rho_min || a > asym * h);
}

fn find(parent: &mut [u32], mut a: u32) -> u32 {
    while parent[a as usize] != a {
        let g = parent[parent[a as usize] as usize];
        parent[a as usize] = g;
        a = g;
    }
    a
}

/// Keeps the Poisson system non-singular where a connected region of inner fluid touches no
/// surface carrier (§5.2): a small region (fewer carriers than [`PIN_BELOW`], a droplet) is
/// marked surface whole; a larger one — fluid sealed in a container — has only its highest
/// carrier along `up` (against gravity) pinned to p = 0, so the rest of it still gets its
/// pressure, non-negative below the pin (the pure-Neumann system is singular only by a
/// constant). Returns how many carriers were marked.
pub(crate) fn mark_isolated(ctx: &Ctx, x: &[Vector], up: Vector, surface: &mut [bool]) -> usize {
    let nf = ctx.n_fluid();
    let h2 = ctx.kernel.support() * ctx.kernel.support();
    let mut parent: Vec<u32> = (0..nf as u32).collect();
    let mut touches = vec![false; nf];
    for i in 0..nf {
        if surface[i] {
            continue;
        }
        for &j in ctx.lists.row(i) {
            let j = j as usize;
            if j >= nf || (x[j] - x[i]).length_squared() >= h2 {
                continue;
            }
            if surface[j] {
                touches[i] = true;
            } else if j > i {
                let (a, b) = (find(&mut parent, i as u32), find(&mut parent, j as u32));
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
    }
    let mut root_ok = vec![false; nf];
    for i in 0..nf {
        if !surface[i] && touches[i] {
            let r = find(&mut parent, i as u32);
            root_ok[r as usize] = true;
        }
    }
    let mut size = vec![0u32; nf];
    let mut top: Vec<u32> = (0..nf as u32).collect();
    for i in 0..nf {
        if !surface[i] {
            let r = find(&mut parent, i as u32) as usize;
            size[r] += 1;
            if x[i].dot(up) > x[top[r] as usize].dot(up) {
                top[r] = i as u32;
            }
        }
    }
    let mut marked = 0;
    for (i, s) in surface.iter_mut().enumerate() {
        if *s {
            continue;
        }
        let r = find(&mut parent, i as u32) as usize;
        if !root_ok[r] && (size[r] < PIN_BELOW || top[r] as usize == i) {
            *s = true;
            marked += 1;
        }
    }
    marked
}

/// Isolated regions with at least this many carriers are pinned at one carrier instead of
/// being marked surface whole.
pub(crate) const PIN_BELOW: u32 = 27;
