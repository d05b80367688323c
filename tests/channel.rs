//! Slip conditions (He 2012 §5.2): a fluid column falling between two vertical plates.
//! No-slip plates hold the fluid beside them back and shape a parabola-like profile; free-slip
//! plates let the whole column fall together.
use staggered_fluid::prelude::*;
use staggered_fluid::scenes;

const WIDTH: f32 = 0.1;
const SPACING: f32 = 0.01;
const COLUMNS: usize = 10; // one profile bin per carrier column

/// Vertical velocity profile across the channel after `seconds` (m/s, downward positive).
fn profile(slip: Slip, seconds: f64) -> Vec<f32> {
    // ν = 0.01 m²/s: the viscous time w²/ν is 1 s, so 0.3 s shapes a clear boundary layer
    let mut sc = scenes::channel(WIDTH, SPACING, 3, slip, 0.01, FluidParams::default()).unwrap();
    sc.run(seconds, |_, _| {}).unwrap();
    let p = scenes::channel_profile(&sc.world, WIDTH, COLUMNS);
    p.iter().map(|v| -v).collect()
}

#[test]
fn no_slip_plates_hold_the_wall_fluid_back() {
    let p = profile(Slip::NoSlip, 0.3);
    println!("no-slip profile {p:?}");
    let centre = 0.5 * (p[4] + p[5]);
    assert!(centre > 0.5, "centreline should fall, got {centre} m/s");
    for wall in [p[0], p[COLUMNS - 1]] {
        assert!(
            wall.abs() < 0.1 * centre,
            "wall column {wall} vs centre {centre}"
        );
    }
    // parabola-like: monotone from each wall to the centre
    for k in 0..4 {
        assert!(
            p[k] < p[k + 1] + 0.02 * centre,
            "not rising to the centre: {p:?}"
        );
        assert!(
            p[COLUMNS - 1 - k] < p[COLUMNS - 2 - k] + 0.02 * centre,
            "{p:?}"
        );
    }
    // and curved: the quarter points fall well below the centre, well above the walls
    let quarter = 0.5 * (p[2] + p[7]);
    assert!(quarter > 0.4 * centre && quarter < 0.95 * centre, "{p:?}");
}

#[test]
fn free_slip_plates_let_the_column_fall_together() {
    let p = profile(Slip::FreeSlip, 0.3);
    println!("free-slip profile {p:?}");
    let mean = p.iter().sum::<f32>() / p.len() as f32;
    // free fall for 0.3 s reaches g t = 2.9 m/s
    assert!(mean > 2.0, "column should fall freely, mean {mean} m/s");
    for v in &p {
        assert!((v - mean).abs() < 0.1 * mean, "profile not flat: {p:?}");
    }
}
