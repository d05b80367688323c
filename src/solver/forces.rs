//! Body force and the generalized viscous force (He 2012 Eq. 24), then the prediction
//! ṽ = v + Δt (f + F^viscous/m) (Algorithm 1, lines 2–3).

use super::{for_rows, Ctx};
use crate::math::Vector;

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
            for &j in ctx.lists.row(i) {
                let j = j as usize;
                if j < nf {
                    if !fluid_visc {
                        continue;
                    }
                    let r = (x[j] - xi).length();
                    if r < h {
                        a += (v_old[j] - v0)
                            * (ctx.viscosity * vol * ctx.kernel.viscous_laplacian(r));
                    }
                } else {
                    let s = j - nf;
                    let b = ctx.solid_body[s];
                    let body = &ctx.bodies[b as usize];
                    if body.viscosity <= 0.0 || ctx.viscosity <= 0.0 {
                        continue;
                    }
                    let r = (ctx.solid_x[s] - xi).length();
                    if r >= h {
                        continue;
                    }
                    let n = ctx.solid_n[s];
                    let rel = ctx.solid_u[s] - v0;
                    let tangential = rel - n * rel.dot(n);
                    let mu = (ctx.viscosity * body.viscosity).sqrt();
                    let dv = tangential * (mu * vol * ctx.kernel.viscous_laplacian(r));
                    a += dv;
                    acc.add(s, -dv * (ctx.mass * dt));
                }
            }
        }
        *vi = v_old[i] + a * dt;
    })
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
                    // normal part (a free-slip wall does not hold the fluid back)
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
