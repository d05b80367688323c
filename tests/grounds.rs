//! Grounds a game uses couple to the fluid (issue 19): rapier's guide's 200 m ground cuboid, a
//! half-space and a height field, each the floor of a 0.5 m pool walled by fluid-only boxes,
//! are sampled only where the water can reach, and hold the water; `add_rapier_tank` makes a
//! tank for both worlds at once, and water poured around its colliders fills it as a
//! fluid-only block would.
use rapier3d::parry::utils::Array2;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

const DX: f32 = 0.04;

/// A pool `[0, 0.5]²` with walls of fluid-only boxes reaching into the ground, the ground a
/// rapier collider; 0.2 m of water, 2 s at 1/60 s. Returns (seconds to couple, ground
/// carriers, water lost, lowest carrier height at the end).
fn pool_on(ground: ColliderBuilder) -> (f64, usize, usize, f32) {
    let bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    colliders.insert(ground);
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: DX,
        ..Default::default()
    })
    .unwrap();
    let (w, t) = (0.5f32, 0.12f32);
    for (name, lo, hi) in [
        (
            "-x",
            Vector::new(-t, -0.2, -t),
            Vector::new(0.0, 0.6, w + t),
        ),
        (
            "+x",
            Vector::new(w, -0.2, -t),
            Vector::new(w + t, 0.6, w + t),
        ),
        ("-z", Vector::new(0.0, -0.2, -t), Vector::new(w, 0.6, 0.0)),
        ("+z", Vector::new(0.0, -0.2, w), Vector::new(w, 0.6, w + t)),
    ] {
        fluid.add_static_box(name, lo, hi, Slip::FreeSlip).unwrap();
    }
    let start = std::time::Instant::now();
    let done = fluid
        .couple_all(&bodies, &colliders, Slip::FreeSlip)
        .unwrap();
    assert_eq!(done.coupled.len(), 1, "skipped: {:?}", done.skipped);
    let n = fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(w, 0.2, w),
            Vector::ZERO,
            &colliders,
        )
        .unwrap();
    fluid
        .step(Vector::new(0.0, -9.81, 0.0), 1.0 / 60.0)
        .unwrap();
    let couple = start.elapsed().as_secs_f64();
    let ground = fluid.solid(done.coupled[0].1).unwrap().range.len();
    for _ in 0..119 {
        fluid
            .step(Vector::new(0.0, -9.81, 0.0), 1.0 / 60.0)
            .unwrap();
    }
    let lowest = fluid
        .fluid()
        .x
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min);
    (couple, ground, n - fluid.fluid().len(), lowest)
}

#[test]
fn game_grounds_couple_where_the_water_is_and_hold_it() {
    // rapier's guide: a ground cuboid 200 m wide, 0.2 m thick, its top at y = 0
    let cuboid =
        ColliderBuilder::cuboid(100.0, 0.1, 100.0).translation(Vector::new(0.0, -0.1, 0.0));
    let half_space = ColliderBuilder::new(SharedShape::halfspace(Vector::Y));
    // a 20 m terrain with ±1 cm bumps around y = 0, 1 m cells
    let (rows, cols) = (21, 21);
    let heights: Vec<f32> = (0..rows * cols)
        .map(|k| 0.01 * ((k % 7) as f32 / 3.0 - 1.0))
        .collect();
    let terrain = ColliderBuilder::heightfield(
        Array2::new(rows, cols, heights),
        Vector::new(20.0, 1.0, 20.0),
    );
    for (name, ground) in [
        ("cuboid", cuboid),
        ("half-space", half_space),
        ("height field", terrain),
    ] {
        let (t, carriers, lost, lowest) = pool_on(ground);
        println!("{name}: coupled and sampled in {t:.3} s, {carriers} ground carriers, {lost} carriers lost, lowest at {lowest:.4} m");
        // sampled where the water can reach: the domain's footprint, not 200 m (a whole
        // 200 m shell would be 10⁸ carriers at this spacing)
        assert!(
            carriers > 0 && carriers < 20_000,
            "{name}: {carriers} ground carriers"
        );
        assert_eq!(lost, 0, "{name}: water lost");
        // nothing sank into the ground (the height field's bumps are ±1 cm)
        assert!(lowest > -0.015, "{name}: a carrier at {lowest} m");
    }
}

#[test]
fn a_ground_on_a_moving_body_is_refused_by_name() {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let b = bodies.insert(RigidBodyBuilder::dynamic());
    colliders.insert_with_parent(
        ColliderBuilder::new(SharedShape::halfspace(Vector::Y)).density(1000.0),
        b,
        &mut bodies,
    );
    let mut fluid = FluidWorld::new(FluidParams::default()).unwrap();
    let done = fluid
        .couple_all(&bodies, &colliders, Slip::FreeSlip)
        .unwrap();
    assert!(done.coupled.is_empty());
    let e = done.skipped[0].1.to_string();
    assert!(
        e.contains("HalfSpace") && e.contains("collider 0") && e.contains("fixed ground"),
        "{e}"
    );
}

/// `add_rapier_tank` makes the fluid's walls and rapier's colliders together; water poured
/// around the colliders (a floating box among them) fills the tank as a fluid-only block of
/// the same box does, less the lattice points the box takes.
#[test]
fn a_rapier_tank_fills_like_a_fluid_only_block() {
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let params = FluidParams {
        spacing: 0.02,
        ..Default::default()
    };
    let (lo, hi) = (Vector::ZERO, Vector::new(0.4, 0.3, 0.2));
    let mut plain = FluidWorld::new(params.clone()).unwrap();
    plain.add_open_tank(lo, hi, Slip::NoSlip).unwrap();
    let n_plain = plain
        .add_block(lo, Vector::new(0.4, 0.2, 0.2), Vector::ZERO)
        .unwrap();
    let mut fluid = FluidWorld::new(params).unwrap();
    let tank = fluid
        .add_rapier_tank(&mut colliders, lo, hi, Slip::NoSlip)
        .unwrap();
    assert_eq!(colliders.len(), 5);
    let n_empty = fluid
        .add_block_around(lo, Vector::new(0.4, 0.2, 0.2), Vector::ZERO, &colliders)
        .unwrap();
    assert_eq!(n_empty, n_plain, "the tank's own colliders take no water");
    // with a box among the colliders, coupled: 0.12 × 0.08 × 0.12 m, its faces midway
    // between lattice planes, under the water's level
    let mut again = FluidWorld::new(fluid.params().clone()).unwrap();
    let mut colliders = ColliderSet::new();
    again
        .add_rapier_tank(&mut colliders, lo, hi, Slip::NoSlip)
        .unwrap();
    let b = bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.1, 0.1)));
    colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.06, 0.04, 0.06).density(500.0),
        b,
        &mut bodies,
    );
    let coupled = again
        .couple_all(&bodies, &colliders, Slip::FreeSlip)
        .unwrap();
    assert_eq!(
        coupled.coupled.len(),
        1,
        "only the box: the tank is the fluid's already"
    );
    let n_box = again
        .add_block_around(lo, Vector::new(0.4, 0.2, 0.2), Vector::ZERO, &colliders)
        .unwrap();
    assert_eq!(
        n_box,
        n_plain - 6 * 4 * 6,
        "the box displaces its own lattice points"
    );
    assert_eq!(tank.walls.len(), 5);
}
