//! Hydrostatic tank: the fluid's weight reaches the floor.
use staggered_fluid::prelude::*;
use staggered_fluid::scenes;

/// Issue 2's still tank with the default parameters: E (Eq. 29) of every solve after the first
/// 0.1 s within the 1 % tolerance, with the floor, containment and mass checks of
/// [`still_tank`].
#[test]
fn still_tank_carries_its_weight() {
    let (worst, _) = still_tank(Default::default(), 2.0);
    assert!(worst <= 0.01, "max E {worst}");
}

/// Known failure (ARCHITECTURE.md, "Known problems": the still tank circulates down its
/// vertical edges): the largest carrier speed over the last 0.5 s of 2 s should average under
/// 2 % of √(gH) (0.0343 m/s). It averages 0.0459 m/s and swings between about 0.03 and
/// 0.08 m/s from frame to frame; the single sample at 2.0 s this test used to take was under
/// the bound (0.0338 m/s) by chance.
#[test]
#[ignore = "known failure: the still tank keeps 2–3 % of √(gH) of circulation at its edges"]
fn still_tank_comes_to_rest() {
    let (_, vmax) = still_tank(Default::default(), 2.0);
    let limit = 0.02 * (9.81f32 * 0.3).sqrt();
    assert!(vmax < limit, "largest speed {vmax} m/s ≥ {limit}");
}

/// Water placed at rest starting with its hydrostatic pressure
/// ([`FluidParams::hydrostatic_start`], `step/rest_pressure.rs`): the still tank stepped at
/// rapier's 1/60 s carries its weight from the first frame — the floor force within 10 % of
/// the weight in each of the first three frames — and the density constraint has no
/// compression to chase, so the third frame takes at most four substeps (the body-force
/// limit's three plus one). By default the water starts from zero pressure and first falls
/// onto the floor while the pressure memory builds up: more than 1.3× the weight there in
/// the first frame (1.49×) and many substeps a frame after it.
#[test]
fn water_placed_at_rest_starts_hydrostatic_when_asked() {
    let start = |hydrostatic_start: bool| {
        let params = FluidParams {
            hydrostatic_start,
            ..Default::default()
        };
        let mut sc = scenes::hydrostatic(0.4, 0.3, 0.02, params).unwrap();
        sc.dt = 1.0 / 60.0;
        let mut substeps = Vec::new();
        let r = sc
            .run(3.0 / 60.0, |_, rep| substeps.push(rep.substeps))
            .unwrap();
        let forces: Vec<f64> = r
            .metric
            .iter()
            .filter(|m| m.t > 0.0)
            .map(|m| m.normalized)
            .collect();
        println!("hydrostatic start {hydrostatic_start}: floor force / weight by frame {forces:?}, substeps {substeps:?}");
        assert!(forces.len() >= 3, "{forces:?}");
        assert_eq!(substeps.len(), 3);
        (forces, substeps)
    };
    let (forces, substeps) = start(true);
    for (k, f) in forces.iter().take(3).enumerate() {
        assert!((f - 1.0).abs() < 0.1, "frame {k}: floor force / weight {f}");
    }
    assert!(substeps[2] <= 4, "substeps a frame {substeps:?}");
    let (forces, substeps) = start(false);
    assert!(
        forces[0] > 1.3,
        "from zero pressure: frame 0's floor force / weight {}",
        forces[0]
    );
    assert!(
        substeps[2] > 4,
        "from zero pressure: substeps a frame {substeps:?}"
    );
}

/// The same tank with the hydrostatic wall pressure at its (static, no-slip) walls
/// ([`FluidParams::hydrostatic_walls`], Adami et al. 2012): the wall carriers take their share
/// of the pressure gradient, nothing drives the edge circulation, and the largest speed over
/// the last 0.5 s averages under 2 % of √(gH).
#[test]
fn still_tank_comes_to_rest_with_hydrostatic_walls() {
    let params = FluidParams {
        hydrostatic_walls: true,
        ..Default::default()
    };
    let (worst, vmax) = still_tank(params, 2.0);
    let limit = 0.02 * (9.81f32 * 0.3).sqrt();
    println!("largest speed {vmax:.4} m/s (limit {limit:.4}), worst E {worst:.2e}");
    assert!(worst <= 0.01, "max E {worst}");
    assert!(vmax < limit, "largest speed {vmax} m/s ≥ {limit}");
}

/// Over free-slip walls nothing holds the water beside a wall up but the pressure gradient,
/// of which Eq. 23's mirrored wall carriers give the carriers at a vertical edge only part: the
/// edge columns sink (and the bulk rises) at about 4 cm/s for as long as the run lasts. With
/// the hydrostatic wall pressure the wall carriers supply the missing part: over the last
/// 0.5 s of 2 s the carriers within two spacings of two walls sink by less than a spacing per
/// 2 s on average (0.01 m/s), and the floor carries the weight within 1 %.
#[test]
fn free_slip_tank_edges_do_not_sink_with_hydrostatic_walls() {
    let edge_sinking = |hydrostatic_walls: bool| {
        // the comparison is Eq. 23 as printed: `wall_support` (the default) gives the edge
        // carriers the vertical support too (they sank at 0.005 m/s with it alone)
        let params = FluidParams {
            hydrostatic_walls,
            wall_support: hydrostatic_walls,
            ..Default::default()
        };
        let mut spec = scenes::hydrostatic_spec(0.4, 0.3, 0.02, params);
        spec.tanks[0].slip = Slip::FreeSlip;
        let mut sc = spec.build().unwrap();
        let (mut vy, mut count) = (0.0f64, 0usize);
        let r = sc
            .run(2.0, |s, rep| {
                if rep.time < 1.5 - 1e-9 {
                    return;
                }
                let f = s.world.fluid();
                let near = |c: f32| !(0.04..=0.36).contains(&c);
                for (x, v) in f.x.iter().zip(&f.v) {
                    if near(x.x) && near(x.z) && x.y < 0.26 {
                        vy += v.y as f64;
                        count += 1;
                    }
                }
            })
            .unwrap();
        (vy / count.max(1) as f64, floor_over_weight(&r, 1.8))
    };
    let (with, floor) = edge_sinking(true);
    let (without, _) = edge_sinking(false);
    println!(
        "edge carriers' mean vertical velocity: {with:.4} m/s with the hydrostatic wall \
         pressure, {without:.4} m/s without; floor {floor:.4} W"
    );
    assert!(with.abs() < 0.01, "edges sink at {with} m/s");
    assert!((floor - 1.0).abs() < 0.01, "floor carries {floor} W");
    // the comparison run shows the mechanism the option answers
    assert!(
        without < -0.02,
        "without the option the edges sank at {without} m/s"
    );
}

/// The second solver (Shao et al. 2014: PCISPH, Akinci boundary carriers, velocity–position
/// correction) on the same tank: every PCISPH loop converges to the 1 % mean compression.
#[test]
fn pcisph_tank_carries_its_weight_and_holds_its_density() {
    let (worst, _) = still_tank(
        FluidParams {
            solver: Solver::Pcisph,
            ..Default::default()
        },
        1.0,
    );
    assert!(worst <= 0.01, "mean compression reached {worst}");
}

/// PCISPH at rapier's 1/60 s: the solver splits the frame by its own body-force limit
/// (`PCISPH_BODY_FORCE_LIMIT`). With the shared limit its substeps were 3–6 ms, the water
/// settled at the loop's 1 % tolerance and then the loop diverged: the tank erupted at 0.13 s.
#[test]
fn pcisph_tank_holds_at_rapiers_step() {
    let (worst, _) = still_tank_at(
        FluidParams {
            solver: Solver::Pcisph,
            ..Default::default()
        },
        1.0,
        1.0 / 60.0,
    );
    assert!(worst <= 0.01, "mean compression reached {worst}");
}

/// Runs the 20 × 15 × 20 = 6000-carrier tank (Δx 2 cm, Δt 2 ms) for `secs`; asserts the floor
/// force over the last 0.2 s within 3 % of the weight, no carrier in a wall or outside the
/// tank, and mass conserved. Returns the worst solver error after the first 0.1 s and the
/// largest carrier speed averaged over the steps of the last 0.5 s.
fn still_tank(params: FluidParams, secs: f64) -> (f64, f32) {
    still_tank_at(params, secs, 0.002)
}

/// [`still_tank`] at steps of `dt`.
fn still_tank_at(params: FluidParams, secs: f64, dt: f32) -> (f64, f32) {
    let mut sc = scenes::hydrostatic(0.4, 0.3, 0.02, params).unwrap();
    sc.dt = dt;
    assert!(sc.world.fluid().len() >= 5000);
    let mass0 = sc.world.fluid_mass();
    let (mut worst, mut speeds) = (0.0f64, Vec::new());
    let r = sc
        .run(secs, |_, rep| {
            if rep.time > 0.1 {
                worst = worst.max(rep.error);
            }
            if rep.time >= secs - 0.5 - 1e-9 {
                speeds.push(rep.max_speed);
            }
        })
        .unwrap();
    let mean = floor_over_weight(&r, secs - 0.2);
    println!("floor / weight over the last 0.2 s: {mean:.4}");
    assert!(
        (mean - 1.0).abs() < 0.03,
        "floor force / weight over the last 0.2 s = {mean}"
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
    (
        worst,
        speeds.iter().sum::<f32>() / speeds.len().max(1) as f32,
    )
}

/// The scene metric (floor force over the water's weight) averaged over the samples from
/// `from` seconds on.
fn floor_over_weight(r: &scenes::RunReport, from: f64) -> f64 {
    let tail: Vec<f64> = r
        .metric
        .iter()
        .filter(|m| m.t >= from - 1e-9)
        .map(|m| m.normalized)
        .collect();
    tail.iter().sum::<f64>() / tail.len() as f64
}

#[test]
fn sealed_box_gets_hydrostatic_pressure() {
    // a 0.2 m cube of water sealed by a lid: no free surface anywhere
    let (s, dx) = (0.2f32, 0.02f32);
    let mut w = FluidWorld::new(FluidParams {
        spacing: dx,
        ..Default::default()
    })
    .unwrap();
    let walls = w
        .add_open_tank(Vector::ZERO, Vector::new(s, s, s), Slip::NoSlip)
        .unwrap();
    let t = 2.0 * w.params().support_radius() + dx;
    let lid = w
        .add_static_box(
            "lid",
            Vector::new(-t, s, -t),
            Vector::new(s + t, s + t, s + t),
            Slip::NoSlip,
        )
        .unwrap();
    w.add_block(Vector::ZERO, Vector::new(s, s, s), Vector::ZERO)
        .unwrap();
    let g = 9.81f32;
    let weight = w.fluid_mass() * g as f64;
    let (mut floor, mut top, mut sides, mut steps) = (0.0f64, 0.0f64, 0.0f64, 0);
    for k in 0..250 {
        w.step(Vector::new(0.0, -g, 0.0), 0.002).unwrap();
        if k >= 150 {
            floor -= w.solid(walls[0]).unwrap().force.y as f64;
            top -= w.solid(lid).unwrap().force.y as f64;
            for h in &walls[1..] {
                sides -= w.solid(*h).unwrap().force.y as f64;
            }
            steps += 1;
        }
    }
    let (floor, top, sides) = (
        floor / steps as f64,
        top / steps as f64,
        sides / steps as f64,
    );
    // the container carries the weight (momentum balance at rest): the floor's downward push
    // less the lid's upward push, plus what the side walls' edge carriers (diagonal normals)
    // take. A sealed box's absolute pressure is a convention (the density constraint keeps
    // its lowest remembered pressure at 0), so floor and lid may both carry a uniform part.
    println!("floor {floor} lid {top} sides {sides} weight {weight}");
    assert!(
        ((floor + top + sides) / weight - 1.0).abs() < 0.03,
        "floor {floor} N, lid {top} N, sides {sides} N (downward positive) vs {weight} N"
    );
    // and the uniform part stays bounded: below the hydrostatic pressure at the floor times
    // ten (the memory integrating an unrelievable compression grew it by 9 N a step)
    assert!(
        floor < 10.0 * weight,
        "floor {floor} N against a {weight} N column"
    );
    assert!(top.abs() < 0.1 * weight, "lid {top} N");
    // the total pressure p^d + p^v grows with depth like ρ g (H − y): the region is solved,
    // not left to p = 0 (before pinning, every carrier here was flagged and p^v was 0)
    let f = w.fluid();
    let layer = |y: f32| {
        let v: Vec<f64> =
            f.x.iter()
                .zip(f.p_velocity.iter().zip(&f.p_density))
                .filter(|(x, _)| (x.y - y).abs() < 0.5 * dx)
                .map(|(_, (&pv, &pd))| (pv + pd) as f64)
                .collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    let (bottom, middle) = (layer(0.5 * dx), layer(0.5 * s + 0.5 * dx));
    println!("p bottom {bottom} middle {middle}");
    let expect = 1000.0 * g as f64 * 0.5 * s as f64;
    assert!(
        ((bottom - middle) / expect - 1.0).abs() < 0.15,
        "p bottom {bottom} − middle {middle} vs ρ g H/2 = {expect}"
    );
    // every carrier but the pinned one and the few top-edge carriers beside a pocket under the
    // lid (flagged free surface by the density criterion; 1 without XSPH smoothing, 4 with it)
    // is an unknown of the velocity constraint, and the solve reaches the E tolerance (before
    // pinning the sealed region had no unknown at all)
    let r = w.last_report();
    assert!(
        r.n_unknown + r.n_fluid / 100 >= r.n_fluid,
        "{} of {} solved",
        r.n_unknown,
        r.n_fluid
    );
    assert!(r.converged && r.error <= 0.01, "E {}", r.error);
}

/// `body_force_limit` sets how a long step of water at rest is split: Δt ≤ c √(Δx/|g|) is
/// 6.8 ms at the default c = 0.15 and Δx = 2 cm, so an 8 ms step takes two substeps; at c = 0.6
/// it is one step, and the water still stays in its tank. (The density constraint's own
/// substeps, taken while it misses its tolerance, are kept out of the way here: at 8 ms a
/// step it asks for two.)
#[test]
fn body_force_limit_sets_the_substeps() {
    for (c, want) in [(0.15f32, 2u32), (0.6, 1)] {
        let params = FluidParams {
            body_force_limit: c,
            density_mean_tolerance: 0.5,
            density_max_tolerance: 0.5,
            ..Default::default()
        };
        let mut sc = scenes::hydrostatic(0.2, 0.1, 0.02, params).unwrap();
        let n = sc.world.fluid().len();
        for _ in 0..25 {
            let r = sc.world.step(sc.gravity, 0.008).unwrap();
            assert_eq!(r.substeps, want, "c = {c}");
        }
        assert_eq!(sc.world.fluid().len(), n, "c = {c}: carriers lost");
        assert_eq!(sc.world.removed_total(), 0);
    }
}

/// The density constraint's step controller at a game's 1/60 s: the still tank, placed at
/// rest and so started hydrostatic, takes on average at most 4 substeps a frame over its
/// first second (the body-force limit asks 3 at Δx = 2 cm; the controller adds a few while the
/// block, cut from the cubic lattice, settles into the scheme's own packing: 218 substeps
/// when written, peak 9 a frame at 0.35 s) while the water stays within the mean-density
/// tolerance on average. From zero pressure the start's fall raised the first frames to 26
/// substeps and the first second took 344 (the test's earlier form, at most 5 a frame from 0.3 s,
/// was written for that start).
#[test]
fn density_substeps_stay_near_the_body_force_limit() {
    let mut sc = scenes::hydrostatic(0.4, 0.3, 0.02, Default::default()).unwrap();
    sc.dt = 1.0 / 60.0;
    let tol = sc.world.params().density_mean_tolerance as f64;
    let mut frames = Vec::new();
    sc.run(1.0, |_, rep| {
        frames.push((rep.time, rep.substeps, rep.compression_mean))
    })
    .unwrap();
    let substeps: u32 = frames.iter().map(|f| f.1).sum();
    assert!(
        substeps as usize <= 4 * frames.len(),
        "{substeps} substeps in {} frames",
        frames.len()
    );
    let mean = frames.iter().map(|f| f.2).sum::<f64>() / frames.len() as f64;
    assert!(
        mean <= tol,
        "mean compression {mean} above the tolerance {tol}"
    );
}
