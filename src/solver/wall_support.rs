//! The walls' push as their geometry says ([`crate::FluidParams::wall_support`]): per fluid
//! carrier beside a solid, the shape's outward normal and nearest surface point, and the
//! gradient correction along gravity of carriers beside walls, for
//! [`super::density::pressure_accel`].

use super::{Ctx, ROWS};
use crate::math::{Pose, Vector};
use rapier3d::parry::shape::SharedShape;
use rayon::prelude::*;

/// What [`crate::FluidParams::wall_support`] adds to [`super::density::pressure_accel`], built once per
/// substep from the predicted positions.
pub(crate) struct WallSupport {
    /// Per fluid carrier, its [`Tangential`] correction.
    pub(super) tang: Vec<Tangential>,
    /// Per fluid carrier, whether it or a fluid neighbour has a correction (its pairs then
    /// take the corrected form).
    pub(super) near: Vec<bool>,
    /// Per fluid carrier `i`, `entries[offsets[i]..offsets[i + 1]]`: each solid beside it,
    /// that solid's outward surface normal at `x_i` and the surface point nearest `x_i` (where
    /// the push acts on the body), relative to the solid's centre.
    offsets: Vec<u32>,
    entries: Vec<(u32, Vector, Vector)>,
    /// The solid carriers' places when built (before the loop's iterations move the bodies):
    /// the reactions' arms (`FluidWorld::absorb_shared_from`).
    pub(crate) start: Vec<Vector>,
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
pub(super) struct Tangential {
    sigma: f32,
    u: Vector,
}

impl Tangential {
    /// `L̃ d`.
    #[inline]
    pub(super) fn apply(self, d: Vector) -> Vector {
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
    pub(super) fn normal(&self, i: usize, b: u32, n_s: Vector) -> (Vector, Option<Vector>) {
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
