//! Every supported parry shape samples into a shell of solid carriers that lie inside the shape,
//! within one support radius of its surface, with unit outward normals, and that leave no hole
//! in the surface (issue 3: "Shapes").
use rapier3d::parry::shape::{SharedShape, TriMeshFlags};
use staggered_fluid::internals::sample_shell;
use staggered_fluid::prelude::*;

mod support;

const DX: f32 = 0.02;
const H: f32 = 0.04; // support radius = shell thickness

fn shapes() -> Vec<(&'static str, SharedShape)> {
    let hull_pts: Vec<Vector> = [
        (0.12, 0.0, 0.0),
        (-0.1, 0.02, 0.01),
        (0.0, 0.11, -0.02),
        (0.01, -0.09, 0.03),
        (0.02, 0.01, 0.13),
        (-0.03, 0.0, -0.1),
        (0.07, 0.07, 0.07),
    ]
    .iter()
    .map(|&(x, y, z)| Vector::new(x, y, z))
    .collect();
    let hull = SharedShape::convex_hull(&hull_pts).expect("hull");
    let (v, i) = hull.as_convex_polyhedron().unwrap().to_trimesh();
    let mesh = SharedShape::trimesh_with_flags(v, i, TriMeshFlags::ORIENTED).expect("mesh");
    let compound = SharedShape::compound(vec![
        (
            Pose::from_translation(Vector::new(-0.1, 0.0, 0.0)),
            SharedShape::cuboid(0.06, 0.05, 0.05),
        ),
        (
            Pose::from_translation(Vector::new(0.12, 0.0, 0.0)),
            SharedShape::ball(0.07),
        ),
    ]);
    vec![
        ("cuboid", SharedShape::cuboid(0.1, 0.07, 0.05)),
        ("ball", SharedShape::ball(0.1)),
        ("capsule", SharedShape::capsule_y(0.1, 0.06)),
        ("cylinder", SharedShape::cylinder(0.1, 0.08)),
        ("cone", SharedShape::cone(0.1, 0.08)),
        ("convex polyhedron", hull),
        ("closed triangle mesh", mesh),
        ("compound", compound),
    ]
}

/// Signed distance from parry's point projection (negative inside).
fn signed_distance(shape: &SharedShape, p: Vector) -> f32 {
    let pr = shape.project_local_point(p, false);
    let d = (pr.point - p).length();
    if pr.is_inside {
        -d
    } else {
        d
    }
}

#[test]
fn every_supported_shape_samples_into_a_reachable_shell() {
    for (name, shape) in shapes() {
        let s = sample_shell(shape.as_ref(), DX, H).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(s.len() > 20, "{name}: only {} carriers", s.len());
        for c in &s {
            let d = signed_distance(&shape, c.x);
            assert!(d <= 1e-5, "{name}: carrier {:?} outside ({d})", c.x);
            assert!(
                -d <= H + 1e-5,
                "{name}: carrier {:?} deeper than h ({d})",
                c.x
            );
            assert!((c.phi - d).abs() < 1e-4, "{name}: phi {} vs {d}", c.phi);
            assert!(
                (c.n.length() - 1.0).abs() < 1e-4,
                "{name}: normal {:?}",
                c.n
            );
            // outward: stepping along n leaves the shape within twice the depth (a face normal
            // leaves at the depth, an edge or corner diagonal within √3 times it)
            let out = c.x + c.n * (-2.0 * d + 0.25 * DX);
            assert!(
                signed_distance(&shape, out) > 0.0,
                "{name}: normal {:?} at {:?} does not point out",
                c.n,
                c.x
            );
        }
        // no hole: a fluid carrier touching any surface point has a solid carrier inside its
        // support (a lattice diagonal on faces; sharp tips thinner than Δx, like the cone's
        // apex, only reach this looser bound)
        let aabb = shape.compute_local_aabb();
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..300 {
            let p = Vector::new(
                aabb.mins.x + rnd() * (aabb.maxs.x - aabb.mins.x),
                aabb.mins.y + rnd() * (aabb.maxs.y - aabb.mins.y),
                aabb.mins.z + rnd() * (aabb.maxs.z - aabb.mins.z),
            );
            let q = shape.project_local_point(p, false).point;
            let nearest = s
                .iter()
                .map(|c| (c.x - q).length())
                .fold(f32::INFINITY, f32::min);
            assert!(
                nearest < H,
                "{name}: surface point {q:?} has no carrier within {nearest}"
            );
        }
    }
}

#[test]
fn open_meshes_and_unbounded_shapes_are_rejected_by_name() {
    // an open mesh: one triangle short of a tetrahedron
    let v = vec![
        Vector::new(0.0, 0.0, 0.0),
        Vector::new(0.2, 0.0, 0.0),
        Vector::new(0.0, 0.2, 0.0),
        Vector::new(0.0, 0.0, 0.2),
    ];
    let open = SharedShape::trimesh(v, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2]]).unwrap();
    let e = sample_shell(open.as_ref(), DX, H).unwrap_err();
    assert!(e.to_string().contains("TriMesh"), "{e}");
    let hs = SharedShape::halfspace(Vector::Y);
    let e = sample_shell(hs.as_ref(), DX, H).unwrap_err();
    assert!(e.to_string().contains("HalfSpace"), "{e}");
}

/// A wall one spacing thick keeps every carrier: midway between its faces the SDF's central
/// differences cancel, and the face parry projects onto gives the normal.
#[test]
fn a_wall_one_spacing_thick_is_sampled_whole() {
    use rapier3d::parry::shape::Cuboid;
    let dx = 0.02;
    let s = staggered_fluid::internals::sample_shell(
        &Cuboid::new(Vector::new(0.2, 0.5 * dx, 0.2)),
        dx,
        2.0 * dx,
    )
    .unwrap();
    assert_eq!(
        s.len(),
        20 * 20,
        "one carrier per lattice cell of the plate"
    );
    assert!(s.iter().all(|c| c.n.length() > 0.99));
}

/// A compound's parts meet at internal faces, where the least signed distance over the parts
/// ties. A carrier of an open box's shell (walls standing on a floor, one compound) that the
/// water touches across one face only (below the rim) must have that face's normal — the foot of a wall once
/// pointed diagonally down into the floor, and PCISPH's correction pushed water there.
#[test]
fn a_compound_boxs_carriers_face_the_water_at_its_seams() {
    let (dx, inner, wall, height) = (0.02f32, 0.1f32, 0.04f32, 0.16f32);
    let s = sample_shell(&*support::open_box(inner, wall, height), dx, 2.0 * dx).unwrap();
    let water =
        |q: Vector| q.x.abs().max(q.z.abs()) < inner && q.y > wall && q.y < wall + height - dx;
    let mut checked = 0;
    for c in s.iter().filter(|c| !c.two_sided) {
        let wet: Vec<Vector> = [
            Vector::X,
            -Vector::X,
            Vector::Y,
            -Vector::Y,
            Vector::Z,
            -Vector::Z,
        ]
        .into_iter()
        .filter(|&e| water(c.x + e * dx))
        .collect();
        if let [e] = wet[..] {
            assert!(
                c.n.dot(e) > 0.99,
                "carrier at {:?} beside water along {e:?} has normal {:?}",
                c.x,
                c.n
            );
            checked += 1;
        }
    }
    // the floor's 10 × 10 and four walls' 10 × 7 carriers beside the water (the rim's
    // layer, at a convex edge, faces the water and the air)
    assert_eq!(checked, 100 + 4 * 70);
}
