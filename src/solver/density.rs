//! Density constraint (He 2012 Algorithm 2): iterations of density (Eq. 22) → EOS pressure
//! p^d ≥ 0 → generalized pressure force (Eq. 23) → velocity and position update. The loop
//! itself is in `FluidWorld::substep`, which moves dynamic bodies with each iteration's force.
//!
//! The EOS is LPSPH's with ħ_max = 0 in the paper; here it is the PCISPH stiffness derived from
//! Δt (Solenthaler & Pajarola 2009, Shao et al. 2014 Eq. 5): the pressure accumulates
//! `p^d += k (ρ − ρ̄)` over the iterations (clamped at 0), `k` chosen so that one iteration
//! removes the density error of a particle in a full rest neighbourhood, and the final force
//! moves the predicted positions and velocities once.

pub(crate) use super::wall_support::{push_direction, WallSupport};
use super::Ctx;
use crate::math::Vector;
use rayon::prelude::*;

/// Eq. 22: `ρ_i = m Σ_j W(|x_i − x_j|)` over fluid and solid neighbours (self included),
/// normalised so that a rest lattice has exactly ρ̄, and the neighbour count `N_i` (carriers
/// within the support, Eq. 7) of every fluid carrier at positions `x`.
///
/// With `asym`, the same neighbour loop also gives Eq. 25's asymmetry `|Σ_j (x_j − x_i) W_ij| /
/// Σ_j W_ij` (solid neighbours unweighted, self included in the sum of weights) for
/// [`super::surface::detect`], so the surface marking needs no loop of its own.
///
/// With `scale = (c, surface)`, it also gives each carrier's [`pressure_scale`] in `c` (the
/// density loop's first evaluation, so that the scale costs no pass of its own; `surface`:
/// the carriers it leaves at 1).
///
/// With `head` ([`WallHead`]), static wall carriers count as far as they are wet.
#[allow(clippy::too_many_arguments)]
pub(crate) fn density_and_count(
    ctx: &Ctx,
    x: &[Vector],
    rho: &mut [f32],
    count: &mut [u32],
    asym: Option<&mut [f32]>,
    scale: Option<(&mut [f32], &[bool])>,
    head: Option<&WallHead>,
) {
    match (asym, scale) {
        (Some(a), Some((t, surface))) => {
            eval::<true, true>(ctx, x, rho, count, a, t, head);
            pressure_scale(ctx, t, surface);
        }
        (Some(a), None) => eval::<true, false>(ctx, x, rho, count, a, &mut [], head),
        (None, Some((t, surface))) => {
            eval::<false, true>(ctx, x, rho, count, &mut [], t, head);
            pressure_scale(ctx, t, surface);
        }
        (None, None) => eval::<false, false>(ctx, x, rho, count, &mut [], &mut [], head),
    }
}

/// The static walls under [`crate::FluidParams::hydrostatic_walls`]: each wall carrier takes
/// the fluid's pressure carried hydrostatically to it (Adami et al. 2012), `p_s = p_i + ρ̄ (g −
/// a_i)·(x_s − x_i)`, `a_i` the carrier's acceleration over the last substeps, and stands for
/// water only as far as it is wet ([`wetness`]): a wall above the water borders air, so it
/// neither adds to the density of the water beside it nor pushes it. (Counted as water, the
/// tank's walls above the waterline packed the surface water beside them and held it up: the
/// five balls' far field stood 5 mm under the level its pressure gives.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WallHead<'a> {
    /// Gravity.
    pub gravity: Vector,
    /// Each fluid carrier's recent acceleration (may be empty: at rest).
    pub accel: &'a [Vector],
    /// ρ̄.
    pub rest: f32,
    /// Each solid carrier's wetness in [0, 1] ([`wetness`]).
    pub wet: &'a [f32],
}

impl<'a> WallHead<'a> {
    /// The walls of a world with the wetness `wet` (`None` when it is empty: no hydrostatic
    /// walls).
    pub(crate) fn new(
        gravity: Vector,
        accel: &'a [Vector],
        rest: f32,
        wet: &'a [f32],
    ) -> Option<Self> {
        (!wet.is_empty()).then_some(Self {
            gravity,
            accel,
            rest,
            wet,
        })
    }

    /// `p_s` of a wall carrier at `d = x_s − x_i` from fluid carrier `i` of pressure `p_i`.
    fn pressure(&self, i: usize, p_i: f32, d: Vector) -> f32 {
        let a = self.accel.get(i).copied().unwrap_or(Vector::ZERO);
        p_i + self.rest * (self.gravity - a).dot(d)
    }

    /// How much of solid carrier `s` stands for water.
    fn wet(&self, s: usize) -> f32 {
        self.wet.get(s).copied().unwrap_or(1.0)
    }
}

/// Per solid carrier, how much of it stands for water: 1 for carriers of moving bodies and
/// of ceilings (normal facing down against gravity: water pressed under a lid), else the share
/// of its layer `y_s ± Δx/2` under the water beside it, whose top layer reaches `top + Δx/2`
/// (`top` the highest fluid carrier within its support).
pub(crate) fn wetness(ctx: &Ctx, fluid_x: &[Vector], up: Vector, dx: f32) -> Vec<f32> {
    let nf = ctx.n_fluid();
    let h2 = ctx.kernel.support() * ctx.kernel.support();
    let mut top = vec![f32::NEG_INFINITY; ctx.solid_x.len()];
    for (i, &xi) in fluid_x.iter().enumerate().take(nf) {
        let yi = xi.dot(up);
        for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
            let s = j as usize - nf;
            if (ctx.solid_x[s] - xi).length_squared() < h2 && yi > top[s] {
                top[s] = yi;
            }
        }
    }
    top.par_iter()
        .enumerate()
        .map(|(s, &t)| {
            let fixed = ctx.bodies[ctx.solid_body[s] as usize].fixed;
            if !fixed || ctx.solid_n[s].dot(up) < -0.5 {
                return 1.0;
            }
            ((t - ctx.solid_x[s].dot(up) + dx) / dx).clamp(0.0, 1.0)
        })
        .collect()
}

/// Largest factor [`pressure_scale`] applies either way: in the bulk the carriers' moment
/// stays within a few percent of 1 (1.020 on the cubic rest lattice, 0.995 in a settled still
/// tank); a carrier with fewer neighbours (beside the free surface, not marked) is not
/// scaled beyond it.
const MAX_SCALE: f32 = 1.05;

/// [`crate::FluidParams::pressure_scale`]: per fluid carrier, `c_i = 3 / tr M_i` with
/// `M_i = Σ_j V_j d_ij d_ijᵀ |∇W_ij| / r_ij` over its fluid neighbours (`V = m/ρ̄`) and solid
/// ones (their volume, as far as they are wet), within [`MAX_SCALE`] of 1; 1 on the free
/// surface (`surface`, whose missing neighbours are air). `trace` holds `Σ_j v_j r_ij |∇W_ij|`
/// ([`density_and_count`]; `v` the volume over a fluid carrier's) and becomes the scale. The
/// symmetric force `−m Σ (c_i p_i/ρ_i² + c_j p_j/ρ_j²) ∇W_ij` of a linear pressure `p = p₀ +
/// b·x` in a region of like `c` is `−(c/ρ) M b`: with the scale, `−b/ρ` as an isotropic `M`
/// asks (still antisymmetric pair by pair, so momentum is kept). Without it, the still tank's
/// pressure settled rising 1.0064 ρ̄g with depth, its carriers' vertical moment 0.9936.
fn pressure_scale(ctx: &Ctx, trace: &mut [f32], surface: &[bool]) {
    let vol = ctx.mass / ctx.rest_density;
    trace.par_iter_mut().enumerate().for_each(|(i, t)| {
        let m = vol * *t / 3.0;
        *t = if surface.get(i).copied().unwrap_or(false) || m <= 0.0 {
            1.0
        } else {
            (1.0 / m).clamp(1.0 / MAX_SCALE, MAX_SCALE)
        };
    });
}

fn eval<const ASYM: bool, const TRACE: bool>(
    ctx: &Ctx,
    x: &[Vector],
    rho: &mut [f32],
    count: &mut [u32],
    asym: &mut [f32],
    trace: &mut [f32],
    head: Option<&WallHead>,
) {
    let nf = ctx.n_fluid();
    let k = &ctx.kernel;
    let h2 = k.support() * k.support();
    let scale = ctx.mass / ctx.kernel_norm;
    let w0 = k.w(0.0);
    let h = k.support();
    // r |∇W| (the trace of d dᵀ |∇W|/r) within the support, for [`pressure_scale`]
    let moment_trace = |r: f32| {
        if r < h && r > 1e-9 {
            r * k.grad_mag(r)
        } else {
            0.0
        }
    };
    let row = |buf: &mut Vec<(Vector, f32)>,
               i: usize,
               r: &mut f32,
               c: &mut u32,
               a: Option<&mut f32>,
               t: Option<&mut f32>| {
        let xi = x[i];
        let (mut s, mut n) = (w0, 0u32);
        let (mut fluid_trace, mut solid_trace) = (0.0f32, 0.0f32);
        let (mut moment, mut wsum) = (Vector::ZERO, w0);
        // the offsets first, then the kernel over all of them (a loop without gathers, which
        // vectorises), then the sums in neighbour order
        buf.clear();
        buf.extend(
            ctx.lists.indices[ctx.lists.fluid_range(i)]
                .iter()
                .map(|&j| (x[j as usize] - xi, 0.0)),
        );
        for (d, w) in buf.iter_mut() {
            // W is zero at and beyond the support: only the count needs the test
            let d2 = d.length_squared();
            let r = d2.sqrt();
            *w = k.w(r);
            n += (d2 < h2) as u32;
            if TRACE {
                fluid_trace += moment_trace(r);
            }
        }
        for &(d, w) in buf.iter() {
            s += w;
            if ASYM {
                moment += d * w;
                wsum += w;
            }
        }
        for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
            let sj = j as usize - nf;
            let d = ctx.solid_x[sj] - xi;
            let (d2, wet) = (d.length_squared(), head.map_or(1.0, |h| h.wet(sj)));
            let r = d2.sqrt();
            let w = k.w(r);
            s += ctx.solid_volume[sj] * w * wet;
            n += (d2 < h2) as u32;
            if TRACE {
                solid_trace += ctx.solid_volume[sj] * wet * moment_trace(r);
            }
            if ASYM {
                moment += d * w;
                wsum += w;
            }
        }
        *r = scale * s;
        *c = n;
        if let Some(a) = a {
            *a = moment.length() / wsum;
        }
        if let Some(t) = t {
            *t = fluid_trace + solid_trace;
        }
    };
    let rows = rho.par_iter_mut().zip(count.par_iter_mut());
    match (ASYM, TRACE) {
        (true, true) => rows
            .zip(asym.par_iter_mut().zip(trace.par_iter_mut()))
            .enumerate()
            .for_each_init(Vec::new, |b, (i, ((r, c), (a, t)))| {
                row(b, i, r, c, Some(a), Some(t))
            }),
        (true, false) => rows
            .zip(asym.par_iter_mut())
            .enumerate()
            .for_each_init(Vec::new, |b, (i, ((r, c), a))| {
                row(b, i, r, c, Some(a), None)
            }),
        (false, true) => rows
            .zip(trace.par_iter_mut())
            .enumerate()
            .for_each_init(Vec::new, |b, (i, ((r, c), t))| {
                row(b, i, r, c, None, Some(t))
            }),
        (false, false) => rows
            .enumerate()
            .for_each_init(Vec::new, |b, (i, (r, c))| row(b, i, r, c, None, None)),
    }
}

thread_local! {
    /// Per-thread pair buffer of [`pressure_accel`].
    static PAIRS: std::cell::RefCell<Vec<(Vector, f32)>> = const { std::cell::RefCell::new(Vec::new()) };
    /// Its second field's (a [`Spring`]'s `p_{k−1}`).
    static PAIRS_OLD: std::cell::RefCell<Vec<f32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// PCISPH stiffness `k = c ρ̄² / (m² Δt² Σ|∇W|²)` (see module doc; `c` the lattice normalisation).
pub(crate) fn stiffness(ctx: &Ctx, grad_sq_sum: f32, dt: f32) -> f32 {
    0.5 * ctx.kernel_norm * ctx.rest_density * ctx.rest_density
        / (ctx.mass * ctx.mass * dt * dt * grad_sq_sum)
}

/// `p_s`: the pressure Eq. 23 mirrors onto a moving rigid shell's carrier at `d = x_s − x_i`
/// from fluid carrier `i` of pressure `p_i`, carried there hydrostatically, `p_i + ρ̄ g·d`
/// (≥ 0). As printed (`p_s = p_i`) a body's bottom carrier, above the water it presses on,
/// mirrored the deeper pressure and pushed that water away: it settled 0.54Δx under the face
/// instead of 0.5Δx, and a box of 500 kg/m³ floated 2.8 % high once the body's weight was
/// shared with the water beside it (`share_weight`); carried: 0.50Δx, 0.2 % high. Not on
/// deformable bodies' SBPs: there it sank the stiff LSM box 1 mm past Archimedes (50.77 mm
/// against 49.74 without, 50.0 asked) and took the elastic box's wall push from 0.967 to
/// 0.949 of hydrostatic (not traced).
#[inline]
pub(crate) fn mirrored(p_i: f32, rho_g: Vector, d: Vector) -> f32 {
    (p_i + rho_g.dot(d)).max(0.0)
}

/// How solid carriers push in [`pressure_accel`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum WallPush<'a> {
    /// Eq. 23: the fluid pressure mirrored, along the solid's normal; at moving rigid shells
    /// carried to the wall carrier by `ρ̄ g` ([`mirrored`]; zero: as printed).
    Normal(Vector),
    /// Akinci et al. 2012 boundary particles (Shao 2014 Eq. 7).
    Akinci,
    /// At static solids, the fluid pressure carried to the wall carrier by the momentum
    /// balance `∇p = ρ (g − a_i)` (gravity, each carrier's acceleration over the last
    /// substeps), along the pair (Adami et al. 2012; [`crate::FluidParams::hydrostatic_walls`]);
    /// moving solids push as with `Normal`.
    Hydrostatic(WallHead<'a>),
}

/// Generalized pressure force (Eq. 23) of the pressure field `p` as accelerations `accel`;
/// returns the per-body reaction impulses over a step `dt`.
///
/// Fluid pairs push along `x_i − x_j` with `m (p_i/ρ_i² + p_j/ρ_j²) |∇W|`: the symmetric SPH
/// form, antisymmetric (fluid momentum is conserved exactly) and the full gradient of a smooth
/// field, where Eq. 23 as printed, `(p_i + p_j)/2ρ_j`, gives half of it. A solid carrier mirrors
/// the fluid pressure (`m (p_i + p_s)/ρ_i²`, [`mirrored`]) and pushes along its outward normal with the directional derivative `∂W/∂n ≥ 0` (clamped so a carrier
/// that penetrated is never pulled inward). Walls never pull: negative pressures act on fluid
/// pairs only. With `support` ([`WallSupport`]) the push follows the shape's normal at the
/// fluid carrier, and fluid pairs beside walls carry the corrected gradient along gravity
/// `−m Σ (p_i/ρ_i² L̃_i + p_j/ρ_j² L̃_j) ∇W_ij` (still antisymmetric: momentum is kept).
///
/// With [`WallPush::Akinci`] the solid carriers act as in Akinci et al. 2012 (Shao 2014 Eq. 7)
/// instead, along the pair direction and weighted by `ψ_s = ρ̄ V_s` (the carrier's relative
/// volume), with
/// the fluid pressure mirrored onto the boundary carrier: `a_i = −ψ_s 2 (p_i/ρ_i²) ∇W_is`.
/// With the single `p_i/ρ_i²` of Eq. 7 as printed, the floor of a still tank carried 0.967 of
/// the fluid's weight and the fluid moved at up to 0.5 m/s (mirrored: 0.996–1.000).
///
/// With a [`Spring`] the same pass also gives the density loop's relaxed accelerations.
#[allow(clippy::too_many_arguments)]
pub(crate) fn pressure_accel<P: Copy + Into<f64> + Sync>(
    ctx: &Ctx,
    x: &[Vector],
    p: &[P],
    rho: &[f32],
    accel: &mut [Vector],
    dt: f32,
    walls: WallPush<'_>,
    support: Option<&WallSupport>,
    scale: &[f32],
    spring: Option<Spring<'_>>,
) -> super::Impulses {
    // c p/ρ² once per carrier, not once per pair
    let pr = over_rho2(p, rho, scale);
    let pass = Pass {
        ctx,
        x,
        rho,
        dt,
        walls,
        support,
        scale,
    };
    match spring {
        None => pass.rows(
            accel,
            &mut [],
            Fields {
                p: |i| [Into::<f64>::into(p[i]) as f32],
                pr: [&pr[..]],
                weight: [1.0],
            },
            None,
        ),
        Some(sp) => {
            let pr_old = over_rho2(sp.p, rho, scale);
            pass.rows(
                accel,
                sp.next,
                Fields {
                    p: |i| [Into::<f64>::into(p[i]) as f32, sp.p[i]],
                    pr: [&pr[..], &pr_old[..]],
                    weight: [1.0, -sp.lag],
                },
                Some((sp.ahead, sp.lag)),
            )
        }
    }
}

/// `c p/ρ²` per carrier, `c` its [`pressure_scale`] (1 where `scale` is empty; an f32
/// pressure passes through f64 unchanged).
fn over_rho2<P: Copy + Into<f64> + Sync>(p: &[P], rho: &[f32], scale: &[f32]) -> Vec<f32> {
    p.par_iter()
        .zip(rho.par_iter())
        .enumerate()
        .map(|(i, (&p, &r))| scale.get(i).copied().unwrap_or(1.0) * p.into() as f32 / (r * r))
        .collect()
}

/// The split relaxation of the density loop's positions
/// (`crate::step::density::DensityLoop::position_relaxation`): besides the force `a(p_k)`,
/// [`pressure_accel`] writes the accelerations the positions follow,
/// `ā_k = a(p_k) − λ (a(p_{k−1}) − ā_{k−1})` (`λ = 1 − α`): the last iteration's pressure at
/// the moved positions (the spring) relaxed, the pressure's increment in full, from the
/// same neighbour pass. Its impulses are those of `a(p_k) − λ a(p_{k−1})`; the caller adds
/// `λ` times `ā_{k−1}`'s. `a(p_k)` itself stays the force the displacement cap and the
/// surface extrapolation read (with `ā` in its place, a single combined field
/// `p_k − λ p_{k−1}` would do for the fluid pairs, but a hot melting scene then lost a
/// carrier out of the domain; same wall time).
pub(crate) struct Spring<'a> {
    /// `p_{k−1}`.
    pub p: &'a [f32],
    /// `λ = 1 − α`.
    pub lag: f32,
    /// `ā_{k−1}`.
    pub ahead: &'a [Vector],
    /// Out: `ā_k`.
    pub next: &'a mut [Vector],
}

/// The pressure fields one pass of [`pressure_accel`] takes: each carrier's pressures, the
/// `p/ρ²` per carrier, and each field's weight in the impulses.
struct Fields<'a, F, const N: usize> {
    p: F,
    pr: [&'a [f32]; N],
    weight: [f32; N],
}

/// What one pass of [`pressure_accel`] reads besides the pressures.
#[derive(Clone, Copy)]
struct Pass<'c> {
    ctx: &'c Ctx<'c>,
    x: &'c [Vector],
    rho: &'c [f32],
    dt: f32,
    walls: WallPush<'c>,
    support: Option<&'c WallSupport>,
    /// Per carrier, its [`pressure_scale`] (empty: 1).
    scale: &'c [f32],
}

impl Pass<'_> {
    /// The rows of [`pressure_accel`] for `N` (1 or 2) pressure fields: field 0's force into
    /// `accel`; with `relax = (ā_{k−1}, λ)` the [`Spring`]'s `ā_k` into `next`. The impulses
    /// are the fields' weighted sum.
    fn rows<F: Fn(usize) -> [f32; N] + Sync, const N: usize>(
        self,
        accel: &mut [Vector],
        next: &mut [Vector],
        f: Fields<'_, F, N>,
        relax: Option<(&[Vector], f32)>,
    ) -> super::Impulses {
        let Pass {
            ctx,
            x,
            rho,
            dt,
            walls,
            support,
            scale,
        } = self;
        let nf = ctx.n_fluid();
        let h = ctx.kernel.support();
        let rho_g = match walls {
            WallPush::Normal(rho_g) => rho_g,
            WallPush::Hydrostatic(h) => h.gravity * h.rest,
            WallPush::Akinci => Vector::ZERO,
        };
        super::for_rows2(accel, next, |i, ai, next_i, acc| {
            let xi = x[i];
            let pi = (f.p)(i);
            let pri: [f32; N] = std::array::from_fn(|k| f.pr[k][i]);
            // the scale applies to the wall's mirrored pressure as to the carrier's own
            let c_i = scale.get(i).copied().unwrap_or(1.0);
            let mut a = self.fluid_pairs(i, pri, f.pr);
            if pi.iter().any(|&p| p > 0.0) {
                for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
                    let s = j as usize - nf;
                    let d = xi - ctx.solid_x[s];
                    let r = d.length();
                    if r >= h || r <= 1e-9 {
                        continue;
                    }
                    let psi = ctx.solid_volume[s] * ctx.mass;
                    let body = ctx.bodies[ctx.solid_body[s] as usize];
                    // static walls only: a moving body keeps Eq. 23's push along its normal
                    // (along the pair, the wall pressure has a torque about a ball's centre)
                    let hydro = match walls {
                        WallPush::Hydrostatic(h) if body.fixed => Some(h),
                        _ => None,
                    };
                    let akinci = matches!(walls, WallPush::Akinci);
                    let (n, arm) = match support {
                        Some(w) if hydro.is_none() && !akinci => {
                            w.normal(i, ctx.solid_body[s], ctx.solid_n[s])
                        }
                        _ => (ctx.solid_n[s], None),
                    };
                    let mut dj = Vector::ZERO;
                    for k in 0..N {
                        if pi[k] <= 0.0 {
                            continue;
                        }
                        let da = if let Some(h) = hydro {
                            // the wall carrier takes the fluid's pressure carried
                            // hydrostatically to it (Adami et al. 2012) and pushes along the
                            // pair like a fluid neighbour, as far as it is wet
                            let (ps, wet) = (h.pressure(i, pi[k], -d).max(0.0), h.wet(s));
                            d * (wet
                                * psi
                                * (pri[k] + c_i * ps / (rho[i] * rho[i]))
                                * ctx.kernel.grad_mag(r)
                                / r)
                        } else if akinci {
                            d * (psi * 2.0 * pri[k] * ctx.kernel.grad_mag(r) / r)
                        } else {
                            // Eq. 23 for a fluid–solid pair: along the solid normal, with the
                            // directional derivative clamped so a carrier that penetrated is
                            // never pulled inward
                            let cos = (d.dot(n) / r).max(0.0);
                            let ps = if body.carried {
                                mirrored(pi[k], rho_g, -d)
                            } else {
                                pi[k]
                            };
                            n * (psi
                                * (pri[k] + c_i * ps / (rho[i] * rho[i]))
                                * ctx.kernel.grad_mag(r)
                                * cos)
                        };
                        a[k] += da;
                        dj += da * f.weight[k];
                    }
                    let j = -dj * (ctx.mass * dt);
                    acc.add(s, j);
                    if let (Some(arm), Some(w)) = (arm, support) {
                        // the push acts along its line at the body's surface point nearest
                        // x_i: the reaction's torque about the centre takes that arm, not the
                        // carrier's (a ball's pushes pass through its centre whatever the
                        // water does)
                        let b = ctx.solid_body[s];
                        let at = w.start[s] - ctx.bodies[b as usize].com;
                        acc.add_couple(b, (arm - at).cross(j));
                    }
                }
            }
            *ai = a[0];
            if let (Some(o), Some((ahead, lag))) = (next_i, relax) {
                *o = a[0] + lag * (ahead[i] - a[N - 1]);
            }
        })
    }

    /// The fluid pairs' part of carrier `i`'s force for each field (`p/ρ²`: `pri` its own,
    /// `pr` all carriers').
    fn fluid_pairs<const N: usize>(self, i: usize, pri: [f32; N], pr: [&[f32]; N]) -> [Vector; N] {
        let (ctx, x, xi) = (self.ctx, self.x, self.x[i]);
        let mut a = [Vector::ZERO; N];
        PAIRS.with(|buf| {
            PAIRS_OLD.with(|old| {
                let (mut buf, mut old) = (buf.borrow_mut(), old.borrow_mut());
                let idx = &ctx.lists.indices[ctx.lists.fluid_range(i)];
                // gather (offset, p_j/ρ_j²), then the kernel over all pairs (no gathers, so it
                // vectorises), then the sum in neighbour order
                buf.clear();
                buf.extend(idx.iter().map(|&j| (x[j as usize] - xi, pr[0][j as usize])));
                old.clear();
                if N > 1 {
                    old.extend(idx.iter().map(|&j| pr[N - 1][j as usize]));
                }
                if let Some(w) = self.support.filter(|w| w.near[i]) {
                    let ti = w.tang[i];
                    for (k, (&j, &(d, prj))) in idx.iter().zip(buf.iter()).enumerate() {
                        let r = d.length();
                        let c = ctx.mass * ctx.kernel.grad_mag(r) / r.max(1e-9);
                        let tj = w.tang[j as usize];
                        let (di, dj) = (ti.apply(d), tj.apply(d));
                        a[0] -= (di * pri[0] + dj * prj) * c;
                        if N > 1 {
                            a[N - 1] -= (di * pri[N - 1] + dj * old[k]) * c;
                        }
                    }
                    return;
                }
                for (k, (d, c)) in buf.iter_mut().enumerate() {
                    let r = d.length();
                    // |∇W| is zero at and beyond the support; coincident carriers exert nothing
                    let (g, rm) = (ctx.kernel.grad_mag(r), r.max(1e-9));
                    *c = ctx.mass * (pri[0] + *c) * g / rm;
                    if N > 1 {
                        old[k] = ctx.mass * (pri[N - 1] + old[k]) * g / rm;
                    }
                }
                for &(d, c) in buf.iter() {
                    a[0] -= d * c;
                }
                if N > 1 {
                    for (&(d, _), &c) in buf.iter().zip(old.iter()) {
                        a[N - 1] -= d * c;
                    }
                }
            })
        });
        a
    }
}
