//! Emitters and sinks on He 2012 Fig. 13 (tap water on a sphere): the tap delivers
//! `speed × outlet area` of water, the sink removes what reaches the floor, every carrier is
//! accounted for, none enters the sphere, and the §5.2 no-stick inequality decides whether
//! the water leaves the sphere (no-stick) or wraps around it and drips from its bottom
//! (sticky).

use staggered_fluid::scenes;
use staggered_fluid::FluidParams;

/// A block of water at rest in `[min, max]`.
fn still_water(min: [f32; 3], max: [f32; 3]) -> staggered_fluid::scenes::BlockSpec {
    staggered_fluid::scenes::BlockSpec {
        min,
        max,
        velocity: [0.0; 3],
        around_bodies: false,
    }
}

fn tap(name: &str) -> (f64, u64, u64, usize) {
    let mut sc = scenes::by_name(name, None).unwrap();
    let dx = sc.world.params().spacing;
    let r = sc.run(0.8, |_, _| {}).unwrap();
    // 21 carriers per layer (a disc of radius 2.5 Δx on the lattice), one layer per Δx of
    // travel at 1 m/s, the first at the opening
    let layers = 1 + (0.8f32 / dx + 1e-3).floor() as u64;
    assert!(
        r.emitted.abs_diff(21 * layers) <= 21,
        "{name}: emitted {} against {}",
        r.emitted,
        21 * layers
    );
    // nothing is lost without being counted
    assert_eq!(
        r.n_fluid as u64,
        r.emitted - r.sunk - r.removed_outside,
        "{name}: carriers unaccounted for"
    );
    assert!(r.sunk > 0, "{name}: the sink never drained");
    assert_eq!(
        scenes::carriers_inside_solids(&sc.world),
        0,
        "{name}: water inside the sphere"
    );
    let share = r.comparison.values["lower_half_share_of_wetting_fluid_second_half"]
        .as_f64()
        .unwrap();
    (share, r.emitted, r.sunk, r.n_fluid)
}

#[test]
fn tap_water_leaves_a_no_stick_sphere_and_wraps_a_sticky_one() {
    let (free, ..) = tap("tap");
    let (sticky, ..) = tap("tap_sticky");
    // no-stick: the stream separates from the upper half and splashes off; almost none of the
    // water touching the sphere is on its lower half
    assert!(
        free < 0.1,
        "no-stick: {:.2} of the wetting water below the equator",
        free
    );
    // sticky: the film follows the sphere round to its bottom
    assert!(
        sticky > 0.3,
        "sticky: {:.2} of the wetting water below the equator",
        sticky
    );
}

#[test]
fn an_emitter_that_opens_later_and_closes_adds_only_while_open() {
    use staggered_fluid::scenes::{EmitterSpec, OutletSpec};
    let mut spec = scenes::spec_by_name("tap", Some(0.02), FluidParams::default()).unwrap();
    spec.emitters[0].outlet = OutletSpec::Rectangle {
        half_extents: [0.02, 0.04],
    };
    // a second tap that opens at 0.1 s and closes at 0.2 s
    spec.emitters.push(EmitterSpec {
        start: 0.1,
        stop: Some(0.2),
        center: [0.1, 0.4, 0.1],
        ..spec.emitters[0].clone()
    });
    let mut sc = spec.build().unwrap();
    let mut counts = Vec::new();
    let r = sc
        .run(0.3, |s, _| {
            counts.push((s.world.time(), s.emitters[1].emitted))
        })
        .unwrap();
    // the rectangle: 3 × 5 carriers per layer at Δx = 2 cm, 50 layers per second
    let per = 3 * 5;
    let first = r.emitted - sc.emitters[1].emitted;
    assert!(first.abs_diff(per * 16) <= per, "first tap emitted {first}");
    let second = sc.emitters[1].emitted;
    assert!(
        second.abs_diff(per * 5) <= per,
        "second tap emitted {second}"
    );
    for (t, n) in counts {
        if t < 0.1 - 1e-6 {
            assert_eq!(n, 0, "the second tap emitted before opening (t = {t})");
        }
        if t > 0.2 + 0.003 {
            assert_eq!(n, second, "the second tap emitted after closing (t = {t})");
        }
    }
}

#[test]
fn an_emitter_above_the_tank_rim_is_inside_the_domain() {
    // the automatic domain is fixed at the first step; it must include the outlet of a tap
    // that opens later, above every wall, over water already in the tank
    let mut spec = scenes::spec_by_name("tap", Some(0.02), FluidParams::default()).unwrap();
    spec.emitters[0].center[1] = 0.8;
    spec.emitters[0].start = 0.05;
    spec.fluid
        .push(still_water([0.0, 0.06, 0.0], [0.1, 0.16, 0.1]));
    let mut sc = spec.build().unwrap();
    let r = sc.run(0.4, |_, _| {}).unwrap();
    assert!(r.emitted > 0);
    assert_eq!(
        r.n_fluid as u64,
        125 + r.emitted - r.sunk - r.removed_outside
    );
    // the stream fell 0.3 m into the tank: it reached below the rim at 0.5 m
    let lowest = sc
        .world
        .fluid()
        .x
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min);
    assert!(lowest < 0.5 || r.sunk > 0, "lowest carrier at {lowest} m");
}

#[test]
fn a_submerged_outlet_adds_no_carrier_on_top_of_another() {
    // a tap inside a full tank: the water in front cannot move on, so most layer points are
    // occupied; no carrier may be placed within half a spacing of another
    let mut spec = scenes::spec_by_name("tap", Some(0.02), FluidParams::default()).unwrap();
    spec.sinks.clear();
    spec.emitters[0].center = [0.2, 0.1, 0.2];
    spec.fluid.push(still_water([0.0; 3], [0.4, 0.2, 0.4]));
    let mut sc = spec.build().unwrap();
    let n0 = sc.world.fluid().len() as u64;
    let r = sc.run(0.1, |_, _| {}).unwrap();
    let e = &sc.emitters[0];
    assert!(e.blocked > 0, "no layer point was found occupied");
    assert_eq!(r.n_fluid as u64, n0 + r.emitted - r.removed_outside);
    // the emitted water is pushed into the tank, not stacked: carriers stay apart
    let x = &sc.world.fluid().x;
    let dx = 0.02f32;
    let close = (0..x.len())
        .flat_map(|i| (i + 1..x.len()).map(move |j| (i, j)))
        .filter(|&(i, j)| (x[i] - x[j]).length() < 0.3 * dx)
        .count();
    assert_eq!(close, 0, "{close} pairs of carriers closer than 0.3 Δx");
}
