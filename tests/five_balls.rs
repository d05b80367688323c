//! He 2012 Fig. 15: five balls of density 550…1450 kg/m³ dropped into a tank (rapier coupling).
use rapier3d::prelude::CoefficientCombineRule;
use staggered_fluid::metrics::{hydrostatic_fit, sphere_draft, waterline};
use staggered_fluid::scenes;
use staggered_fluid::FluidParams;

/// Runs the five balls for 2 s with `params`; returns the scene, its run and the two floating
/// balls' drafts below the far-field waterline, averaged over the last 0.3 s.
fn five_balls_run(params: FluidParams) -> (scenes::Scene, scenes::RunReport, [f64; 2]) {
    let mut sc = scenes::five_balls(0.02, params).unwrap();
    let handles: Vec<_> = sc.tracked.iter().map(|t| t.1).collect();
    let mut drafts = [0.0f64; 2];
    let mut samples = 0usize;
    let r = sc
        .run(2.0, |s, _| {
            if s.world.time() < 1.7 {
                return;
            }
            let ph = s.physics.as_ref().unwrap();
            let c: Vec<_> = handles
                .iter()
                .map(|h| ph.bodies[*h].translation())
                .collect();
            let level = waterline(s.world.fluid().x.iter().copied(), &c, 0.12, 0.02).unwrap();
            for k in 0..2 {
                drafts[k] += (level - (c[k].y - 0.06)) as f64;
            }
            samples += 1;
        })
        .unwrap();
    (sc, r, drafts.map(|d| d / samples as f64))
}

/// Issue 18's target: the two floating balls' drafts within 3 % of Archimedes'.
fn drafts_within_three_percent(drafts: [f64; 2]) {
    for (k, rho) in [550.0f64, 775.0].into_iter().enumerate() {
        let h = sphere_draft(0.06, rho / 1000.0);
        println!(
            "ball {rho}: draft {:.1} mm, Archimedes {:.1} mm",
            1e3 * drafts[k],
            1e3 * h
        );
        assert!(
            ((drafts[k] - h) / h).abs() < 0.03,
            "ball {rho}: draft {} m vs Archimedes {h} m",
            drafts[k]
        );
    }
}

#[test]
fn five_balls_float_sink_and_never_hold_water() {
    let (sc, r, drafts) = five_balls_run(Default::default());
    // no fluid carrier inside any ball at the end of any step
    let worst = r.metric.iter().map(|m| m.value).fold(0.0, f64::max);
    assert_eq!(worst, 0.0, "fluid carriers found inside a ball");
    assert_eq!(r.removed_outside, 0);
    let ph = sc.physics.as_ref().unwrap();
    let (dx, radius, g) = (0.02f32, 0.06f32, scenes::G);
    let track = |name: &str| r.bodies.iter().find(|b| b.name == name).unwrap();
    let tail = |name: &str, seconds: f64| {
        let s = &track(name).samples;
        let t_end = s.last().unwrap().t;
        s.iter()
            .filter(move |x| x.t >= t_end - seconds - 1e-9)
            .cloned()
            .collect::<Vec<_>>()
    };
    // floating balls: at rest the fluid carries their whole weight (Archimedes in force form)
    for (name, rho) in [("ball 550", 550.0f32), ("ball 775", 775.0)] {
        let t = tail(name, 0.3);
        let fy = t.iter().map(|s| s.fluid_force[1]).sum::<f32>() / t.len() as f32;
        let w = rho * 4.0 / 3.0 * std::f32::consts::PI * radius.powi(3) * g;
        println!("{name}: fluid force {fy:.3} N, weight {w:.3} N");
        assert!(
            (fy / w - 1.0).abs() < 0.05,
            "{name}: {fy} N vs weight {w} N"
        );
    }
    // Archimedes in depth form (issue 18's target): the submerged cap π h² (3R − h)/3 holds
    // the ball's volume times ρ_b/ρ, the draft against the far-field waterline within 3 % of
    // h (6.2 / 6.7 % short with `wall_support: false`: the water beside their flanks leaned on
    // the water under them; 4.5 / 4.0 % before the balls' weight was shared with their lumps,
    // whose leak hid part of it)
    drafts_within_three_percent(drafts);
    // the heavy ball sinks and rests on the floor through rapier contact
    let h = &ph.bodies[sc.tracked[4].1];
    println!(
        "ball 1450 at y {:.4}, speed {:.4}",
        h.center_of_mass().y,
        h.linvel().length()
    );
    assert!((h.center_of_mass().y - radius).abs() < 0.25 * dx);
    assert!(h.linvel().length() < 0.05 * (g * radius).sqrt());
    // the neutral ball, once its plunge is over (0.5 s), neither sinks nor rises more than a
    // spacing (issue 18; it drifted at 2–3 cm/s before the explicit stages shared its kicks
    // with the water beside it, world/lumps.rs)
    let n = tail("ball 1000", 1.5);
    let (lo, hi) = n
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), s| {
            (a.min(s.position[1]), b.max(s.position[1]))
        });
    println!(
        "ball 1000: height range {:.1} mm over the last 1.5 s",
        1e3 * (hi - lo)
    );
    assert!(hi - lo < dx, "ball 1000 moved {} m", hi - lo);
}

/// He 2012 Fig. 14 as numbers during the descent: a stone spinning at 30 rad/s about its long
/// axis, dropped into water, keeps more of its spin under free slip than under no slip.
#[test]
fn stone_keeps_more_spin_under_free_slip() {
    let spin_after = |slip| {
        let mut sc = scenes::stone(0.02, 30.0, slip, Default::default()).unwrap();
        sc.run(0.15, |_, _| {}).unwrap();
        let ph = sc.physics.as_ref().unwrap();
        ph.bodies[sc.tracked[0].1].angvel().x
    };
    let (free, stuck) = (
        spin_after(staggered_fluid::Slip::FreeSlip),
        spin_after(staggered_fluid::Slip::NoSlip),
    );
    println!("spin after 0.15 s: free slip {free:.1} rad/s, no slip {stuck:.1} rad/s");
    assert!(free > 1.5 * stuck && stuck > 0.0, "{free} vs {stuck}");
}

/// He 2012 Fig. 1 (right): scripted pillars spinning at ±10 rad/s in a dam break; the water
/// resists each pillar's spin (torque opposite to its angular velocity) once it arrives.
#[test]
fn spinning_pillars_feel_the_water() {
    let mut sc = scenes::pillars(0.02, Default::default()).unwrap();
    let r = sc.run(1.0, |_, _| {}).unwrap();
    assert_eq!(r.removed_outside, 0);
    for b in &r.bodies {
        let tail = &b.samples[b.samples.len() - 20..];
        let resist: f32 = tail
            .iter()
            .map(|s| s.fluid_torque[1] * s.angvel[1].signum())
            .sum::<f32>()
            / tail.len() as f32;
        println!("{}: mean torque along its spin {resist:.4} N m", b.name);
        assert!(resist < 0.0, "{}: torque along its spin {resist}", b.name);
    }
}

/// The far field's pressure gradient over ρ̄g, the pressure's zero level and the waterline
/// (the top carriers plus Δx/2): a least-squares fit over the carriers more than R + 2Δx from
/// every ball, 2Δx above the floor and 2Δx under the waterline.
fn far_field(sc: &scenes::Scene) -> (f64, f64, f32) {
    let (dx, radius) = (0.02f32, 0.06f32);
    let ph = sc.physics.as_ref().unwrap();
    let c: Vec<_> = sc
        .tracked
        .iter()
        .map(|t| ph.bodies[t.1].translation())
        .collect();
    let fl = sc.world.fluid();
    let level = waterline(fl.x.iter().copied(), &c, 2.0 * radius, dx).unwrap();
    let far = |x: staggered_fluid::math::Vector| {
        c.iter()
            .all(|b| ((x.x - b.x).powi(2) + (x.z - b.z).powi(2)).sqrt() > radius + 2.0 * dx)
    };
    let fit = hydrostatic_fit((0..fl.len()).filter_map(|k| {
        let x = fl.x[k];
        (far(x) && x.y > 2.0 * dx && x.y < level - 2.0 * dx)
            .then(|| (x.y as f64, (fl.p_density[k] + fl.p_velocity[k]) as f64))
    }))
    .unwrap();
    (
        fit.gradient / (1000.0 * scenes::G as f64),
        fit.zero_level,
        level,
    )
}

/// Issue 18's five-ball target with [`FluidParams::hydrostatic_walls`] (which also leaves out
/// the wall carriers above the water) and [`FluidParams::surface_rest_density`]: the far field's
/// pressure grows with depth as ρ̄g within 1 % ([`far_field`], averaged over the last 0.3 s as
/// the drafts are: one instant's fit swings by about 1 % with the water's sloshing — 0.9994
/// and 1.0102 at 2 s in two runs whose balls rested differently on the floor; 3.8 % steep by
/// default), and the two floating balls' drafts lie within 3 % of Archimedes'.
#[test]
fn with_hydrostatic_walls_and_a_surface_rest_density_the_balls_sit_at_archimedes() {
    let params = FluidParams {
        hydrostatic_walls: true,
        surface_rest_density: true,
        ..Default::default()
    };
    let mut sc = scenes::five_balls(0.02, params).unwrap();
    let (mut slopes, mut drafts, mut samples) = (0.0f64, [0.0f64; 2], 0usize);
    let r = sc
        .run(2.0, |s, _| {
            if s.world.time() < 1.7 {
                return;
            }
            let (slope, _, level) = far_field(s);
            let ph = s.physics.as_ref().unwrap();
            for (k, d) in drafts.iter_mut().enumerate() {
                *d += (level - (ph.bodies[s.tracked[k].1].translation().y - 0.06)) as f64;
            }
            slopes += slope;
            samples += 1;
        })
        .unwrap();
    assert_eq!(r.removed_outside, 0);
    let (now, zero, level) = far_field(&sc);
    let slope = slopes / samples as f64;
    println!(
        "far field: dp/dy {slope:.4} ρ̄g over the last 0.3 s ({now:.4} at 2 s), p = 0 at \
         {zero:.4} m, top carriers + Δx/2 at {level:.4} m"
    );
    assert!((slope - 1.0).abs() < 0.01, "dp/dy {slope} ρ̄g");
    drafts_within_three_percent(drafts.map(|d| d / samples as f64));
}

/// Issue 18's step-size jump with bodies: after 1 s of the five balls, a 1 µs and a 1 ns
/// rapier step, then three of the scene's 1/240 s. Over the short steps gravity and the water
/// can change a ball's speed by about g·1 µs; re-projecting the velocity moves it by a few
/// per cent at most (each ball's speed, or its rim speed, within 5 % and 1 mm/s); after them
/// no ball moves at more than twice its earlier speed (plus 1 cm/s), no carrier is lost and
/// none is left inside a ball. The hand-off to rapier divides the fluid's displacement by the
/// step: a 1 ns step must not turn the `f32` round-off of a pose into a speed.
#[test]
fn microsecond_and_nanosecond_steps_leave_the_balls_alone() {
    let mut sc = scenes::five_balls(0.02, Default::default()).unwrap();
    sc.run(1.0, |_, _| {}).unwrap();
    let n = sc.world.fluid().len();
    let handles: Vec<_> = sc.tracked.iter().map(|t| t.1).collect();
    let speeds = |sc: &scenes::Scene| -> Vec<f32> {
        let ph = sc.physics.as_ref().unwrap();
        handles
            .iter()
            .map(|h| {
                let b = &ph.bodies[*h];
                b.linvel().length().max(b.angvel().length() * 0.06)
            })
            .collect()
    };
    let before = speeds(&sc);
    for (k, dt) in [1e-6f32, 1e-9, 1.0 / 240.0, 1.0 / 240.0, 1.0 / 240.0]
        .into_iter()
        .enumerate()
    {
        let ph = sc.physics.as_mut().unwrap();
        ph.integration_parameters.dt = dt;
        let rep = sc.world.step_physics_world(ph).unwrap();
        let now = speeds(&sc);
        println!("after {dt:e} s: {now:?} (before {before:?})");
        for (b, (v0, v)) in before.iter().zip(&now).enumerate() {
            let bound = if k < 2 {
                (v - v0).abs() <= 0.05 * v0 + 1e-3
            } else {
                *v <= 2.0 * v0 + 0.01
            };
            assert!(
                bound,
                "ball {b} after the {dt} s step: {v} m/s, before {v0}"
            );
        }
        assert_eq!(sc.world.fluid().len(), n, "carriers lost");
        assert_eq!(rep.removed_outside, 0);
    }
    let ph = sc.physics.as_ref().unwrap();
    let inside = sc
        .world
        .fluid()
        .x
        .iter()
        .filter(|p| {
            handles.iter().any(|h| {
                let b = &ph.bodies[*h];
                (**p - b.translation()).length() < 0.06
            })
        })
        .count();
    assert_eq!(inside, 0, "carriers inside a ball");
}

/// The five balls at rapier's 1/60 s: after the splash (0.5–1 s) the defaults take two
/// substeps a frame, most frames (the body-force limit 0.2 √(Δx/|g|) = 9.0 ms and the loop spring, μ ≤ 4,
/// both allow 8.3 ms; three before the density loop relaxed only its spring, whose whole-force
/// relaxation stalled above the 0.1 % tolerance at that length) with the inner carriers'
/// mean compression within the defaults' 0.1 % on average over those frames; the settings
/// for games (`FluidParams::for_games`, tolerances five times looser) spend fewer density
/// iterations over the first second and stay within their own 0.5 % at every frame after the
/// splash; no carrier is lost.
#[test]
fn rapier_frames_take_two_substeps_and_the_game_settings_fewer_iterations() {
    let run = |params: FluidParams| {
        let mut spec = scenes::five_balls_spec(0.02, params);
        spec.dt = 1.0 / 60.0;
        let mut sc = spec.build().unwrap();
        let n = sc.world.fluid().len();
        let (mut worst, mut mean, mut late) = (0.0f64, 0.0f64, Vec::new());
        let mut iterations = 0u32;
        let r = sc
            .run(1.0, |s, rep| {
                iterations += rep.density_iterations;
                if s.world.time() > 0.5 {
                    worst = worst.max(rep.compression_mean);
                    mean += rep.compression_mean;
                    late.push(rep.substeps);
                }
            })
            .unwrap();
        assert_eq!(r.n_fluid, n);
        let frames = late.len().max(1) as f64;
        let late = late.iter().sum::<u32>() as f64 / frames;
        (iterations, late, mean / frames, worst)
    };
    let (default, default_late, default_mean, default_worst) = run(FluidParams::default());
    let (game, game_late, _, worst) = run(FluidParams::default().for_games());
    println!(
        "density iterations in 1 s: {game} for games, {default} by default; substeps a frame \
         after 0.5 s: {game_late:.2} for games, {default_late:.2} by default; mean compression \
         after 0.5 s by default {:.3} % (worst frame {:.3} %), for games at most {:.3} %",
        100.0 * default_mean,
        100.0 * default_worst,
        100.0 * worst
    );
    assert!(
        default_late <= 2.5 && game_late <= 2.5,
        "substeps a frame after the splash: {default_late} by default, {game_late} for games"
    );
    assert!(default_mean <= 0.001, "mean compression {default_mean}");
    assert!(
        game < default,
        "{game} density iterations against {default}"
    );
    assert!(worst <= 0.005, "mean compression {worst}");
}

/// Water pressure on a ball passes through its centre, so a free-slip ball floating against
/// a tank wall in still water has nothing to turn it. Its collider is made frictionless
/// (rapier's friction rolls a ball that bobs while the water presses it on the wall: that
/// spin is rapier's, ω = v_y / R), so only the water can turn it: its surface should not
/// outrun the water's own noise (≈ 3 cm/s rms at rapier's 1/60 s), i.e. |ω| R < 0.03 m/s over
/// 3 s. Here 0.015 rad/s at most; 5.1 rad/s (0.31 m/s) when the sealed faces' push acted at
/// the carriers' face points (an arm about the centre), and 12.7 rad/s in 5 s for the
/// five-balls ball that drifts against the x = 0 wall when it acted along the wall's normal.
#[test]
fn a_floating_ball_against_a_wall_does_not_spin() {
    let (r, draft) = (0.06f32, 0.064f32);
    let mut spec = scenes::five_balls_spec(0.02, FluidParams::default());
    spec.dt = 1.0 / 60.0;
    spec.bodies.truncate(1);
    // against the x = 0 wall (0.5 mm gap), at its floating draft in the 0.3 m deep water
    spec.bodies[0].position = [r + 5e-4, 0.3 + r - draft, 0.15];
    spec.fluid[0].around_bodies = true;
    let mut sc = spec.build().unwrap();
    let h = sc.tracked[0].1;
    let ph = sc.physics.as_mut().unwrap();
    let c = ph.bodies[h].colliders()[0];
    ph.colliders[c].set_friction(0.0);
    ph.colliders[c].set_friction_combine_rule(CoefficientCombineRule::Min);
    let (mut fastest, mut at) = (0.0f32, 0.0f64);
    let r_run = sc
        .run(3.0, |s, _| {
            let w = s.physics.as_ref().unwrap().bodies[h].angvel().length();
            if w > fastest {
                (fastest, at) = (w, s.world.time());
            }
        })
        .unwrap();
    assert_eq!(r_run.removed_outside, 0);
    let x = sc.physics.as_ref().unwrap().bodies[h].translation().x;
    println!("fastest spin {fastest:.2} rad/s at {at:.2} s; the ball's centre at x = {x:.4} m");
    assert!(fastest * r < 0.03, "spin {fastest} rad/s at {at} s");
}
