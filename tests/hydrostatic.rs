//! Hydrostatic tank: the fluid's weight reaches the floor.
use staggered_fluid::scenes;

#[test]
fn floor_force_matches_fluid_weight() {
    // 20 × 15 × 20 = 6000 fluid carriers, 2 s at Δt = 2 ms
    let mut sc = scenes::hydrostatic(0.4, 0.3, 0.02, Default::default()).unwrap();
    assert!(sc.world.fluid().len() >= 5000);
    let mass0 = sc.world.fluid_mass();
    let mut errs = Vec::new();
    let r = sc
        .run(2.0, |_, rep| {
            if rep.time > 0.1 {
                errs.push(rep.error);
            }
        })
        .unwrap();
    let tail: Vec<f64> = r
        .metric
        .iter()
        .filter(|m| m.t >= 1.8 - 1e-9)
        .map(|m| m.normalized)
        .collect();
    let mean = tail.iter().sum::<f64>() / tail.len() as f64;
    assert!(
        (mean - 1.0).abs() < 0.03,
        "floor force / weight over the last 0.2 s = {mean}"
    );
    // E (Eq. 29) of every solve after the first 0.1 s is within the 1 % tolerance
    assert!(
        errs.iter().all(|&e| e <= 0.01),
        "max E {}",
        errs.iter().cloned().fold(0.0, f64::max)
    );
    // no fluid carrier inside a wall or outside the tank (inner space [0, 0.4]² × [0, 0.45])
    for (k, p) in sc.world.fluid().x.iter().enumerate() {
        assert!(
            p.x > 0.0 && p.x < 0.4 && p.z > 0.0 && p.z < 0.4 && p.y > 0.0,
            "carrier {k} at {p:?} is in a wall or outside the tank"
        );
    }
    // fluid mass is only ever lost through counted removals
    let removed = sc.world.removed_total() as f64 * sc.world.particle_mass() as f64;
    assert!((sc.world.fluid_mass() + removed - mass0).abs() < 1e-9 * mass0);
}
