//! Free-surface detection (He 2012 §5.2, Eq. 25).

use super::regions::Regions;
use super::Ctx;
use crate::math::Vector;
use rayon::prelude::*;

/// Eq. 25: a fluid carrier is on the free surface when its asymmetry
/// `Asy_i = |x_i − Σ_j x_j W̃_ij|` exceeds `asym·h` or its density is below `dens·ρ̄`.
/// Solid neighbours count, so walls do not create false surface. `asymmetry` holds
/// `Asy_i` per carrier, from [`super::density::density_and_count`].
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

/// Keeps the Poisson system non-singular where a connected region of inner fluid touches no
/// surface carrier (§5.2): a small region (fewer carriers than [`PIN_BELOW`], a droplet) is
/// marked surface whole; a larger one — fluid sealed in a container — has only its highest
/// carrier along `up` (against gravity) pinned to p = 0, so the rest of it still gets its
/// pressure, non-negative below the pin (the pure-Neumann system is singular only by a
/// constant). Returns how many carriers were marked.
///
/// The regions are found by a parallel union–find over the inner fluid pairs; which carriers
/// form a region does not depend on the order of the unions, and everything chosen from the
/// regions (size, highest carrier, first of equals) is taken in row order afterwards, so the
/// result does not depend on the thread count.
pub(crate) fn mark_isolated(ctx: &Ctx, x: &[Vector], up: Vector, surface: &mut [bool]) -> usize {
    let nf = ctx.n_fluid();
    let h2 = ctx.kernel.support() * ctx.kernel.support();
    let regions = Regions::new(nf);
    let surf: &[bool] = surface;
    let touches: Vec<bool> = (0..nf)
        .into_par_iter()
        .map(|i| {
            if surf[i] {
                return false;
            }
            let mut t = false;
            for &j in &ctx.lists.indices[ctx.lists.fluid_range(i)] {
                let j = j as usize;
                if (x[j] - x[i]).length_squared() >= h2 {
                    continue;
                }
                if surf[j] {
                    t = true;
                } else if j > i {
                    regions.union(i as u32, j as u32);
                }
            }
            t
        })
        .collect();
    // every region's root is its smallest carrier index (links point downwards)
    let roots = regions.roots();
    let find = |a: u32| roots[a as usize];
    let mut root_ok = vec![false; nf];
    for i in 0..nf {
        if !surface[i] && touches[i] {
            let r = find(i as u32);
            root_ok[r as usize] = true;
        }
    }
    let mut size = vec![0u32; nf];
    let mut top: Vec<u32> = (0..nf as u32).collect();
    for i in 0..nf {
        if !surface[i] {
            let r = find(i as u32) as usize;
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
        let r = find(i as u32) as usize;
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
