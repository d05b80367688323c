//! The cell-grid neighbour search equals brute force.
#![allow(clippy::needless_range_loop)] // index loops read as matrix algebra here
use staggered_fluid::internals::{brute_force, build_lists, counting_sort, Grid, NeighborLists};
use staggered_fluid::math::Vector;

fn lcg(seed: &mut u64) -> f32 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 33) as f32) / (1u64 << 31) as f32
}

/// Lists of `n` random points in a 1 × 0.5 × 0.3 box against the brute-force oracle, built
/// into `lists` (which may hold an earlier build).
fn check_against_brute_force(n: usize, radius: f32, lists: &mut NeighborLists) -> usize {
    let mut seed = 7;
    let pts: Vec<Vector> = (0..n)
        .map(|_| Vector::new(lcg(&mut seed), lcg(&mut seed) * 0.5, lcg(&mut seed) * 0.3))
        .collect();
    let grid = Grid::new(Vector::splat(-0.01), Vector::splat(1.01), radius);
    let cells: Vec<u32> = pts.iter().map(|p| grid.cell_of(*p)).collect();
    let (order, start) = counting_sort(&cells, grid.cell_count() as usize);
    let sorted: Vec<Vector> = order.iter().map(|&o| pts[o as usize]).collect();
    let empty_start = vec![0u32; grid.cell_count() as usize + 1];
    build_lists(
        &grid,
        radius,
        &sorted,
        &start,
        &[],
        &[],
        &empty_start,
        lists,
    );
    let oracle = brute_force(&sorted, radius);
    let mut total = 0;
    for i in 0..sorted.len() {
        // rows come sorted (the velocity constraint finds each pair's transpose by walking
        // rows in order), so they equal the sorted oracle as they are
        assert_eq!(lists.row(i), oracle[i].as_slice(), "row {i}");
        total += oracle[i].len();
    }
    assert_eq!(lists.pair_count(), total);
    total
}

#[test]
fn grid_search_equals_brute_force_on_random_points() {
    let total = check_against_brute_force(3000, 0.05, &mut NeighborLists::default());
    assert!(total > 3000, "test must exercise real pairs ({total})");
}

#[test]
fn lists_grow_past_the_last_builds_row_lengths() {
    // the pairs are written into regions sized from the last build's mean row length: after a
    // sparse build (about 1 pair a row) the dense one overflows them and must still be right
    let mut lists = NeighborLists::default();
    let sparse = check_against_brute_force(3000, 0.02, &mut lists);
    let dense = check_against_brute_force(3000, 0.08, &mut lists);
    assert!(
        dense > 20 * sparse.max(1),
        "the second build must outgrow the first ({sparse} → {dense})"
    );
    // and shrink back
    check_against_brute_force(3000, 0.02, &mut lists);
}

#[test]
fn solid_neighbours_are_found_with_offset_indices() {
    let radius = 0.1;
    let grid = Grid::new(Vector::ZERO, Vector::ONE, radius);
    let fluid = vec![Vector::splat(0.5)];
    let solids = [Vector::new(0.55, 0.5, 0.5), Vector::new(0.8, 0.5, 0.5)];
    let fc: Vec<u32> = fluid.iter().map(|p| grid.cell_of(*p)).collect();
    let (_, fstart) = counting_sort(&fc, grid.cell_count() as usize);
    let sc: Vec<u32> = solids.iter().map(|p| grid.cell_of(*p)).collect();
    let (sorder, sstart) = counting_sort(&sc, grid.cell_count() as usize);
    let mut lists = NeighborLists::default();
    build_lists(
        &grid, radius, &fluid, &fstart, &solids, &sorder, &sstart, &mut lists,
    );
    assert_eq!(lists.row(0), &[1u32]); // fluid count 1 + solid 0
    assert_eq!(lists.fluid_range(0), 0..0);
    assert_eq!(lists.solid_range(0), 0..1);
}

/// Rows list their fluid neighbours first and their solids after `fluid_end`, and together
/// they are exactly the brute-force neighbours, on random fluid and solid points.
#[test]
fn rows_hold_fluid_first_then_solids() {
    let mut seed = 11;
    let mut pts = |n: usize| -> Vec<Vector> {
        (0..n)
            .map(|_| Vector::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 0.4)
            .collect()
    };
    let (fluid, solids) = (pts(800), pts(800));
    let radius = 0.06;
    let grid = Grid::new(Vector::splat(-0.01), Vector::splat(0.41), radius);
    let sort = |p: &[Vector]| {
        let cells: Vec<u32> = p.iter().map(|q| grid.cell_of(*q)).collect();
        counting_sort(&cells, grid.cell_count() as usize)
    };
    let (forder, fstart) = sort(&fluid);
    let fsorted: Vec<Vector> = forder.iter().map(|&o| fluid[o as usize]).collect();
    let (sorder, sstart) = sort(&solids);
    let mut lists = NeighborLists::default();
    build_lists(
        &grid, radius, &fsorted, &fstart, &solids, &sorder, &sstart, &mut lists,
    );
    let nf = fsorted.len() as u32;
    let (mut nfl, mut nsol) = (0, 0);
    for i in 0..fsorted.len() {
        let (fr, sr) = (lists.fluid_range(i), lists.solid_range(i));
        assert_eq!(fr.start, lists.range(i).start);
        assert_eq!(sr.end, lists.range(i).end);
        assert_eq!(fr.end, sr.start);
        assert!(lists.indices[fr.clone()].iter().all(|&j| j < nf), "row {i}");
        assert!(
            lists.indices[sr.clone()].iter().all(|&j| j >= nf),
            "row {i}"
        );
        let mut all: Vec<Vector> = fsorted.clone();
        all.extend(solids.iter().copied());
        let mut got: Vec<u32> = lists.row(i).to_vec();
        got.sort();
        let want: Vec<u32> = (0..all.len() as u32)
            .filter(|&j| {
                j as usize != i && (all[j as usize] - fsorted[i]).length_squared() < radius * radius
            })
            .collect();
        assert_eq!(got, want, "row {i}");
        nfl += fr.len();
        nsol += sr.len();
    }
    assert!(
        nfl > 800 && nsol > 800,
        "both kinds must occur ({nfl}, {nsol})"
    );
}

/// The automatic domain keeps the 0.1 m margin where fluid can leave (above an open tank,
/// beyond its ends) but not across a slab between two walls: there the dense cell grid would
/// otherwise hold tens of empty cells per particle.
#[test]
fn automatic_domain_is_thin_across_a_walled_slab() {
    let mut sc = staggered_fluid::scenes::dam_break(0.1, 0.005, 4, Default::default()).unwrap();
    sc.world.step(sc.gravity, sc.dt).unwrap();
    let (lo, hi) = sc.world.domain().unwrap();
    let h = sc.world.params().support_radius();
    let margin = sc.world.params().domain_margin;
    // the tank is 0.5 m long and 0.3 m high: full margin along x and y
    assert!(hi.x - lo.x > 0.5 + 2.0 * margin);
    assert!(hi.y - lo.y > 0.3 + 2.0 * margin);
    // across the 20 mm slab (walls 2h + Δx thick each side): at most twice its extent plus 2h
    let extent = 0.02 + 2.0 * (2.0 * h + 0.005);
    assert!(
        hi.z - lo.z <= 2.0 * extent + 2.0 * h + 1e-4,
        "z extent {} for a slab {extent} m wide",
        hi.z - lo.z
    );
}

/// The search on a box of the grid's cells around the points (`Grid::crop`, what a step uses)
/// gives exactly the lists of the search on the whole grid, solids outside the box left out.
#[test]
fn cropped_grid_gives_the_same_lists() {
    let mut seed = 5;
    let mut pts = |n: usize, s: f32, o: f32| -> Vec<Vector> {
        (0..n)
            .map(|_| {
                Vector::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * s + Vector::splat(o)
            })
            .collect()
    };
    // fluid in the middle of a large domain, solids everywhere
    let (fluid, solids) = (pts(1500, 0.3, 0.35), pts(3000, 1.0, 0.0));
    let radius = 0.05;
    let full = Grid::new(Vector::splat(-0.01), Vector::splat(1.01), radius);
    let lists = |grid: &Grid| {
        let cells: Vec<u32> = fluid.iter().map(|p| grid.cell_of(*p)).collect();
        let (forder, fstart) = counting_sort(&cells, grid.cell_count() as usize);
        let sorted: Vec<Vector> = forder.iter().map(|&o| fluid[o as usize]).collect();
        let (lo, hi) = (grid.min(), grid.hi());
        let inside: Vec<u32> = (0..solids.len() as u32)
            .filter(|&s| {
                (0..3).all(|k| solids[s as usize][k] >= lo[k] && solids[s as usize][k] <= hi[k])
            })
            .collect();
        let sc: Vec<u32> = inside
            .iter()
            .map(|&s| grid.cell_of(solids[s as usize]))
            .collect();
        let (sorder, sstart) = counting_sort(&sc, grid.cell_count() as usize);
        let ids: Vec<u32> = sorder.iter().map(|&o| inside[o as usize]).collect();
        let mut l = NeighborLists::default();
        build_lists(
            grid, radius, &sorted, &fstart, &solids, &ids, &sstart, &mut l,
        );
        (sorted, l)
    };
    let (a, b) = fluid.iter().fold(
        (
            Vector::splat(f32::INFINITY),
            Vector::splat(f32::NEG_INFINITY),
        ),
        |(a, b), p| (a.min(*p), b.max(*p)),
    );
    let (ca, cb) = (full.coords(a), full.coords(b));
    let crop = full.crop(ca.map(|c| c - 2), cb.map(|c| c + 2));
    assert!(
        crop.cell_count() * 4 < full.cell_count(),
        "the crop must be smaller"
    );
    let (s1, l1) = lists(&full);
    let (s2, l2) = lists(&crop);
    assert!(s1 == s2, "the same cell order");
    assert_eq!(l1.offsets, l2.offsets);
    assert_eq!(l1.fluid_end, l2.fluid_end);
    assert_eq!(l1.indices, l2.indices);
    assert!(l1.indices.len() > 10 * fluid.len(), "real pairs");
    assert!(
        (0..fluid.len()).any(|i| !l1.solid_range(i).is_empty()),
        "solids among the neighbours"
    );
}
