//! Snapshots: a run resumed from a snapshot matches the uninterrupted run step for step, bit for
//! bit (fluid carriers, rapier bodies, emitter output), with rapier bodies in contact, a
//! sink and an emitter.

use staggered_fluid::scenes::{self, Scene};
use staggered_fluid::snapshot::Snapshot;
use staggered_fluid::FluidParams;

/// Position and velocity of one particle or body.
type Motion = [f32; 6];

/// Positions and velocities of the fluid (by stable id) and of every rapier body.
fn state(s: &Scene) -> (Vec<(u32, Motion)>, Vec<Motion>) {
    let f = s.world.fluid();
    let mut fluid: Vec<(u32, Motion)> = (0..f.len())
        .map(|i| {
            let (x, v) = (f.x[i], f.v[i]);
            (f.id[i], [x.x, x.y, x.z, v.x, v.y, v.z])
        })
        .collect();
    fluid.sort_by_key(|e| e.0);
    let bodies = s
        .physics
        .as_ref()
        .map(|ph| {
            ph.bodies
                .iter()
                .map(|(_, b)| {
                    let (x, v) = (b.translation(), b.linvel());
                    [x.x, x.y, x.z, v.x, v.y, v.z]
                })
                .collect()
        })
        .unwrap_or_default();
    (fluid, bodies)
}

fn resumed_matches(mut a: Scene, before: usize, after: usize) {
    let dt = a.dt as f64;
    a.run(before as f64 * dt, |_, _| {}).unwrap();
    let path = std::env::temp_dir().join(format!("sf_snapshot_{}.bin", a.name));
    Snapshot::save(&a, &path).unwrap();
    let mut b = Snapshot::load(&path).unwrap().resume().unwrap();
    std::fs::remove_file(&path).ok();
    assert_eq!(
        state(&a),
        state(&b),
        "{}: state right after resuming",
        a.name
    );
    for k in 0..after {
        a.run(dt, |_, _| {}).unwrap();
        b.run(dt, |_, _| {}).unwrap();
        let (sa, sb) = (state(&a), state(&b));
        assert!(!sa.0.is_empty());
        assert_eq!(sa, sb, "{}: step {k} after resuming differs", a.name);
        assert_eq!(a.world.time(), b.world.time());
    }
}

#[test]
fn resumed_five_balls_match_step_for_step() {
    // balls falling into the water and touching it during the resumed steps
    let s = scenes::five_balls(0.04, FluidParams::default()).unwrap();
    resumed_matches(s, 30, 15);
}

#[test]
fn resumed_tap_matches_step_for_step() {
    // an emitter half way through a layer and a sink draining
    let s = scenes::spec_by_name("tap", Some(0.02), FluidParams::default())
        .unwrap()
        .build()
        .unwrap();
    resumed_matches(s, 113, 20);
}

#[test]
fn a_file_that_is_not_a_snapshot_is_an_error() {
    let err = Snapshot::from_bytes(b"hello, this is not a snapshot")
        .err()
        .expect("rejected");
    assert!(
        err.to_string().contains("not a staggered-fluid snapshot"),
        "{err}"
    );
    let mut bytes =
        Snapshot::encode(&scenes::hydrostatic(0.2, 0.1, 0.05, FluidParams::default()).unwrap())
            .unwrap();
    bytes.truncate(bytes.len() / 2);
    assert!(Snapshot::from_bytes(&bytes).is_err());
}

#[test]
fn a_resumed_tank_keeps_its_step_and_measures_the_same_floor() {
    let mut a = scenes::hydrostatic(0.2, 0.1, 0.04, FluidParams::default()).unwrap();
    a.dt *= 0.5;
    a.run(0.01, |_, _| {}).unwrap();
    let b = Snapshot::from_bytes(&Snapshot::encode(&a).unwrap())
        .unwrap()
        .resume()
        .unwrap();
    assert_eq!(b.dt, a.dt);
    // the probe still points at the floor: the same force
    assert_eq!(a.sample().value, b.sample().value);
    assert!(b.sample().normalized > 0.5, "{:?}", b.sample());
}
