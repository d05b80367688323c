//! Body force and the generalized viscous force (He 2012 Eq. 24), then the prediction
//! ṽ = v + Δt (f + F^viscous/m) (Algorithm 1, lines 2–3).

use super::{for_rows, Ctx};
use crate::math::Vector;
use crate::solver::staggered::Slip;

/// Adds gravity and the generalized viscous force (Eq. 24) to the fluid velocities `v` (in
/// place) and returns the per-body reaction impulses.
///
/// Eq. 24's ∇²W is replaced by the positive weight `2|W'|/r` (Morris et al. 1997); fluid–solid
/// pairs use `sqrt(μ^f μ^s)` and only the tangential relative velocity (operator T).
pub(crate) fn viscous_prediction(
    ctx: &Ctx,
    x: &[Vector],
    v_old: &[Vector],
    v: &mut [Vector],
    gravity: Vector,
    dt: f32,
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    let vol = ctx.mass / ctx.rest_density;
    let fluid_visc = ctx.viscosity > 0.0;
    let any_wall_visc = ctx.bodies.iter().any(|b| b.viscosity > 0.0);
    for_rows(v, |i, vi, acc| {
        let mut a = gravity;
        if fluid_visc || any_wall_visc {
            let (xi, v0) = (x[i], v_old[i]);
            for &j in &ctx.lists.indices[ctx.lists.fluid_range(i)] {
                if !fluid_visc {
                    break;
                }
                let j = j as usize;
                let r = (x[j] - xi).length();
                if r < h {
                    a += (v_old[j] - v0) * (ctx.viscosity * vol * ctx.kernel.viscous_laplacian(r));
                }
            }
            // wall shear: each pair's tangential rate c (u − v)_t, taken point-implicitly in
            // the carrier's own velocity: the acceleration along the walls is divided by
            // (1 + Δt Σc) (exact for one flat wall), so a boundary layer of any viscosity is
            // stable at the step's length and reaches the same balance
            if any_wall_visc && ctx.viscosity > 0.0 {
                WALL_PAIRS.with(|buf| {
                    let mut pairs = buf.borrow_mut();
                    pairs.clear();
                    let (mut wall, mut c_sum, mut n_sum) = (Vector::ZERO, 0.0f32, Vector::ZERO);
                    for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
                        if let Some((s, c, t)) = wall_shear(ctx, xi, v0, j as usize - nf, h, vol) {
                            wall += t * c;
                            c_sum += c;
                            n_sum += ctx.solid_n[s] * c;
                            pairs.push((s, c));
                        }
                    }
                    if c_sum > 0.0 {
                        let k = 1.0 / (1.0 + dt * c_sum);
                        let n = n_sum.try_normalize().unwrap_or(Vector::ZERO);
                        let other = a - n * a.dot(n);
                        // what the walls change: k (a_t + wall) − a_t, shared as c/Σc
                        let by_walls = wall * k - other * (1.0 - k);
                        a += by_walls;
                        let share = ctx.mass * dt / c_sum;
                        for &(s, c) in pairs.iter() {
                            acc.add(s, -by_walls * (c * share));
                        }
                    }
                });
            }
        }
        *vi = v_old[i] + a * dt;
    })
}

thread_local! {
    /// Per-thread (solid carrier, rate) pairs of one fluid carrier's wall shear, so the
    /// reaction is shared out without evaluating the pairs twice.
    static WALL_PAIRS: std::cell::RefCell<Vec<(usize, f32)>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// The wall shear between fluid carrier `i` (at `xi`, velocity `v0`) and solid carrier `s`:
/// the solid's index, the rate `c = sqrt(μ^f μ^s) V ∇²W · β` (1/s) and the tangential
/// relative velocity `(u − v)_t`, or `None` if the pair has no wall viscosity or is beyond
/// the support. `β = 1 + d_s/d_i` puts the wall velocity on the wall's surface (Morris et al.
/// 1997: the solid carrier's velocity mirrored, `d_s` its depth, `d_i` the fluid carrier's
/// distance to the surface along the normal, at least a quarter spacing), so that the shear on
/// the first layer is `μ (v − u)/d_i` as in a resolved boundary layer.
#[inline]
pub(crate) fn wall_shear(
    ctx: &Ctx,
    xi: Vector,
    v0: Vector,
    s: usize,
    h: f32,
    vol: f32,
) -> Option<(usize, f32, Vector)> {
    let body = &ctx.bodies[ctx.solid_body[s] as usize];
    if body.viscosity <= 0.0 {
        return None;
    }
    let d = xi - ctx.solid_x[s];
    let r = d.length();
    if r >= h {
        return None;
    }
    let n = ctx.solid_n[s];
    let rel = ctx.solid_u[s] - v0;
    let tangential = rel - n * rel.dot(n);
    let mu = (ctx.viscosity * body.viscosity).sqrt();
    let beta = match body.slip {
        Slip::BoundaryLayer => {
            let ds = ctx.solid_depth.get(s).copied().unwrap_or(0.25 * h).max(0.0);
            let di = (d.dot(n) - ds).max(0.125 * h);
            1.0 + ds / di
        }
        _ => 1.0,
    };
    Some((
        s,
        mu * vol * ctx.kernel.viscous_laplacian(r) * beta,
        tangential,
    ))
}

/// XSPH velocity smoothing (Monaghan 1989): `v_i += ε Σ_j 2m/(ρ_i + ρ_j) W_ij (v_j − v_i)`
/// over fluid neighbours. The pair weight is symmetric, so the fluid's momentum is unchanged
/// to round-off. It plays the part of the averaging in the paper's Eq. 19 remap (carrier
/// velocity from its staggered particles), which the momentum-conserving projection
/// ([`crate::params::Remap::Consistent`]) does not have.
pub(crate) fn xsph(
    ctx: &Ctx,
    x: &[Vector],
    v_in: &[Vector],
    rho: &[f32],
    eps: f32,
    walls: bool,
    v: &mut [Vector],
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    for_rows(v, |i, vi, acc| {
        let (xi, v0) = (x[i], v_in[i]);
        let mut dv = Vector::ZERO;
        for &j in &ctx.lists.indices[ctx.lists.fluid_range(i)] {
            let j = j as usize;
            let r = (x[j] - xi).length();
            if r < h {
                dv += (v_in[j] - v0) * (2.0 * ctx.mass / (rho[i] + rho[j]) * ctx.kernel.w(r));
            }
        }
        if walls {
            for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
                let s = j as usize - nf;
                let r = (ctx.solid_x[s] - xi).length();
                if r < h {
                    let w = ctx.solid_volume[s] * ctx.mass / rho[i].max(1e-6) * ctx.kernel.w(r);
                    let rel = ctx.solid_u[s] - v0;
                    // a no-slip wall averages the whole relative velocity, others only its
                    // normal part (their friction is the viscous force's)
                    let rel = match ctx.bodies[ctx.solid_body[s] as usize].slip {
                        crate::solver::staggered::Slip::NoSlip => rel,
                        _ => {
                            let n = ctx.solid_n[s];
                            n * n.dot(rel)
                        }
                    };
                    let d = rel * (w * eps);
                    dv += rel * w;
                    // the carrier's momentum change goes to the wall
                    acc.add(s, -d * ctx.mass);
                }
            }
        }
        *vi = v0 + dv * eps;
    })
}
