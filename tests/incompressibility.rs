//! The density constraint holds the SPH density, not only a divergence-free velocity (issue 18):
//! a still tank at rapier's 1/240 s and 1/60 s stays at rest density with its level where an
//! incompressible fluid's would be, and a sequence of very different step lengths neither
//! removes fluid nor turns the density correction into a jet.
mod support;
use staggered_fluid::metrics::{hydrostatic_fit, waterline};
use staggered_fluid::prelude::*;
use staggered_fluid::scenes;

const DX: f32 = 0.02;
const G: f32 = 9.81;

/// Kinetic energy of the fluid, J.
fn kinetic(w: &FluidWorld) -> f64 {
    let m = w.particle_mass() as f64;
    w.fluid()
        .v
        .iter()
        .map(|v| 0.5 * m * v.length_squared() as f64)
        .sum()
}

/// The 0.4 × 0.3 × 0.4 m still tank (Δx 2 cm, 6 000 carriers, no-slip walls) stepped at `dt`
/// for 1.5 s. After the first second: the inner carriers' mean compression, averaged over the
/// steps, within the 0.1 % default tolerance (a step that misses it is reported in
/// `StepReport::density_converged` and makes the next ones substep), the water level (top carriers + Δx/2, median over columns) within Δx/4
/// of the incompressible level V/A, the floor carrying the weight within 1 % as issue 18 asks
/// (the no-slip walls pin their first layer and hold part of the weight by friction, issue
/// 19: 0.9–1.0 % when this allowed 1.5 %, 0.16–0.2 % now; the free-slip test below holds the
/// floor to 0.1 %), and the total
/// pressure p^d + p^v rising with depth as ρ g within 1 % (least-squares slope over the inner
/// carriers more than 2Δx from the walls and the surface; the symmetric SPH force as printed
/// settles at 1.0114 / 1.0092 ρ̄g, its carriers' vertical moment 0.994, and with
/// `pressure_scale` at 1.0045 / 1.0047), reaching zero within Δx/4 of the
/// level, and the layer beneath the surface carrying its own depth's head within ρ̄gΔx/4.
fn still_tank_at(dt: f32) {
    let mut sc = scenes::hydrostatic(0.4, 0.3, DX, Default::default()).unwrap();
    let n = sc.world.fluid().len();
    let weight = sc.world.fluid_mass() * G as f64;
    let level0 = n as f32 * DX.powi(3) / (0.4 * 0.4);
    let floor = support::floor_index(&sc.world);
    let steps = (1.5 / dt).round() as usize;
    let (mut mean, mut worst, mut force, mut samples) = (0.0f64, 0.0f64, 0.0f64, 0);
    for k in 0..steps {
        let r = sc.world.step(sc.gravity, dt).unwrap();
        assert_eq!(r.removed_outside, 0, "step {k}: carriers left the tank");
        if (k + 1) as f32 * dt > 1.0 {
            mean += r.compression_mean;
            worst = worst.max(r.compression_mean);
            force -= sc.world.solids()[floor].force.y as f64;
            samples += 1;
        }
    }
    let (force, mean) = (force / samples as f64, mean / samples as f64);
    let level = waterline(sc.world.fluid().x.iter().copied(), &[], 0.0, DX).unwrap();
    // p^d + p^v against height, inner carriers away from the walls
    let f = sc.world.fluid();
    let rho_g = 1000.0 * G as f64;
    let samples: Vec<(f32, f64)> = (0..f.len())
        .filter(|&i| {
            let x = f.x[i];
            !f.surface[i]
                && x.x > 2.0 * DX
                && x.x < 0.4 - 2.0 * DX
                && x.z > 2.0 * DX
                && x.z < 0.4 - 2.0 * DX
        })
        .map(|i| (f.x[i].y, (f.p_density[i] + f.p_velocity[i]) as f64))
        .collect();
    // fitted over the carriers more than 2Δx above the floor and 3Δx below the level
    let fit = hydrostatic_fit(
        samples
            .iter()
            .filter(|(y, _)| *y > 2.0 * DX && *y < level - 3.0 * DX)
            .map(|&(y, p)| (y as f64, p)),
    )
    .expect("a pressure field to fit");
    // where the fitted pressure reaches zero: the free surface, where the water ends
    let (slope, zero) = (fit.gradient, fit.zero_level);
    // the second layer's pressure against its depth below the water's end
    let layer: Vec<f64> = samples
        .iter()
        .filter(|(y, _)| *y > level - 2.0 * DX && *y < level - DX)
        .map(|&(y, p)| p - rho_g * (level - y) as f64)
        .collect();
    let excess = layer.iter().sum::<f64>() / layer.len().max(1) as f64 / (rho_g * DX as f64);
    let n2 = layer.len();
    println!(
        "dt {dt}: compression {:.4} % (worst step {:.3} %), level {level:.4} vs {level0:.4} m, floor {:.4} W, dp/dy {:.4} ρg, p = 0 at {zero:.4} m, second layer {excess:+.3} ρ̄gΔx above ρ̄g·depth",
        100.0 * mean,
        100.0 * worst,
        force / weight,
        slope / rho_g
    );
    assert!(mean <= 0.001, "mean compression {mean}");
    assert!(
        (level - level0).abs() <= 0.25 * DX,
        "level {level} vs {level0}"
    );
    assert!(
        (force / weight - 1.0).abs() <= 0.01,
        "floor {force} N vs {weight} N"
    );
    assert!(
        (slope / rho_g - 1.0).abs() <= 0.01,
        "dp/dy {slope} vs ρg {rho_g}"
    );
    // the pressure vanishes where the water ends, not one layer above it (with p = 0 at the
    // top carriers the layer beneath carried two layers' head: zero at +0.4Δx, buoyancy
    // raised by ρ̄gΔx/2 at every depth)
    assert!(
        (zero - level as f64).abs() <= 0.25 * DX as f64,
        "pressure zero at {zero} m, water level {level} m"
    );
    // the layer beneath the surface carries its own depth's head, not the top layer's too
    // (with p = 0 at the top carriers: +0.4 ρ̄gΔx); a quarter spacing of head, as for the level
    assert!(
        n2 > 0 && excess.abs() <= 0.25,
        "second layer {excess} ρ̄gΔx above hydrostatic"
    );
}

#[test]
fn still_tank_holds_its_density_at_rapier_240hz() {
    still_tank_at(1.0 / 240.0);
}

#[test]
fn still_tank_holds_its_density_at_rapier_60hz() {
    still_tank_at(1.0 / 60.0);
}

/// Hydrostatics without wall friction: in the still tank with free-slip walls, stepped at
/// rapier's 1/60 s, the floor carries the water's weight within 0.1 % over the last 0.5 s
/// and the side walls nothing (with no-slip walls they hold 0.15–0.2 % of it: the first
/// layer is pinned to them, issue 19).
#[test]
fn still_tank_floor_carries_the_weight_without_wall_friction() {
    let mut spec = scenes::hydrostatic_spec(0.4, 0.3, DX, Default::default());
    spec.tanks[0].slip = Slip::FreeSlip;
    let mut sc = spec.build().unwrap();
    let weight = sc.world.fluid_mass() * G as f64;
    let dt = 1.0f32 / 60.0;
    let (mut floor, mut walls, mut samples) = (0.0f64, 0.0f64, 0);
    for k in 0..(1.5 / dt).round() as usize {
        sc.world.step(sc.gravity, dt).unwrap();
        if (k + 1) as f32 * dt > 1.0 {
            for s in sc.world.solids() {
                let fy = -s.force.y as f64;
                if s.name.contains("floor") {
                    floor += fy;
                } else {
                    walls += fy.abs();
                }
            }
            samples += 1;
        }
    }
    let (floor, walls) = (floor / samples as f64, walls / samples as f64);
    println!(
        "free slip: floor {:.5} W, side walls |Fy| {:.5} W",
        floor / weight,
        walls / weight
    );
    assert!(
        (floor / weight - 1.0).abs() <= 0.001,
        "floor {floor} N vs {weight} N"
    );
    assert!(walls / weight <= 1e-4, "side walls {walls} N");
}

/// Step lengths a game may produce: 60 steps of 5 ms of a dam break, then one of 1 µs, one of
/// 1 ns, then 20 of 5 ms again. No carrier leaves the domain, the largest speed never exceeds
/// twice its value before the short steps, and the kinetic energy never jumps by more than 10 %
/// in one step after them. (On 78174e6 the 1 µs step took the largest speed from 0.11 to
/// 285 m/s and 68 % of the fluid left.)
#[test]
fn step_sequence_with_microsecond_steps_stays_calm() {
    step_sequence(Default::default());
}

/// The same with the hydrostatic wall pressure, which carries each carrier's acceleration to
/// the walls: averaged over the last 0.1 √(Δx/|g|) of simulated time, weighted by substep
/// length, so the 1 µs step's acceleration (the velocity constraint's correction over 1 µs)
/// barely counts. (With the last substep's acceleration alone the wall pressure took the
/// largest speed past twice its value.)
#[test]
fn step_sequence_stays_calm_with_hydrostatic_walls() {
    step_sequence(FluidParams {
        hydrostatic_walls: true,
        ..Default::default()
    });
}

/// The same under the second solver (PCISPH): its loop starts from zero pressure every
/// substep and its correction is positional, so a 1 µs step has nothing to release.
#[test]
fn step_sequence_stays_calm_under_pcisph() {
    step_sequence(FluidParams {
        solver: Solver::Pcisph,
        ..Default::default()
    });
}

fn step_sequence(params: FluidParams) {
    let mut sc = scenes::dam_break(0.15, 0.015, 3, params).unwrap();
    let n = sc.world.fluid().len();
    let g = sc.gravity;
    for _ in 0..60 {
        sc.world.step(g, 0.005).unwrap();
    }
    assert_eq!(sc.world.fluid().len(), n, "carriers lost in the 5 ms steps");
    let vmax = sc.world.last_report().max_speed;
    let mut ke = kinetic(&sc.world);
    let seq: Vec<f32> = [1e-6f32, 1e-9].into_iter().chain([0.005; 20]).collect();
    for (k, &dt) in seq.iter().enumerate() {
        let r = sc.world.step(g, dt).unwrap();
        let e = kinetic(&sc.world);
        println!(
            "step {k} dt {dt:e}: max speed {:.3} (before {vmax:.3}), KE {e:.5} J (was {ke:.5})",
            r.max_speed
        );
        assert_eq!(r.removed_outside, 0, "step {k} (dt {dt}): carriers removed");
        assert!(
            r.max_speed <= 2.0 * vmax,
            "step {k} (dt {dt}): speed {} vs {vmax}",
            r.max_speed
        );
        // the water is still falling: 5 ms of free fall at the largest speed adds
        // g·v·Δt per unit mass at most, far below 10 % here
        assert!(e <= 1.1 * ke, "step {k} (dt {dt}): KE {e} after {ke}");
        ke = e;
    }
    assert_eq!(sc.world.fluid().len(), n);
}

/// No silent eruption, and no substeps beyond what the limits ask: the still tank stepped at
/// rapier's 1/60 s for 3 s keeps its kinetic energy below 0.1 J (0.15 % of its potential
/// energy above the floor) after the first 0.3 s, loses no carrier, and after the first 0.5 s
/// takes on average fewer than 3.5 substeps a frame, where the body-force limit asks for three
/// (5.6 ms). The density iterations of a 5.6 ms substep used to diverge — the memory's
/// hydrostatic pressure acting on the carriers' disorder as a spring the loop's prediction
/// overshot (`step/he2012.rs`, `position_relaxation`) — so the step controller held four
/// substeps, retried three every twelfth frame and split those frames to five to seven (4.2
/// substeps a frame on average); before a substep that diverged re-split the rest of its
/// frame, the three substeps of one frame took the energy to 3.1 J and one carrier to 43 %.
#[test]
fn still_tank_at_rapier_60hz_never_erupts() {
    let mut sc = scenes::hydrostatic(0.4, 0.3, DX, Default::default()).unwrap();
    let n = sc.world.fluid().len();
    let dt = 1.0f32 / 60.0;
    let (mut worst, mut at, mut max_c) = (0.0f64, 0.0f64, 0.0f64);
    let (mut substeps, mut frames) = (0u32, 0u32);
    for k in 0..(3.0 / dt).round() as usize {
        let r = sc.world.step(sc.gravity, dt).unwrap();
        if (k + 1) as f32 * dt > 0.3 {
            let ke = kinetic(&sc.world);
            if ke > worst {
                (worst, at) = (ke, r.time);
            }
            max_c = max_c.max(r.compression_max);
        }
        if (k + 1) as f32 * dt > 0.5 {
            substeps += r.substeps;
            frames += 1;
        }
    }
    let per_frame = substeps as f32 / frames as f32;
    println!(
        "largest kinetic energy {worst:.3e} J at {at:.3} s, largest compression {:.2} %, {per_frame:.2} substeps a frame",
        100.0 * max_c
    );
    assert_eq!(sc.world.fluid().len(), n);
    assert!(worst < 0.1, "kinetic energy {worst} J at {at} s");
    assert!(per_frame < 3.5, "{per_frame} substeps a frame");
}

/// A blob of water packed at 0.95 spacings (17 % over rest density), in zero gravity and no
/// solids, placed with velocity `v0` (a stream, which the placement pass leaves alone, or at
/// rest), after one 1 ms step with `drift_iterations`: its largest speed, its momentum gained,
/// the inner carriers' compression and its kinetic energy.
fn packed_blob(drift_iterations: u32, v0: Vector) -> (f32, Vector, f64, f64) {
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        drift_iterations,
        // the step without the correction is an eruption the energy guard would stop
        on_failure: staggered_fluid::OnFailure::Warn,
        ..Default::default()
    })
    .unwrap();
    let mut pts = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            for k in 0..8 {
                pts.push(Vector::new(i as f32, j as f32, k as f32) * (0.95 * DX));
            }
        }
    }
    w.add_particles(&pts, v0).unwrap();
    let r = w.step(Vector::ZERO, 0.001).unwrap();
    let m = w.particle_mass();
    let p = w
        .fluid()
        .v
        .iter()
        .fold(Vector::ZERO, |a, v| a + (*v - v0) * m);
    (r.max_speed, p, r.compression_mean, kinetic(&w))
}

/// `FluidParams::drift_iterations`: compression a blob already holds is moved out of the
/// positions, not turned into velocity. Without the correction a 1 ms step turns the packing
/// into speeds at the density loop's cap (a quarter spacing a substep, 5 m/s) and 11 J of
/// kinetic energy; with three iterations the carriers are shifted apart first and the
/// velocity loop meets only what the shift left (measured 0.85 m/s, 0.4 J): at most a quarter
/// of the speed and a tenth of the energy, no more compression left, and the momentum zero
/// to round-off either way (the shift moves no momentum). The blob moves at 0.1 mm/s, so the
/// pass that relieves water placed at rest (below) stays out of it. The same blob placed at
/// rest gets that pass by default (measured 0.96 m/s): the same bounds.
#[test]
fn drift_correction_moves_stored_compression_out_of_the_positions() {
    let v0 = Vector::new(1e-4, 0.0, 0.0);
    let (kick, p0, c0, e0) = packed_blob(0, v0);
    let (calm, p1, c1, e1) = packed_blob(3, v0);
    let (placed, p2, c2, e2) = packed_blob(0, Vector::ZERO);
    println!(
        "largest speed {kick:.3} → {calm:.3} m/s (placed at rest {placed:.3}), kinetic energy {e0:.3} → {e1:.3} J ({e2:.3}), compression {:.2} → {:.2} % ({:.2}), momentum {p0} / {p1} / {p2}",
        100.0 * c0,
        100.0 * c1,
        100.0 * c2
    );
    for (speed, e, c) in [(calm, e1, c1), (placed, e2, c2)] {
        assert!(speed < 0.25 * kick, "{speed} vs {kick} m/s");
        assert!(e < 0.1 * e0, "{e} vs {e0} J");
        assert!(c <= c0 + 1e-4, "{c} vs {c0}");
    }
    for p in [p0, p1, p2] {
        assert!(p.length() < 1e-4, "momentum {p}");
    }
}

/// Water placed around a solid 0.18 m under water (`add_block_around`, Δx 2.5 cm) starts with
/// the placement's compression beside the solid's faces. A world whose first steps are 1 µs
/// long must not turn that old compression into a jet: in 1 µs gravity adds 1e-5 m/s, so the
/// largest speed after three of them stays under 1 cm/s, below the f32 floor of a position
/// over the step (ulp(0.2 m)/1 µs = 1.5 cm/s, where 30 such steps level off). The first
/// reached 2.98 m/s: with no earlier substeps the loop's stiffness was the 1 µs step's own,
/// and the placement's compression came out within it. Then 1/60 s frames go on
/// as from a first 1/60 s frame: over 0.25 s the largest speed at most twice that run's (the
/// step-sequence test's bound), no carrier removed.
#[test]
fn first_steps_of_a_microsecond_keep_water_placed_around_a_body_at_rest() {
    use rapier3d::prelude::*;
    let run = |first: &[f32]| {
        let dx = 0.025f32;
        let mut fluid = FluidWorld::new(FluidParams {
            spacing: dx,
            ..Default::default()
        })
        .unwrap();
        fluid
            .add_open_tank(Vector::ZERO, Vector::new(0.4, 0.8, 0.4), Slip::NoSlip)
            .unwrap();
        let c = Vector::new(0.2, 0.12, 0.2);
        let shape = SharedShape::cuboid(0.05, 0.05, 0.05);
        let mut colliders = ColliderSet::new();
        colliders.insert(ColliderBuilder::new(shape.clone()).translation(c));
        fluid
            .add_kinematic_solid("cube", shape, Pose::from_translation(c), Slip::FreeSlip)
            .unwrap();
        fluid
            .add_block_around(
                Vector::ZERO,
                Vector::new(0.4, 0.35, 0.4),
                Vector::ZERO,
                &colliders,
            )
            .unwrap();
        let n = fluid.fluid().len();
        let g = Vector::new(0.0, -G, 0.0);
        let mut short = 0.0f32;
        for &dt in first {
            short = short.max(fluid.step(g, dt).unwrap().max_speed);
        }
        let mut frames = 0.0f32;
        for _ in 0..15 {
            let r = fluid.step(g, 1.0 / 60.0).unwrap();
            assert_eq!(r.removed_outside, 0);
            frames = frames.max(r.max_speed);
        }
        assert_eq!(fluid.fluid().len(), n);
        (short, frames)
    };
    let (_, plain) = run(&[]);
    let (short, after) = run(&[1e-6; 3]);
    println!(
        "after three 1 µs steps {short:.2e} m/s; largest over 0.25 s {after:.3} m/s (without them {plain:.3})"
    );
    assert!(short < 0.01, "1 µs first steps threw water at {short} m/s");
    assert!(
        after <= 2.0 * plain,
        "largest speed over 0.25 s {after} against {plain} without the 1 µs steps"
    );
}

/// Step-size jumps in a rapier world with floating and sinking bodies (the five balls, Δx
/// 2 cm): 30 frames at rapier's 1/60 s (the balls in the water, still splashing), then two
/// steps of 1 µs, a frame, one of 0.1 s (split into substeps by the limits), frames, one of
/// 1/240 s and frames again. Every step returns Ok (no guard fired), no carrier leaves the
/// tank, the water's largest speed never exceeds twice its largest over the ten frames before
/// the jumps (the existing step-sequence test's bound), and over
/// each 1 µs step no ball's speed changes by more than 1 cm/s (gravity and buoyancy change it
/// by ~1e-5 m/s there).
#[test]
fn step_jumps_with_floating_bodies_stay_calm() {
    let mut sc = scenes::five_balls(0.02, Default::default()).unwrap();
    let n = sc.world.fluid().len();
    let frame = 1.0f32 / 60.0;
    let speeds = |sc: &scenes::Scene| -> Vec<f32> {
        let ph = sc.physics.as_ref().unwrap();
        sc.tracked
            .iter()
            .map(|(_, h)| ph.bodies[*h].linvel().length())
            .collect()
    };
    let step = |sc: &mut scenes::Scene, dt: f32| {
        let ph = sc.physics.as_mut().unwrap();
        ph.integration_parameters.dt = dt;
        let r = sc.world.step_physics_world(ph).unwrap();
        assert_eq!(r.removed_outside, 0, "dt {dt}: carriers removed");
        r
    };
    // the water's largest speed over the last ten frames before the jumps
    let mut before = 0.0f32;
    for k in 0..30 {
        let v = step(&mut sc, frame).max_speed;
        if k >= 20 {
            before = before.max(v);
        }
    }
    let seq: Vec<f32> = [1e-6, 1e-6, frame, 0.1, frame, frame, 1.0 / 240.0]
        .into_iter()
        .chain([frame; 10])
        .collect();
    for (k, &dt) in seq.iter().enumerate() {
        let v0 = speeds(&sc);
        let r = step(&mut sc, dt);
        let v1 = speeds(&sc);
        println!(
            "step {k} dt {dt:.2e}: {} substeps, water's largest speed {:.3} (before {before:.3}), balls {v1:.3?} m/s",
            r.substeps, r.max_speed
        );
        assert!(
            r.max_speed <= 2.0 * before,
            "step {k} (dt {dt}): speed {} vs {before}",
            r.max_speed
        );
        if dt < 1e-5 {
            for (a, b) in v0.iter().zip(&v1) {
                assert!((a - b).abs() <= 0.01, "step {k}: a ball went {a} → {b} m/s");
            }
        }
    }
    assert_eq!(sc.world.fluid().len(), n);
}
