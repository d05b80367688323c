//! Triangle meshes (issue 20): water poured around a closed mesh stays outside it whether or
//! not the mesh was built with pseudo-normals, a closed oriented mesh couples, and an open
//! mesh is left to rapier with a reason even when flagged oriented (it has no inside).
use rapier3d::parry::shape::TriMeshFlags;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

/// A cube `[lo, hi]` as 12 outward-wound triangles; `open` leaves out the top face.
fn cube(lo: Vector, hi: Vector, open: bool) -> (Vec<Vector>, Vec<[u32; 3]>) {
    let v: Vec<Vector> = (0..8)
        .map(|k| {
            Vector::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            )
        })
        .collect();
    let mut t = vec![
        [0, 2, 1],
        [1, 2, 3], // -z
        [4, 5, 6],
        [5, 7, 6], // +z
        [0, 1, 4],
        [1, 5, 4], // -y
        [0, 4, 2],
        [2, 4, 6], // -x
        [1, 3, 5],
        [3, 7, 5], // +x
    ];
    if !open {
        t.extend([[2, 6, 3], [3, 6, 7]]); // +y
    }
    (v, t)
}

fn world() -> FluidWorld {
    FluidWorld::new(FluidParams {
        spacing: 0.02,
        ..Default::default()
    })
    .unwrap()
}

/// A 0.2 m cube mesh in the middle of a 0.4 m block of water: no carrier inside it with or
/// without pseudo-normals (parry's solid distance to a mesh is the distance to its surface even
/// inside, and the block used to fill the cube either way: 1 000 carriers), and the water
/// around it is all there.
#[test]
fn water_poured_around_a_closed_mesh_stays_outside() {
    let (lo, hi) = (Vector::splat(0.1), Vector::splat(0.3));
    for flags in [TriMeshFlags::empty(), TriMeshFlags::ORIENTED] {
        let (v, t) = cube(lo, hi, false);
        let mut colliders = ColliderSet::new();
        colliders.insert(ColliderBuilder::trimesh_with_flags(v, t, flags).unwrap());
        let mut w = world();
        let n = w
            .add_block_around(Vector::ZERO, Vector::splat(0.4), Vector::ZERO, &colliders)
            .unwrap();
        let inside = w
            .fluid()
            .x
            .iter()
            .filter(|p| (0..3).all(|k| p[k] > lo[k] && p[k] < hi[k]))
            .count();
        println!("{flags:?}: {n} carriers, {inside} inside the cube");
        assert_eq!(inside, 0);
        // 20³ lattice points less the cube's 10³ (the points half a spacing from its faces stay)
        assert_eq!(n, 20 * 20 * 20 - 10 * 10 * 10);
    }
}

/// A closed oriented mesh couples; an open one flagged oriented is skipped with the reason;
/// a closed one without pseudo-normals is skipped as before.
#[test]
fn only_closed_oriented_meshes_couple() {
    let bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let (lo, hi) = (Vector::splat(0.1), Vector::splat(0.3));
    let mk = |open: bool, flags| {
        let (v, t) = cube(lo, hi, open);
        ColliderBuilder::trimesh_with_flags(v, t, flags).unwrap()
    };
    let closed = colliders.insert(mk(false, TriMeshFlags::ORIENTED));
    let open = colliders.insert(mk(true, TriMeshFlags::ORIENTED));
    let bare = colliders.insert(mk(false, TriMeshFlags::empty()));
    let mut w = world();
    let c = w.couple_all(&bodies, &colliders, Slip::FreeSlip).unwrap();
    assert_eq!(c.coupled.iter().map(|e| e.0).collect::<Vec<_>>(), [closed]);
    let reason = |h| {
        c.skipped
            .iter()
            .find(|e| e.0 == h)
            .map(|e| e.1.to_string())
            .unwrap_or_default()
    };
    println!("open: {}\nbare: {}", reason(open), reason(bare));
    assert!(reason(open).contains("open"), "{}", reason(open));
    assert!(reason(bare).contains("ORIENTED"), "{}", reason(bare));
}
