//! Density constraint (He 2012 Algorithm 2): iterations of density (Eq. 22) → EOS pressure
//! p^d ≥ 0 → generalized pressure force (Eq. 23) → velocity and position update. The loop
//! itself is in `FluidWorld::substep`, which moves dynamic bodies with each iteration's force.
//!
//! The EOS is LPSPH's with ħ_max = 0 in the paper; here it is the PCISPH stiffness derived from
//! Δt (Solenthaler & Pajarola 2009, Shao et al. 2014 Eq. 5): the pressure accumulates
//! `p^d += k (ρ − ρ̄)` over the iterations (clamped at 0), `k` chosen so that one iteration
//! removes the density error of a particle in a full rest neighbourhood, and the final force
//! moves the predicted positions and velocities once.

use super::{for_rows, Ctx, ROWS};
use crate::math::Pose;
use crate::math::Vector;
use rapier3d::parry::shape::SharedShape;
use rayon::prelude::*;

/// Eq. 22: `ρ_i = m Σ_j W(|x_i − x_j|)` over fluid and solid neighbours (self included),
/// normalised so that a rest lattice has exactly ρ̄, and the neighbour count `N_i` (carriers
/// within the support, Eq. 7) of every fluid carrier at positions `x`.
///
/// With `asym`, the same neighbour loop also gives Eq. 25's asymmetry `|Σ_j (x_j − x_i) W_ij| /
/// Σ_j W_ij` (solid neighbours unweighted, self included in the sum of weights) for
/// [`super::surface::detect`], so the surface marking needs no loop of its own.
///
/// With `head` ([`WallHead`]), static wall carriers count as far as they are wet.
pub(crate) fn density_and_count(
    ctx: &Ctx,
    x: &[Vector],
    rho: &mut [f32],
    count: &mut [u32],
    asym: Option<&mut [f32]>,
    head: Option<&WallHead>,
) {
    match asym {
        Some(a) => eval::<true>(ctx, x, rho, count, a, head),
        None => eval::<false>(ctx, x, rho, count, &mut [], head),
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

fn eval<const ASYM: bool>(
    ctx: &Ctx,
    x: &[Vector],
    rho: &mut [f32],
    count: &mut [u32],
    asym: &mut [f32],
    head: Option<&WallHead>,
) {
    let nf = ctx.n_fluid();
    let k = &ctx.kernel;
    let h2 = k.support() * k.support();
    let scale = ctx.mass / ctx.kernel_norm;
    let w0 = k.w(0.0);
    let row =
        |buf: &mut Vec<(Vector, f32)>, i: usize, r: &mut f32, c: &mut u32, a: Option<&mut f32>| {
            let xi = x[i];
            let (mut s, mut n) = (w0, 0u32);
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
                *w = k.w(d2.sqrt());
                n += (d2 < h2) as u32;
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
                let d2 = d.length_squared();
                let w = k.w(d2.sqrt());
                s += ctx.solid_volume[sj] * w * head.map_or(1.0, |h| h.wet(sj));
                n += (d2 < h2) as u32;
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
        };
    if ASYM {
        rho.par_iter_mut()
            .zip(count.par_iter_mut())
            .zip(asym.par_iter_mut())
            .enumerate()
            .for_each_init(Vec::new, |b, (i, ((r, c), a))| row(b, i, r, c, Some(a)));
    } else {
        rho.par_iter_mut()
            .zip(count.par_iter_mut())
            .enumerate()
            .for_each_init(Vec::new, |b, (i, (r, c))| row(b, i, r, c, None));
    }
}

thread_local! {
    /// Per-thread pair buffer of [`pressure_accel`].
    static PAIRS: std::cell::RefCell<Vec<(Vector, f32)>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// PCISPH stiffness `k = c ρ̄² / (m² Δt² Σ|∇W|²)` (see module doc; `c` the lattice normalisation).
pub(crate) fn stiffness(ctx: &Ctx, grad_sq_sum: f32, dt: f32) -> f32 {
    0.5 * ctx.kernel_norm * ctx.rest_density * ctx.rest_density
        / (ctx.mass * ctx.mass * dt * dt * grad_sq_sum)
}

/// What [`crate::FluidParams::wall_support`] adds to [`pressure_accel`], built once per
/// substep from the predicted positions.
pub(crate) struct WallSupport {
    /// Per fluid carrier, its [`Tangential`] correction.
    tang: Vec<Tangential>,
    /// Per fluid carrier, whether it or a fluid neighbour has a correction (its pairs then
    /// take the corrected form).
    near: Vec<bool>,
    /// Per fluid carrier `i`, `entries[offsets[i]..offsets[i + 1]]`: each solid beside it,
    /// that solid's outward surface normal at `x_i` and the surface point nearest `x_i` (where
    /// the push acts on the body), relative to the solid's centre.
    offsets: Vec<u32>,
    entries: Vec<(u32, Vector, Vector)>,
    /// The solid carriers' places when built (before the loop's iterations move the bodies):
    /// the reactions' arms (`FluidWorld::absorb_shared_from`).
    start: Vec<Vector>,
}

/// The gradient correction of a fluid carrier beside a wall, along gravity: `L̃ = 𝟙 + σ u uᵀ`,
/// `u` the wall-tangent part of gravity's direction and `1 + σ` the ratio of the kernel moment
/// along `u` of all the carrier's neighbours (fluid and solid) to that of its fluid neighbours
/// alone, at most [`MAX_RESTORE`]. The density constraint carries the hydrostatic load; beside
/// a vertical wall the fluid pairs alone give about 1/1.18 of the gradient along gravity (on
/// the lattice), so a flank carrier leaned on the water below it, whose extra pressure then
/// acted on the bottom of the body beside it. Identity away from walls, beside walls square
/// to gravity (a floor: the flow along it is the velocity constraint's) and on free-surface
/// carriers (whose missing neighbours are air).
#[derive(Debug, Clone, Copy, Default)]
struct Tangential {
    sigma: f32,
    u: Vector,
}

impl Tangential {
    /// `L̃ d`.
    #[inline]
    fn apply(self, d: Vector) -> Vector {
        d + self.u * (self.u.dot(d) * self.sigma)
    }
}

/// The largest `1 + σ` of a [`Tangential`] correction: about the lattice's own ratio beside a
/// flat wall (1.18). Along an edge of two walls the lattice gives 1.40, but restoring that
/// much (a cap of 1.5) made the still tank at rapier's 1/60 s erupt (0.28 J at 5.6 ms
/// substeps; 0.049 J with this cap): at edges and corners the few fluid neighbours' moment
/// says little, and the larger gain destabilises the density iterations.
const MAX_RESTORE: f32 = 1.2;

/// Smallest share of gravity along a wall (sine of the wall's tilt from square) for which
/// the gradient along gravity is restored beside it.
const MIN_TILT: f32 = 0.25;

/// Cosine of the largest angle between a solid carrier's normal and its shape's normal at a
/// fluid carrier for which the push follows the latter (beyond it, as at the inner corner of a
/// concave shape, the carrier's own normal).
const NORMAL_AGREEMENT: f32 = 0.5;

impl WallSupport {
    /// Builds the corrections for fluid carriers at `x` (`surface`: the last step's
    /// free-surface flags; `down`: gravity's direction; `shapes`: each solid's shape and pose).
    pub(crate) fn new(
        ctx: &Ctx,
        x: &[Vector],
        surface: &[bool],
        down: Vector,
        shapes: &[Option<(SharedShape, Pose)>],
    ) -> Self {
        let nf = ctx.n_fluid();
        let tang: Vec<Tangential> = (0..nf)
            .into_par_iter()
            .map(|i| tangential(ctx, x, surface, down, i))
            .collect();
        let near: Vec<bool> = (0..nf)
            .into_par_iter()
            .map(|i| {
                tang[i].sigma != 0.0
                    || ctx.lists.indices[ctx.lists.fluid_range(i)]
                        .iter()
                        .any(|&j| tang[j as usize].sigma != 0.0)
            })
            .collect();
        let rows: Vec<Vec<(u32, Vector, Vector)>> = (0..nf.div_ceil(ROWS))
            .into_par_iter()
            .map(|c| {
                let mut out = Vec::new();
                let rows = c * ROWS..((c + 1) * ROWS).min(nf);
                for (i, &xi) in rows.clone().zip(&x[rows]) {
                    let start = out.len();
                    for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
                        let b = ctx.solid_body[j as usize - nf];
                        if out[start..]
                            .iter()
                            .any(|e: &(u32, Vector, Vector)| e.0 == b)
                        {
                            continue;
                        }
                        // (a deformable body has no exact shape: its carriers' own normals)
                        let nq = shapes[b as usize].as_ref().and_then(|(shape, pose)| {
                            crate::sampling::nearest_surface(shape.as_ref(), pose, xi)
                        });
                        let com = ctx.bodies[b as usize].com;
                        out.push(
                            nq.map_or((b, Vector::ZERO, Vector::ZERO), |(n, q)| (b, n, q - com)),
                        );
                    }
                    out.push((u32::MAX, Vector::ZERO, Vector::ZERO));
                }
                out
            })
            .collect();
        // rows are closed by a sentinel: offsets from them, the sentinels dropped
        let mut offsets = Vec::with_capacity(nf + 1);
        let mut entries = Vec::new();
        offsets.push(0u32);
        for e in rows.into_iter().flatten() {
            if e.0 == u32::MAX {
                offsets.push(entries.len() as u32);
            } else {
                entries.push(e);
            }
        }
        Self {
            tang,
            near,
            offsets,
            entries,
            start: ctx.solid_x.to_vec(),
        }
    }

    /// The push direction of solid carrier `s` (of solid `b`, normal `n_s`) on fluid carrier
    /// `i`: its shape's normal at `x_i` where that agrees with `n_s`, else `n_s`; and, when it
    /// follows the shape, the point where it acts on the body (its surface point nearest `x_i`,
    /// relative to the centre).
    #[inline]
    fn normal(&self, i: usize, b: u32, n_s: Vector) -> (Vector, Option<Vector>) {
        let row = &self.entries[self.offsets[i] as usize..self.offsets[i + 1] as usize];
        row.iter()
            .find(|e| e.0 == b)
            .and_then(|e| shape_push(Some(e.1), n_s).map(|n| (n, Some(e.2))))
            .unwrap_or((n_s, None))
    }
}

/// The direction a solid carrier (normal `n_s`) pushes a fluid carrier with `wall_support`:
/// its shape's normal at the fluid carrier `n` where that agrees with `n_s`, else `n_s`.
pub(crate) fn push_direction(n: Option<Vector>, n_s: Vector) -> Vector {
    shape_push(n, n_s).unwrap_or(n_s)
}

/// The shape's normal at the fluid carrier, `n`, if the push follows it (it agrees with `n_s`).
fn shape_push(n: Option<Vector>, n_s: Vector) -> Option<Vector> {
    n.filter(|&n| n != Vector::ZERO && n.dot(n_s) > NORMAL_AGREEMENT)
}

/// [`Tangential`] of fluid carrier `i`.
fn tangential(ctx: &Ctx, x: &[Vector], surface: &[bool], down: Vector, i: usize) -> Tangential {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    if surface.get(i).copied().unwrap_or(false) {
        return Tangential::default();
    }
    let xi = x[i];
    let pairs = |range: std::ops::Range<usize>, solid: bool| {
        ctx.lists.indices[range].iter().filter_map(move |&j| {
            let (p, v) = if solid {
                let s = j as usize - nf;
                (ctx.solid_x[s], ctx.solid_volume[s])
            } else {
                (x[j as usize], 1.0)
            };
            let d = p - xi;
            let r = d.length();
            (r < h && r > 1e-9).then(|| (d, v * ctx.kernel.grad_mag(r) / r))
        })
    };
    // the wall's normal: the direction of the solid neighbours' kernel gradient
    let toward: Vector = pairs(ctx.lists.solid_range(i), true)
        .map(|(d, g)| d * g)
        .fold(Vector::ZERO, |a, b| a + b);
    let Some(n) = toward.try_normalize() else {
        return Tangential::default();
    };
    let t = down - n * n.dot(down);
    if t.length() < MIN_TILT {
        return Tangential::default();
    }
    let u = t.normalize();
    let moment = |(d, g): (Vector, f32)| g * u.dot(d).powi(2);
    let ts: f32 = pairs(ctx.lists.solid_range(i), true).map(moment).sum();
    let tf: f32 = pairs(ctx.lists.fluid_range(i), false).map(moment).sum();
    if tf <= 0.0 {
        return Tangential::default();
    }
    Tangential {
        sigma: ((tf + ts) / tf).min(MAX_RESTORE) - 1.0,
        u,
    }
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
) -> super::Impulses {
    let nf = ctx.n_fluid();
    let h = ctx.kernel.support();
    let rho_g = match walls {
        WallPush::Normal(rho_g) => rho_g,
        WallPush::Hydrostatic(h) => h.gravity * h.rest,
        WallPush::Akinci => Vector::ZERO,
    };
    // p/ρ² once per carrier, not once per pair
    let pr: Vec<f32> = p
        .par_iter()
        .zip(rho.par_iter())
        .map(|(&p, &r)| p.into() as f32 / (r * r))
        .collect();
    for_rows(accel, |i, ai, acc| {
        let (xi, pi) = (x[i], p[i].into() as f32);
        let mut a = Vector::ZERO;
        let pri = pr[i];
        PAIRS.with(|buf| {
            let mut buf = buf.borrow_mut();
            // gather (offset, p_j/ρ_j²), then the kernel over all pairs (no gathers, so it
            // vectorises), then the sum in neighbour order
            buf.clear();
            buf.extend(
                ctx.lists.indices[ctx.lists.fluid_range(i)]
                    .iter()
                    .map(|&j| (x[j as usize] - xi, pr[j as usize])),
            );
            let corrected = support.filter(|w| w.near[i]);
            if let Some(w) = corrected {
                let ti = w.tang[i];
                for (&j, &(d, prj)) in ctx.lists.indices[ctx.lists.fluid_range(i)]
                    .iter()
                    .zip(buf.iter())
                {
                    let r = d.length();
                    let c = ctx.mass * ctx.kernel.grad_mag(r) / r.max(1e-9);
                    let tj = w.tang[j as usize];
                    a -= (ti.apply(d) * pri + tj.apply(d) * prj) * c;
                }
            } else {
                for (d, c) in buf.iter_mut() {
                    let r = d.length();
                    // |∇W| is zero at and beyond the support; coincident carriers exert nothing
                    *c = ctx.mass * (pri + *c) * ctx.kernel.grad_mag(r) / r.max(1e-9);
                }
                for &(d, c) in buf.iter() {
                    a -= d * c;
                }
            }
        });
        if pi > 0.0 {
            for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
                let s = j as usize - nf;
                let d = xi - ctx.solid_x[s];
                let r = d.length();
                if r >= h || r <= 1e-9 {
                    continue;
                }
                let psi = ctx.solid_volume[s] * ctx.mass;
                // static walls only: a moving body keeps Eq. 23's push along its normal (along
                // the pair, the wall pressure has a torque about a ball's centre)
                let hydro = match walls {
                    WallPush::Hydrostatic(h) if ctx.bodies[ctx.solid_body[s] as usize].fixed => {
                        Some((h.pressure(i, pi, -d).max(0.0), h.wet(s)))
                    }
                    _ => None,
                };
                let mut arm = None;
                let da = if let Some((ps, wet)) = hydro {
                    // the wall carrier takes the fluid's pressure carried hydrostatically to it
                    // (Adami et al. 2012) and pushes along the pair like a fluid neighbour, as
                    // far as it is wet
                    d * (wet * psi * (pri + ps / (rho[i] * rho[i])) * ctx.kernel.grad_mag(r) / r)
                } else if matches!(walls, WallPush::Akinci) {
                    d * (psi * 2.0 * pri * ctx.kernel.grad_mag(r) / r)
                } else {
                    // Eq. 23 for a fluid–solid pair: along the solid normal, with the
                    // directional derivative clamped so a carrier that penetrated is never
                    // pulled inward
                    let n = match support {
                        Some(w) => {
                            let (n, a) = w.normal(i, ctx.solid_body[s], ctx.solid_n[s]);
                            arm = a;
                            n
                        }
                        None => ctx.solid_n[s],
                    };
                    let cos = (d.dot(n) / r).max(0.0);
                    let carried = ctx.bodies[ctx.solid_body[s] as usize].carried;
                    let ps = if carried { mirrored(pi, rho_g, -d) } else { pi };
                    n * (psi * (pri + ps / (rho[i] * rho[i])) * ctx.kernel.grad_mag(r) * cos)
                };
                a += da;
                let j = -da * (ctx.mass * dt);
                acc.add(s, j);
                if let (Some(arm), Some(w)) = (arm, support) {
                    // the push acts along its line at the body's surface point nearest x_i: the
                    // reaction's torque about the centre takes that arm, not the carrier's (a
                    // ball's pushes pass through its centre whatever the water does)
                    let b = ctx.solid_body[s];
                    let at = w.start[s] - ctx.bodies[b as usize].com;
                    acc.add_couple(b, (arm - at).cross(j));
                }
            }
        }
        *ai = a;
    })
}
