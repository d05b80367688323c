//! Issue 23: cloth (Shao et al. 2014 §3.4.1, last paragraph, Fig. 10).
use staggered_fluid::deform::{DeformableHandle, DeformableParams};
use staggered_fluid::prelude::*;
use staggered_fluid::Solver;

const DX: f32 = 0.02;
const G: Vector = Vector::new(0.0, -9.81, 0.0);
/// Tank side, cloth height, cloth side.
const TANK: f32 = 0.4;
const AT: f32 = 0.3;
const SIDE: f32 = 0.36;

/// A cloth across the middle of a tank, pinned along its edges, with a column of water
/// (`n`³ carriers) released just above it.
fn cloth_under_a_column(
    params: DeformableParams,
    n: usize,
    solver: Solver,
) -> (FluidWorld, DeformableHandle) {
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        solver,
        on_failure: staggered_fluid::OnFailure::Warn,
        ..Default::default()
    })
    .unwrap();
    let c = 0.5 * TANK;
    w.add_open_tank(Vector::ZERO, Vector::new(TANK, 0.7, TANK), Slip::FreeSlip)
        .unwrap();
    let h = w
        .add_cloth(
            "cloth",
            Pose::from_translation(Vector::new(c, AT, c)),
            [SIDE, SIDE],
            params,
        )
        .unwrap();
    let edge = 0.5 * SIDE - 0.5 * DX;
    let pinned = w
        .pin_deformable(h, |p| (p.x - c).abs() > edge || (p.z - c).abs() > edge)
        .unwrap();
    assert_eq!(pinned, 19 * 19 - 17 * 17);
    let half = 0.5 * n as f32 * DX;
    let lo = Vector::new(c - half, AT + 2.0 * DX, c - half);
    w.add_block(lo, lo + Vector::splat(2.0 * half), Vector::ZERO)
        .unwrap();
    (w, h)
}

/// Fluid carriers below the cloth where it is: under the cloth's footprint, lower than the
/// nearest cloth point by more than half a spacing.
fn through(w: &FluidWorld, h: DeformableHandle) -> usize {
    let pts = w.deformable(h).unwrap().positions();
    let c = 0.5 * TANK;
    w.fluid()
        .x
        .iter()
        .filter(|x| (x.x - c).abs() < 0.5 * SIDE && (x.z - c).abs() < 0.5 * SIDE)
        .filter(|x| {
            let near = pts
                .iter()
                .min_by(|a, b| {
                    let (da, db) = (**a - **x, **b - **x);
                    (da.x * da.x + da.z * da.z).total_cmp(&(db.x * db.x + db.z * db.z))
                })
                .unwrap();
            x.y < near.y - 0.5 * DX
        })
        .count()
}

/// A second of a cloth of stiffness α catching a column of 4³ carriers: the most carriers
/// found through it at any frame, its mean sag (its lowest point below where it was pinned)
/// and the mean vertical force of the water on it over the last half second, with the
/// water's weight.
fn catch(stiffness: f32, solver: Solver) -> (usize, f32, f32, f32) {
    let params = DeformableParams {
        density: 1000.0,
        stiffness,
        half_width: 3,
        damping: 0.1,
        ..Default::default()
    };
    let (mut w, h) = cloth_under_a_column(params, 4, solver);
    let n0 = w.fluid().len();
    let weight = n0 as f32 * w.particle_mass() * 9.81;
    let (mut most, mut sag, mut force) = (0, 0.0, 0.0);
    for k in 0..60 {
        let r = w.step(G, 1.0 / 60.0).unwrap();
        assert!(r.warnings.is_empty(), "{:?}", r.warnings);
        most = most.max(through(&w, h));
        if k >= 30 {
            let b = w.deformable(h).unwrap();
            let low = b
                .positions()
                .iter()
                .map(|p| p.y)
                .fold(f32::INFINITY, f32::min);
            sag += (AT - low) / 30.0;
            force += w.deformable_force(h).unwrap().y / 30.0;
        }
    }
    assert_eq!(w.fluid().len(), n0);
    (most, sag, force, weight)
}

/// A pinned cloth under a falling column of water holds it — no carrier passes, and once the
/// splash is over the water rests on it with its weight (within 10 %) — and sags under it,
/// deeper for a softer cloth.
#[test]
fn a_pinned_cloth_holds_a_falling_column_and_sags() {
    let mut sags = Vec::new();
    for stiffness in [1.0, 0.5] {
        let (through, sag, force, weight) = catch(stiffness, Solver::Staggered);
        assert_eq!(through, 0, "carriers through the cloth at α = {stiffness}");
        assert!(
            (force + weight).abs() < 0.1 * weight,
            "the water pushes the cloth with {force} N, weighs {weight} N"
        );
        sags.push(sag);
    }
    assert!(sags[0] > 0.5 * DX, "the stiff cloth sagged {} m", sags[0]);
    assert!(sags[1] > 1.2 * sags[0], "sags {sags:?}");
}

/// The second solver couples the cloth the same way: it holds the column too.
#[test]
fn a_cloth_holds_water_under_pcisph_too() {
    let (through, sag, force, weight) = catch(1.0, Solver::Pcisph);
    assert_eq!(through, 0);
    assert!(
        (force + weight).abs() < 0.1 * weight,
        "{force} N against {weight} N"
    );
    assert!(sag > 0.5 * DX, "sagged {sag} m");
}

/// Bad cloth input is a clear error that adds nothing.
#[test]
fn bad_cloth_input_is_a_clear_error() {
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        ..Default::default()
    })
    .unwrap();
    let pose = Pose::from_translation(Vector::splat(0.2));
    for (size, says) in [([0.01, 0.3], "size[0]"), ([0.3, f32::NAN], "size[1]")] {
        let e = w
            .add_cloth("c", pose, size, DeformableParams::default())
            .unwrap_err();
        assert!(e.to_string().contains(says), "{e}");
    }
    let melting = DeformableParams {
        melting: Some(Default::default()),
        ..Default::default()
    };
    let e = w.add_cloth("c", pose, [0.3, 0.3], melting).unwrap_err();
    assert!(e.to_string().contains("cannot melt"), "{e}");
    let e = w
        .add_cloth(
            "c",
            pose,
            [0.3, 0.3],
            DeformableParams {
                stiffness: 0.0,
                ..Default::default()
            },
        )
        .unwrap_err();
    assert!(e.to_string().contains("stiffness"), "{e}");
    assert!(w.deformables().is_empty() && w.solids().is_empty());
}
