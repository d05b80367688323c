//! Samplers: parry shapes → solid carrier shells (He 2012 §5, Eq. 20) and boxes → fluid carriers.
//!
//! Solid carriers are placed on a lattice of the fluid spacing in the shape's local frame and
//! kept only in the shell that fluid can reach (depth ≤ `thickness`, normally one support
//! radius). Normals and signed distances come from parry's exact point projection instead of the
//! SPH estimate of Eq. 20.

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::params::MAX_PARTICLES;
use rapier3d::parry::shape::{Shape, TypedShape};

/// One solid carrier in the shape's local frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellSample {
    /// Local position.
    pub x: Vector,
    /// Outward unit normal of the nearest surface point.
    pub n: Vector,
    /// Signed distance to the surface (≤ 0: inside).
    pub phi: f32,
}

fn type_name(shape: &dyn Shape) -> String {
    format!("{:?}", shape.shape_type())
}

/// Rejects shapes that have no closed interior to sample.
pub fn check_supported(shape: &dyn Shape) -> Result<()> {
    let unsupported = |why: &str| {
        Err(FluidError::UnsupportedShape {
            shape: type_name(shape),
            why: why.to_string(),
        })
    };
    match shape.as_typed_shape() {
        TypedShape::HalfSpace(_) => unsupported("infinite; use a large cuboid instead"),
        TypedShape::HeightField(_) => unsupported("height fields have no closed interior"),
        TypedShape::Polyline(_) | TypedShape::Segment(_) | TypedShape::Triangle(_) => {
            unsupported("zero-thickness shapes have no interior")
        }
        TypedShape::Voxels(_) => unsupported("voxel shapes are not supported yet"),
        TypedShape::TriMesh(m) if m.pseudo_normals_if_oriented().is_none() => unsupported(
            "triangle meshes must be closed and built with TriMeshFlags::ORIENTED \
             so inside/outside is defined",
        ),
        TypedShape::Compound(c) => {
            for (_, s) in c.shapes() {
                check_supported(s.as_ref())?;
            }
            Ok(())
        }
        TypedShape::Custom(_) => unsupported("custom shapes are not supported"),
        _ => Ok(()),
    }
}

/// Lattice coordinates along one axis: `n` points spaced `dx` inside `[lo, hi]`, centred in it,
/// or (with an `anchor`) on the lattice `anchor + (k + ½) dx` so that they line up with fluid
/// blocks filled from the same anchor.
fn axis(lo: f32, hi: f32, dx: f32, anchor: Option<f32>) -> (f32, usize) {
    let ext = hi - lo;
    match anchor {
        None => {
            let n = ((ext / dx) + 1e-4).floor().max(1.0) as usize;
            (lo + 0.5 * (ext - (n as f32 - 1.0) * dx), n)
        }
        Some(a) => {
            let k0 = ((lo - a) / dx - 0.5 - 1e-4).ceil();
            let start = a + (k0 + 0.5) * dx;
            let n = (((hi - start) / dx) + 1e-4).floor() as i64 + 1;
            (start, n.max(0) as usize)
        }
    }
}

/// Samples the shell of `shape` (depth ≤ `thickness`) at spacing `dx`, in local coordinates.
///
/// ```
/// use staggered_fluid::internals::sample_shell;
/// use rapier3d::parry::shape::Cuboid;
/// use rapier3d::math::Vector;
/// let s = sample_shell(&Cuboid::new(Vector::new(0.1, 0.1, 0.1)), 0.02, 0.04).unwrap();
/// assert!(s.iter().all(|p| p.phi <= 0.0 && p.phi >= -0.04));
/// ```
pub fn sample_shell(shape: &dyn Shape, dx: f32, thickness: f32) -> Result<Vec<ShellSample>> {
    sample_shell_on(shape, dx, thickness, None)
}

/// [`sample_shell`] on the lattice `anchor + (k + ½) dx` (local frame) instead of a lattice
/// centred in the shape's bounding box: solids sampled from the same anchor as a fluid block
/// (e.g. the faces of a tank) sit exactly one lattice step from it, so the rest density holds
/// up to the wall.
pub fn sample_shell_on(
    shape: &dyn Shape,
    dx: f32,
    thickness: f32,
    anchor: Option<Vector>,
) -> Result<Vec<ShellSample>> {
    check_supported(shape)?;
    if !(dx.is_finite() && dx > 0.0) {
        return Err(FluidError::NonPositive {
            name: "spacing",
            value: dx as f64,
        });
    }
    let aabb = shape.compute_local_aabb();
    let (lo, hi) = (aabb.mins, aabb.maxs);
    for k in 0..3 {
        let e = hi[k] - lo[k];
        if !(e.is_finite()) || e < 0.0 {
            return Err(FluidError::DegenerateShape {
                shape: type_name(shape),
                why: format!("bounding box {lo:?}..{hi:?} is not finite"),
            });
        }
    }
    if (0..3).any(|k| hi[k] - lo[k] <= 1e-9) {
        return Err(FluidError::DegenerateShape {
            shape: type_name(shape),
            why: "zero extent along an axis".into(),
        });
    }
    let (sx, nx) = axis(lo.x, hi.x, dx, anchor.map(|a| a.x));
    let (sy, ny) = axis(lo.y, hi.y, dx, anchor.map(|a| a.y));
    let (sz, nz) = axis(lo.z, hi.z, dx, anchor.map(|a| a.z));
    let cuboid_half = match shape.as_typed_shape() {
        TypedShape::Cuboid(c) => Some(c.half_extents),
        _ => None,
    };
    // Full lattice size bounds the work of the generic path; cuboids skip their core.
    let total = nx as u64 * ny as u64 * nz as u64;
    if cuboid_half.is_none() && total > MAX_PARTICLES {
        return Err(FluidError::TooMany {
            what: "lattice points to test when sampling a shape",
            count: total,
            limit: MAX_PARTICLES,
        });
    }
    let mut out = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            let y = sy + j as f32 * dx;
            let z = sz + k as f32 * dx;
            // For a cuboid, rows deep inside in y and z only keep their x ends.
            let skip = cuboid_half.and_then(|h| {
                let dyz = (h.y - y.abs()).min(h.z - z.abs());
                (dyz > thickness).then(|| {
                    let keep = ((thickness / dx).ceil() as usize + 1).min(nx);
                    (keep, nx.saturating_sub(keep))
                })
            });
            for i in 0..nx {
                if let Some((a, b)) = skip {
                    if i >= a && i < b {
                        continue;
                    }
                }
                let p = Vector::new(sx + i as f32 * dx, y, z);
                if let Some(s) = shell_sample(shape, p, thickness, dx) {
                    out.push(s);
                }
            }
            if out.len() as u64 > MAX_PARTICLES {
                return Err(FluidError::TooMany {
                    what: "solid carriers for one shape",
                    count: out.len() as u64,
                    limit: MAX_PARTICLES,
                });
            }
        }
    }
    if out.is_empty() {
        return Err(FluidError::DegenerateShape {
            shape: type_name(shape),
            why: format!("no solid carrier at spacing {dx}: the shape is thinner than the lattice"),
        });
    }
    Ok(out)
}

/// Signed distance from the local point `p` to the surface of `shape` (negative inside).
///
/// A compound is the union of its parts: outside, the distance to the nearest part; inside,
/// the depth in the part that holds `p` deepest. Parry's projection onto a compound stops at
/// internal faces where parts touch or overlap (a carrier there would get a normal pointing
/// into the next part); the union's depth is exact wherever overlapping parts meet at right
/// angles (hollow boxes from slabs) and conservative elsewhere.
pub fn signed_distance(shape: &dyn Shape, p: Vector) -> f32 {
    if let TypedShape::Compound(c) = shape.as_typed_shape() {
        return c
            .shapes()
            .iter()
            .map(|(pose, part)| signed_distance(part.as_ref(), pose.inverse_transform_point(p)))
            .fold(f32::INFINITY, f32::min);
    }
    let pr = shape.project_local_point(p, false);
    let l = (pr.point - p).length();
    if pr.is_inside {
        -l
    } else {
        l
    }
}

/// The carrier at local point `p` if it lies inside `shape` within `thickness` of its surface.
fn shell_sample(shape: &dyn Shape, p: Vector, thickness: f32, dx: f32) -> Option<ShellSample> {
    let phi = signed_distance(shape, p);
    if phi > 0.0 || -phi > thickness {
        return None;
    }
    // Normal: central differences of the signed distance over half a spacing. Inside a face
    // this is the face normal; at an edge or corner, where the nearest face is a tie, it is the
    // diagonal (the nearest face's normal would let fluid past the edge look "inside").
    let e = 0.5 * dx;
    let sd = |q: Vector| signed_distance(shape, q);
    let g = Vector::new(
        sd(p + Vector::X * e) - sd(p - Vector::X * e),
        sd(p + Vector::Y * e) - sd(p - Vector::Y * e),
        sd(p + Vector::Z * e) - sd(p - Vector::Z * e),
    );
    // Midway through a wall one spacing thick both faces are equally near and the differences
    // cancel: take the face parry projects onto instead of dropping the carrier (a dropped
    // carrier is a hole in the wall).
    let n = g.try_normalize().or_else(|| {
        let pr = shape.project_local_point(p, false);
        let d = (pr.point - p).try_normalize()?;
        Some(if pr.is_inside { d } else { -d })
    })?;
    // Layer the shell parallel to the surface: move the carrier along its normal to the depth
    // (k + ½)Δx of its layer, as on a wall aligned with the fluid lattice. A lattice that cuts
    // the surface anywhere else leaves the outer carriers shallower on average, and the fluid,
    // which keeps a spacing from them, then sees the body bigger than it is (a ball of radius
    // 3Δx felt 1.3 ρgV of buoyancy).
    let depth = (-phi / dx).floor() * dx + 0.5 * dx;
    if depth > thickness {
        return None;
    }
    let q = p - n * (phi + depth);
    let phi_q = signed_distance(shape, q);
    if (phi_q + depth).abs() <= 0.25 * dx {
        Some(ShellSample {
            x: q,
            n,
            phi: phi_q,
        })
    } else {
        // too thin or too sharp here to hold a layer at that depth: keep the lattice point
        Some(ShellSample { x: p, n, phi })
    }
}

/// Fluid carrier positions filling the box `[mins, maxs]` at spacing `dx` (lattice centred in
/// the box, `dx/2` from its faces when the box is a whole number of spacings).
pub fn fill_box(mins: Vector, maxs: Vector, dx: f32) -> Vec<Vector> {
    let cnt = |lo: f32, hi: f32| (((hi - lo) / dx) + 1e-4).floor().max(0.0) as usize;
    let (nx, ny, nz) = (
        cnt(mins.x, maxs.x),
        cnt(mins.y, maxs.y),
        cnt(mins.z, maxs.z),
    );
    let off = |lo: f32, hi: f32, n: usize| lo + 0.5 * (hi - lo - (n as f32 - 1.0) * dx);
    let (ox, oy, oz) = (
        off(mins.x, maxs.x, nx),
        off(mins.y, maxs.y, ny),
        off(mins.z, maxs.z, nz),
    );
    let mut out = Vec::with_capacity(nx * ny * nz);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                out.push(Vector::new(
                    ox + i as f32 * dx,
                    oy + j as f32 * dx,
                    oz + k as f32 * dx,
                ));
            }
        }
    }
    out
}
