//! Issue 19 item 2: a body lying on the floor under water feels the water's pressure on its
//! underside (`step/sealed.rs`). A block of density 800 resting on a rapier tank's floor
//! stayed there for good (no fluid carrier fits under it, so nothing pushed it up); now it
//! lifts off, while a block heavier than water stays down. (The target — rising half
//! its side within twice the frictionless time — is not met: a spacing off the floor the
//! single layer of water under the body still holds it, see docs/experiments.md.)
mod support;

use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

const DX: f32 = 0.025;
const HALF: f32 = 0.05;

/// The block's bottom above the floor after `frames` rapier frames, and the sealed faces the
/// first frame found.
fn lift(rho: f32, slip: Slip, frames: usize) -> (f32, u64) {
    lift_with(rho, slip, frames, FluidParams::default())
}

/// [`lift`] with the fluid's parameters given (their spacing replaced by `DX`).
fn lift_with(rho: f32, slip: Slip, frames: usize, params: FluidParams) -> (f32, u64) {
    let shape = ColliderBuilder::cuboid(HALF, HALF, HALF).density(rho);
    let at = Vector::new(0.2, HALF, 0.2);
    let params = FluidParams {
        spacing: DX,
        ..params
    };
    let support::BodyInTank {
        mut physics,
        mut fluid,
        body: b,
    } = support::body_in_tank_with(shape, at, slip, 0.35, true, params);
    let n = fluid.fluid().len();
    let mut sealed = 0;
    for k in 0..frames {
        let rep = fluid.step_physics_world(&mut physics).unwrap();
        if k == 0 {
            sealed = rep.sealed_faces;
        }
    }
    assert_eq!(fluid.fluid().len(), n, "carriers lost");
    (physics.bodies[b].translation().y - HALF, sealed)
}

/// Without the sealed faces' pressure the block stayed within 0.2 mm of the floor; it must
/// leave it by a fifth of a spacing in 0.5 s (frictionless rise from rest at
/// `a = (ρ_f − ρ_b) g / (ρ_b + 0.6 ρ_f)` would take it 175 mm), under free slip and no slip.
#[test]
fn a_light_block_on_the_floor_lifts_off() {
    for slip in [Slip::FreeSlip, Slip::NoSlip] {
        let (gap, sealed) = lift(800.0, slip, 30);
        println!(
            "{slip:?}: bottom {:.1} mm above the floor after 0.5 s; {sealed} sealed faces in the \
             first frame",
            1e3 * gap
        );
        assert!(sealed > 0, "{slip:?}: no sealed face found");
        assert!(
            gap >= 0.2 * DX,
            "{slip:?}: bottom only {gap} m above the floor"
        );
    }
}

/// A block heavier than water stays on the floor: the pressure under it is the water's, not
/// more (a first version that gave every face touching the floor the full water column lifted
/// a 1 500 kg/m³ block 17 mm).
#[test]
fn a_heavy_block_on_the_floor_stays_down() {
    let (gap, sealed) = lift(1500.0, Slip::FreeSlip, 30);
    println!("bottom {:.1} mm above the floor after 0.5 s", 1e3 * gap);
    assert!(sealed > 0);
    assert!(gap.abs() < 0.1 * DX, "bottom {gap} m above the floor");
}

/// With [`FluidParams::wall_support`] the water beside a block pushes its bottom edge
/// carriers sideways (no edge lift), so the sealed faces carry the whole bottom: each face's
/// uncovered share counts the actual pushes' part along the floor's normal, an edge carrier
/// owns a full spacing² of the bottom, and the pressure is at most the column of water over
/// the block (the first frames' overpressure, up to 1.5× hydrostatic, lifted a 1 500 kg/m³
/// block 26 mm without that bound). Free slip: the 800 kg/m³ block leaves the floor by a
/// fifth of a spacing in 0.5 s, the 1 500 kg/m³ one stays within a tenth of a spacing.
/// (Under no slip, with the body's weight shared with its lump since the thirty-third
/// session, the light block rises 21.6 mm: [`a_light_block_on_the_floor_lifts_off`].)
#[test]
fn with_wall_support_light_blocks_lift_off_and_heavy_ones_stay_down() {
    let params = || FluidParams {
        wall_support: true,
        ..Default::default()
    };
    let (light, sealed) = lift_with(800.0, Slip::FreeSlip, 30, params());
    let (heavy, _) = lift_with(1500.0, Slip::FreeSlip, 30, params());
    println!(
        "wall_support: 800 kg/m³ {:.1} mm, 1 500 kg/m³ {:.1} mm above the floor after 0.5 s",
        1e3 * light,
        1e3 * heavy
    );
    assert!(sealed > 0, "no sealed face found");
    assert!(light >= 0.2 * DX, "800 kg/m³: bottom only {light} m up");
    assert!(heavy.abs() < 0.1 * DX, "1 500 kg/m³: bottom {heavy} m up");
}

/// A ball twice as dense as water resting on the floor of a rapier tank under water, at
/// rapier's 1/60 s: the fluid's substeps keep it off the floor rapier also collides it with,
/// so the pose they hand to rapier is the one rapier keeps — the ball is not driven into the
/// floor by its weight less its buoyancy each frame and lifted back by rapier's contact
/// (1.5 mm a frame before, 0.2 mm now: what is left is the slop of a hundredth of a spacing, 0.25 mm, and
/// rapier's own resting overlap). It stays on the floor, feels its buoyancy from the water,
/// and no carrier ends inside it.
#[test]
fn a_ball_resting_on_the_floor_is_not_pumped_by_the_substeps() {
    let (r, rho, dx) = (0.06f32, 2000.0f32, 0.025f32);
    let support::BodyInTank {
        mut physics,
        mut fluid,
        body,
    } = support::body_in_tank(
        ColliderBuilder::ball(r).density(rho),
        Vector::new(0.2, r, 0.2),
        Slip::FreeSlip,
        0.25,
        true,
        dx,
    );
    let (mut worst, mut lift, mut force) = (0.0f32, 0.0f32, 0.0f32);
    for k in 0..60 {
        fluid
            .step_with_rapier(
                physics.gravity,
                1.0 / 60.0,
                &mut physics.bodies,
                &physics.colliders,
            )
            .unwrap();
        let handed = fluid.rigids()[0].com.y;
        physics.step();
        fluid
            .correct_after_rapier(&mut physics.bodies, &physics.colliders)
            .unwrap();
        let kept = physics.bodies[body].center_of_mass().y;
        if k >= 20 {
            worst = worst.max((handed - kept).abs());
            lift = lift.max((kept - r).abs());
            force += fluid.rigids()[0].impulse[1] as f32 * 60.0 / 40.0;
        }
    }
    let buoyancy = 1000.0 * 9.81 * 4.0 / 3.0 * std::f32::consts::PI * r.powi(3);
    println!(
        "largest jump {:.3} mm, ball centre within {:.3} mm of resting, fluid force {force:.2} N \
         (buoyancy {buoyancy:.2} N)",
        1e3 * worst,
        1e3 * lift
    );
    assert!(worst < 0.015 * dx, "the ball jumps {worst} m a frame");
    assert!(lift < 0.02 * dx, "the ball left the floor by {lift} m");
    // the buoyancy of a ball on the floor (no water under its contact point: a little less)
    assert!(
        force > 0.8 * buoyancy && force < 1.2 * buoyancy,
        "fluid force {force} N"
    );
    let centre = physics.bodies[body].center_of_mass();
    let inside = fluid
        .fluid()
        .x
        .iter()
        .filter(|x| (**x - centre).length() < r - 0.01 * dx)
        .count();
    assert_eq!(inside, 0);
}
