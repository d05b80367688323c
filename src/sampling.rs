//! Samplers: parry shapes → solid carrier shells (He 2012 §5, Eq. 20) and boxes → fluid carriers.
//!
//! Solid carriers are placed on a lattice of the fluid spacing in the shape's local frame and
//! kept only in the shell that fluid can reach (depth ≤ `thickness`, normally one support
//! radius). Normals and signed distances come from parry's exact point projection instead of the
//! SPH estimate of Eq. 20.

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::params::{check_count, MAX_PARTICLES};
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
    /// Midway through a part thinner than a spacing or two: both faces are equally near, so
    /// the normal is only a guess and the step turns it toward the fluid beside the carrier.
    pub two_sided: bool,
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
        // grounds: sampled where the fluid can reach ([`sample_shell_in`] with a clip box)
        TypedShape::HalfSpace(_) | TypedShape::HeightField(_) => Ok(()),
        TypedShape::Polyline(_) | TypedShape::Segment(_) | TypedShape::Triangle(_) => {
            unsupported("zero-thickness shapes have no interior")
        }
        TypedShape::Voxels(_) => unsupported("voxel shapes are not supported yet"),
        TypedShape::TriMesh(m) if m.pseudo_normals_if_oriented().is_none() => unsupported(
            "triangle meshes must be closed and built with TriMeshFlags::ORIENTED \
             so inside/outside is defined",
        ),
        TypedShape::TriMesh(m) if !is_closed(m) => unsupported(
            "the triangle mesh is open (an edge not shared by exactly two triangles): it has \
             no inside to sample, whatever its flags",
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
pub(crate) fn axis(lo: f32, hi: f32, dx: f32, anchor: Option<f32>) -> (f32, usize) {
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
    sample_shell_in(shape, dx, thickness, anchor, None)
}

/// `sample_shell_on` within the local box `clip` only: a ground (a half-space, a height
/// field, a cuboid hundreds of metres wide) is sampled where the fluid can reach, not whole.
///
/// ```
/// use staggered_fluid::internals::sample_shell_in;
/// use rapier3d::parry::shape::HalfSpace;
/// use rapier3d::math::Vector;
/// let clip = (Vector::new(-0.1, -0.2, -0.1), Vector::new(0.1, 0.2, 0.1));
/// let s = sample_shell_in(&HalfSpace::new(Vector::Y), 0.02, 0.04, None, Some(clip)).unwrap();
/// // two layers of 10 × 10 carriers below the plane y = 0, normals up
/// assert_eq!(s.len(), 200);
/// assert!(s.iter().all(|c| c.x.y < 0.0 && c.x.y > -0.04 && c.n.y > 0.99));
/// ```
pub fn sample_shell_in(
    shape: &dyn Shape,
    dx: f32,
    thickness: f32,
    anchor: Option<Vector>,
    clip: Option<(Vector, Vector)>,
) -> Result<Vec<ShellSample>> {
    check_supported(shape)?;
    if !(dx.is_finite() && dx > 0.0) {
        return Err(FluidError::NonPositive {
            name: "spacing",
            value: dx as f64,
        });
    }
    if clip.is_none() && matches!(shape.as_typed_shape(), TypedShape::HalfSpace(_)) {
        return Err(FluidError::UnsupportedShape {
            shape: type_name(shape),
            why: "unbounded: a half-space is sampled within a clip box only (couple it as a \
                  ground and it is sampled within the domain)"
                .into(),
        });
    }
    let mut aabb = shape.compute_local_aabb();
    if let TypedShape::HeightField(_) = shape.as_typed_shape() {
        // the ground under the surface is the solid: its shell lies below the lowest height
        aabb.mins.y -= thickness + dx;
    }
    let (lo, hi) = match clip {
        Some((a, b)) => (aabb.mins.max(a), aabb.maxs.min(b)),
        None => (aabb.mins, aabb.maxs),
    };
    if clip.is_some() && (0..3).any(|k| hi[k] <= lo[k]) {
        // the shape does not reach into the clip box
        return Ok(Vec::new());
    }
    for k in 0..3 {
        let e = hi[k] - lo[k];
        if !(e.is_finite()) || e < 0.0 {
            return Err(FluidError::DegenerateShape {
                shape: type_name(shape),
                why: if (0..3).all(|k| lo[k].is_finite() && hi[k].is_finite()) {
                    format!("bounding box {lo:?}..{hi:?} is inverted")
                } else {
                    "its size is not finite (a NaN or infinite dimension)".into()
                },
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
    // Full lattice size bounds the work of the generic path; cuboids skip their core, so
    // their shell (bounding-box surface × layers, and one row per (y, z) at least) bounds
    // theirs. Both counted in f64 before anything is sampled: a 1e6 m box would otherwise
    // run its rows for hours before the carrier count stopped it.
    let total = nx as f64 * ny as f64 * nz as f64;
    match cuboid_half {
        None => {
            check_count(
                "lattice points to test when sampling a shape",
                total,
                MAX_PARTICLES,
            )?;
        }
        Some(_) => {
            let (ex, ey, ez) = (nx as f64, ny as f64, nz as f64);
            let layers = (thickness / dx).ceil() as f64 + 1.0;
            let shell = (2.0 * (ex * ey + ey * ez + ez * ex) * layers).min(total);
            check_count(
                "solid carriers for one shape",
                shell.max(ey * ez),
                MAX_PARTICLES,
            )?;
        }
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
    if out.is_empty() && clip.is_none() {
        return Err(FluidError::DegenerateShape {
            shape: type_name(shape),
            why: format!("no solid carrier at spacing {dx}: the shape is thinner than the lattice"),
        });
    }
    Ok(out)
}

/// A half-space or a height field: a ground, with no finite shell to sample.
pub(crate) fn is_ground(shape: &dyn Shape) -> bool {
    matches!(
        shape.as_typed_shape(),
        TypedShape::HalfSpace(_) | TypedShape::HeightField(_)
    )
}

/// Static shells beyond this many carriers wait for the domain and are sampled within it.
const DEFER_CARRIERS: f64 = 1.0e6;

/// Whether a shape's whole shell would take more than [`DEFER_CARRIERS`] carriers at spacing
/// `dx` and shell `thickness` (estimated from its bounding box's surface and the shell's
/// layers): a ground cuboid 200 m wide at Δx = 2 cm would need 10⁹ and took 30 s before
/// failing. Grounds (no finite shell) are always too large.
pub(crate) fn too_large_to_sample(shape: &dyn Shape, dx: f32, thickness: f32) -> bool {
    let aabb = shape.compute_local_aabb();
    let e = aabb.maxs - aabb.mins;
    let area = 2.0 * (e.x as f64 * e.y as f64 + e.y as f64 * e.z as f64 + e.z as f64 * e.x as f64);
    let layers = (thickness / dx) as f64 + 1.0;
    let dx = dx as f64;
    is_ground(shape) || !(area.is_finite() && area * layers / (dx * dx) <= DEFER_CARRIERS)
}

/// Signed distance from the local point `p` to the surface of `shape` (negative inside).
///
/// A compound is the union of its parts: outside, the distance to the nearest part; inside,
/// the depth in the part that holds `p` deepest. Parry's projection onto a compound stops at
/// internal faces where parts touch or overlap (a carrier there would get a normal pointing
/// into the next part); the union's depth is exact wherever overlapping parts meet at right
/// angles (hollow boxes from slabs) and conservative elsewhere.
pub fn signed_distance(shape: &dyn Shape, p: Vector) -> f32 {
    match shape.as_typed_shape() {
        TypedShape::Compound(c) => {
            return c
                .shapes()
                .iter()
                .map(|(pose, part)| signed_distance(part.as_ref(), pose.inverse_transform_point(p)))
                .fold(f32::INFINITY, f32::min)
        }
        TypedShape::HeightField(hf) => {
            // a height field is a surface: below it is inside (as a ground)
            let l = (shape.project_local_point(p, false).point - p).length();
            return match height_at(hf, p) {
                Some(y) if p.y < y => -l,
                _ => l,
            };
        }
        TypedShape::ConvexPolyhedron(poly) => {
            return match crate::hull::inside(poly, p) {
                Some(foot) => -(foot - p).length(),
                None => (shape.project_local_point(p, false).point - p).length(),
            }
        }
        _ => {}
    }
    let pr = shape.project_local_point(p, false);
    let l = (pr.point - p).length();
    if pr.is_inside {
        -l
    } else {
        l
    }
}

/// Whether a triangle mesh is closed: every edge (vertices merged by position) shared by
/// exactly two triangles. An open mesh has no inside, whatever its flags say.
pub(crate) fn is_closed(m: &rapier3d::parry::shape::TriMesh) -> bool {
    use std::collections::HashMap;
    let key = |v: Vector| (v.x.to_bits(), v.y.to_bits(), v.z.to_bits());
    let mut ids: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let canon: Vec<u32> = m
        .vertices()
        .iter()
        .map(|v| {
            let n = ids.len() as u32;
            *ids.entry(key(*v)).or_insert(n)
        })
        .collect();
    let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
    for t in m.indices() {
        for k in 0..3 {
            let (a, b) = (canon[t[k] as usize], canon[t[(k + 1) % 3] as usize]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    !edges.is_empty() && edges.values().all(|&c| c == 2)
}

/// Whether the local point `p` is inside a closed triangle mesh, by the parity of a ray's
/// crossings (for meshes built without `TriMeshFlags::ORIENTED`, where parry's projection
/// cannot tell inside from outside). The ray leaves along a direction no lattice or axis
/// aligns with, so it does not graze edges of axis-aligned meshes.
pub(crate) fn inside_closed_mesh(m: &rapier3d::parry::shape::TriMesh, p: Vector) -> bool {
    use rapier3d::parry::query::{Ray, RayCast};
    let aabb = m.local_aabb();
    if (0..3).any(|k| p[k] < aabb.mins[k] || p[k] > aabb.maxs[k]) {
        return false;
    }
    let dir = Vector::new(0.5773, 0.6123, 0.5402).normalize();
    let reach = (aabb.maxs - aabb.mins).length() * 2.0;
    let step = reach * 1e-6;
    let (mut origin, mut crossings) = (p, 0u32);
    // at most one crossing per triangle
    for _ in 0..m.indices().len() {
        match m.cast_local_ray(&Ray::new(origin, dir), reach, false) {
            Some(t) => {
                crossings += 1;
                origin += dir * (t + step);
            }
            None => break,
        }
    }
    crossings % 2 == 1
}

/// Whether the world point `p` lies inside `shape` at `pose` (below it, for a height field,
/// which parry treats as a surface only).
pub(crate) fn contains(shape: &dyn Shape, pose: &crate::math::Pose, p: Vector) -> bool {
    match shape.as_typed_shape() {
        TypedShape::HeightField(_) => signed_distance(shape, pose.inverse_transform_point(p)) < 0.0,
        TypedShape::ConvexPolyhedron(poly) => {
            crate::hull::inside(poly, pose.inverse_transform_point(p)).is_some()
        }
        _ => shape.contains_point(pose, p),
    }
}

/// The outward normal of `shape` at `pose` at the surface point nearest the world point `p`
/// (`None` when `p` lies on the surface), and `p`'s signed distance to it (negative inside).
pub(crate) fn outward_normal(
    shape: &dyn Shape,
    pose: &crate::math::Pose,
    p: Vector,
) -> (Option<Vector>, f32) {
    let local = pose.inverse_transform_point(p);
    let (point, inside) = project(shape, local);
    let off = local - point;
    let n = off
        .try_normalize()
        .map(|d| pose.rotation * if inside { -d } else { d });
    let dist = off.length();
    (n, if inside { -dist } else { dist })
}

/// The outward normal of `shape` at `pose` at the surface point nearest the world point `p`,
/// and that point (world), unless `p` lies on the surface.
pub(crate) fn nearest_surface(
    shape: &dyn Shape,
    pose: &crate::math::Pose,
    p: Vector,
) -> Option<(Vector, Vector)> {
    match outward_normal(shape, pose, p) {
        (Some(n), dist) => Some((n, p - n * dist)),
        (None, _) => None,
    }
}

/// The point of `shape`'s surface nearest the local point `p` and whether `p` is inside (below
/// the surface, for a height field).
pub(crate) fn project(shape: &dyn Shape, p: Vector) -> (Vector, bool) {
    if let TypedShape::ConvexPolyhedron(poly) = shape.as_typed_shape() {
        if let Some(inner) = crate::hull::inside(poly, p) {
            return (inner, true);
        }
        return (shape.project_local_point(p, false).point, false);
    }
    let pr = shape.project_local_point(p, false);
    match shape.as_typed_shape() {
        TypedShape::HeightField(_) => (pr.point, signed_distance(shape, p) < 0.0),
        _ => (pr.point, pr.is_inside),
    }
}

/// The height of the height field `hf` above the point `p` (its local frame), if `p` lies over
/// one of its cells.
fn height_at(hf: &rapier3d::parry::shape::HeightField, p: Vector) -> Option<f32> {
    let (i, j) = hf.cell_at_point(p)?;
    let (a, b) = hf.triangles_at(i, j);
    for t in [a, b].into_iter().flatten() {
        // barycentric coordinates of p in the triangle's projection on the xz plane
        let (p0, p1, p2) = (t.a, t.b, t.c);
        let (v0x, v0z) = (p1.x - p0.x, p1.z - p0.z);
        let (v1x, v1z) = (p2.x - p0.x, p2.z - p0.z);
        let (v2x, v2z) = (p.x - p0.x, p.z - p0.z);
        let den = v0x * v1z - v1x * v0z;
        if den.abs() < 1e-12 {
            continue;
        }
        let v = (v2x * v1z - v1x * v2z) / den;
        let w = (v0x * v2z - v2x * v0z) / den;
        let eps = -1e-5;
        if v >= eps && w >= eps && v + w <= 1.0 - eps {
            return Some(p0.y + v * (p1.y - p0.y) + w * (p2.y - p0.y));
        }
    }
    None
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
    let sd = |q: Vector| signed_distance(shape, q);
    let grad = |e: f32| {
        Vector::new(
            sd(p + Vector::X * e) - sd(p - Vector::X * e),
            sd(p + Vector::Y * e) - sd(p - Vector::Y * e),
            sd(p + Vector::Z * e) - sd(p - Vector::Z * e),
        )
    };
    let g = grad(0.5 * dx);
    // Midway through a wall one spacing thick both faces are equally near and the differences
    // cancel: take the face parry projects onto instead of dropping the carrier (a dropped
    // carrier is a hole in the wall).
    let two_sided = g.length() < 0.05 * dx;
    let exact = || {
        let pr = shape.project_local_point(p, false);
        let d = (pr.point - p).try_normalize()?;
        Some(if pr.is_inside { d } else { -d })
    };
    let n = match (!two_sided).then(|| g.try_normalize()).flatten() {
        // on a curved face the differences over half a spacing are off the true normal by
        // up to a degree (a ball of radius 2Δx: 0.013 rad), enough for the pressure on a light
        // ball to spin it; the nearest surface point's direction is exact there. Where the two
        // differ by more than 8° (edges and corners) the differences' diagonal stays.
        Some(d) => exact().filter(|e| e.dot(d) > 0.99).unwrap_or(d),
        None => exact()?,
    };
    // A compound's parts meet at internal faces, where the least signed distance over the
    // parts (exact outside, too shallow inside) ties and the normal can point into another
    // part: the foot of a wall standing on a floor in one compound pointed down into the
    // floor, and Shao's correction pushed fluid there (a PCISPH box of still water erupted
    // in its first step). A normal along which the carrier does not leave the shape is
    // re-taken from differences a spacing either side, across the seam; where those cancel
    // too, the carrier is two-sided (the step points it at its fluid neighbours).
    let compound = matches!(shape.as_typed_shape(), TypedShape::Compound(_));
    let (n, two_sided) =
        if compound && !two_sided && shape.contains_local_point(p + n * (0.25 * dx - phi)) {
            let g = grad(dx);
            match (g.length() > 0.1 * dx).then(|| g.try_normalize()).flatten() {
                Some(m) => (m, false),
                None => (n, true),
            }
        } else {
            (n, two_sided)
        };
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
            two_sided,
        })
    } else {
        // too thin or too sharp here to hold a layer at that depth: keep the lattice point
        Some(ShellSample {
            x: p,
            n,
            phi,
            two_sided,
        })
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
