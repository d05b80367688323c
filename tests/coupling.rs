//! Two-way rapier coupling: the API, Eq. 21, bad input, and bodies in water.
mod support;

use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

const DX: f32 = 0.02;

/// A tank `[0, w] × [0, 2 depth] × [0, d]` with walls of `tank_slip` and water up to `depth`
/// around the colliders already in `physics`, all coupled with `slip`.
fn tank_with(
    params: FluidParams,
    physics: &PhysicsWorld,
    (w, depth, d): (f32, f32, f32),
    tank_slip: Slip,
    slip: Slip,
) -> FluidWorld {
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: DX,
        ..params
    })
    .unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(w, 2.0 * depth, d), tank_slip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, slip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(w, depth, d),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    fluid
}

fn tank(
    physics: &PhysicsWorld,
    w: f32,
    depth: f32,
    d: f32,
    tank_slip: Slip,
    slip: Slip,
) -> FluidWorld {
    tank_with(Default::default(), physics, (w, depth, d), tank_slip, slip)
}

#[test]
fn bad_bodies_are_clear_errors() {
    let mut physics = PhysicsWorld::new();
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: DX,
        ..Default::default()
    })
    .unwrap();
    // a dynamic body without mass
    let b = physics.bodies.insert(RigidBodyBuilder::dynamic());
    let c = physics.colliders.insert_with_parent(
        ColliderBuilder::ball(0.1).density(0.0),
        b,
        &mut physics.bodies,
    );
    let e = fluid
        .couple_collider(&physics.bodies, &physics.colliders, c, Slip::FreeSlip)
        .unwrap_err();
    assert!(
        matches!(e, FluidError::Coupling(ref m) if m.contains("mass")),
        "{e}"
    );
    // a half-space on a moving body (a ground must be fixed)
    let moving = physics.bodies.insert(RigidBodyBuilder::dynamic());
    let g = physics.colliders.insert_with_parent(
        ColliderBuilder::new(rapier3d::parry::shape::SharedShape::halfspace(Vector::Y)),
        moving,
        &mut physics.bodies,
    );
    let e = fluid
        .couple_collider(&physics.bodies, &physics.colliders, g, Slip::FreeSlip)
        .unwrap_err();
    assert!(
        matches!(e, FluidError::UnsupportedShape { ref shape, .. } if shape.contains("HalfSpace")),
        "{e}"
    );
    // a non-finite pose
    let nan = physics.colliders.insert(
        ColliderBuilder::cuboid(0.1, 0.1, 0.1).translation(Vector::new(f32::NAN, 0.0, 0.0)),
    );
    let e = fluid
        .couple_collider(&physics.bodies, &physics.colliders, nan, Slip::FreeSlip)
        .unwrap_err();
    assert!(matches!(e, FluidError::NonFinite { .. }), "{e}");
    // a handle that no longer names a collider
    let gone = physics.colliders.insert(ColliderBuilder::ball(0.1));
    physics.remove_collider(gone);
    let e = fluid
        .couple_collider(&physics.bodies, &physics.colliders, gone, Slip::FreeSlip)
        .unwrap_err();
    assert!(matches!(e, FluidError::Coupling(_)), "{e}");
}

#[test]
fn removed_collider_is_dropped_and_uncouple_works() {
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 0.004;
    let b = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.25, 0.1)));
    let ball = physics.colliders.insert_with_parent(
        ColliderBuilder::ball(0.05).density(500.0),
        b,
        &mut physics.bodies,
    );
    let post = physics
        .colliders
        .insert(ColliderBuilder::cuboid(0.02, 0.1, 0.02).translation(Vector::new(0.05, 0.1, 0.1)));
    let mut fluid = tank(&physics, 0.4, 0.2, 0.2, Slip::FreeSlip, Slip::FreeSlip);
    let n_tank: usize = fluid.solids()[..5].iter().map(|s| s.range.len()).sum();
    let sb = fluid.solid_of(ball).unwrap();
    let sp = fluid.solid_of(post).unwrap();
    assert_eq!(
        fluid.solid(sb).unwrap().kind,
        staggered_fluid::SolidKind::Dynamic
    );
    assert_eq!(
        fluid.solid(sp).unwrap().kind,
        staggered_fluid::SolidKind::Static
    );
    let n_post = fluid.solid(sp).unwrap().range.len();
    fluid.step_physics_world(&mut physics).unwrap();
    // rapier removes the ball: the next step drops it and counts it
    physics.remove_body(b);
    let r = fluid.step_physics_world(&mut physics).unwrap();
    assert_eq!(r.solids_dropped, 1);
    assert!(fluid.solid(sb).unwrap().removed);
    assert!(fluid.rigids().is_empty());
    assert_eq!(fluid.solid_carriers().len(), n_tank + n_post);
    // the post is uncoupled by hand; the tank's carriers stay where they were
    fluid.uncouple(sp).unwrap();
    assert_eq!(fluid.solid_carriers().len(), n_tank);
    fluid.step_physics_world(&mut physics).unwrap();
    assert!(fluid.solids()[..5].iter().all(|s| !s.removed));
}

/// Eq. 21: the impulse handed to rapier is the solid's force and torque over the step (the
/// water's pushes on its carriers, less what the explicit stages passed on to the water
/// beside the body, `world/lumps.rs`), and the fluid's substep changed the body's momentum by
/// exactly that (and gravity). Rapier's step then takes the body to the pose the fluid's
/// substeps reached (it steps with the velocity that reaches it, its weight held), and the
/// body ends with the velocity the fluid left it (no phantom from gravity acting within
/// rapier's substeps, no jump between the fluid's pose and rapier's); the force is off again.
#[test]
fn impulse_to_rapier_is_the_solids_force() {
    let mut physics = PhysicsWorld::new();
    let dt = 0.002;
    physics.integration_parameters.dt = dt;
    // an off-centre, tilted box half in the water: force and torque both non-zero
    let b = physics.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.2, 0.2, 0.1))
            .rotation(Vector::new(0.3, 0.0, 0.2)),
    );
    let c = physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.06, 0.04, 0.05).density(700.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = tank(&physics, 0.4, 0.2, 0.2, Slip::NoSlip, Slip::NoSlip);
    for _ in 0..5 {
        fluid.step_physics_world(&mut physics).unwrap();
    }
    let v0 = physics.bodies[b].linvel();
    let w0 = physics.bodies[b].angvel();
    let x0 = physics.bodies[b].center_of_mass();
    let r = fluid
        .step_with_rapier(physics.gravity, dt, &mut physics.bodies, &physics.colliders)
        .unwrap()
        .clone();
    assert_eq!(
        r.substeps, 1,
        "one substep keeps the carriers where the impulses acted"
    );
    let s = fluid.solid(fluid.solid_of(c).unwrap()).unwrap();
    let rigid = &fluid.rigids()[0];
    let carriers = fluid.solid_carriers();
    let (mut pushed, mut turned) = (Vector::ZERO, Vector::ZERO);
    for i in s.range.clone() {
        let f = carriers.f[i] * dt;
        pushed += f;
        turned += (carriers.x[i] - s.com).cross(f);
    }
    let (fj, ft) = (s.force * dt, s.torque * dt);
    println!(
        "carriers pushed {pushed} N·s, {turned} N·m·s; the body kept {fj}, {ft} (the rest \
         moved the water beside it)"
    );
    let j = [fj.x as f64, fj.y as f64, fj.z as f64];
    let l = [ft.x as f64, ft.y as f64, ft.z as f64];
    let jn = (j[0] * j[0] + j[1] * j[1] + j[2] * j[2]).sqrt();
    let ln = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    assert!(
        jn > 1e-3 && ln > 1e-6,
        "the test needs a real force and torque: {jn} {ln}"
    );
    for k in 0..3 {
        assert!(
            (rigid.impulse[k] - j[k]).abs() <= 1e-5 * jn,
            "J[{k}] {} vs {}",
            rigid.impulse[k],
            j[k]
        );
        assert!(
            (rigid.impulse[3 + k] - l[k]).abs() <= 1e-4 * ln,
            "L[{k}] {} vs {}",
            rigid.impulse[3 + k],
            l[k]
        );
    }
    // the fluid's substep gave the body exactly that impulse, besides gravity
    let m = physics.bodies[b].mass();
    let (fluid_v, fluid_w) = (fluid.rigids()[0].linvel, fluid.rigids()[0].angvel);
    let fluid_x = fluid.rigids()[0].com;
    let taken = (fluid_v - v0 - physics.gravity * dt) * m;
    let jv = Vector::new(j[0] as f32, j[1] as f32, j[2] as f32);
    assert!(
        (taken - jv).length() <= 1e-4 * jv.length().max(1e-3),
        "{taken:?} vs {jv:?}"
    );
    let iw = physics.bodies[b]
        .mass_properties()
        .effective_world_inv_inertia;
    let lw = iw * Vector::new(l[0] as f32, l[1] as f32, l[2] as f32);
    assert!(
        (fluid_w - w0 - lw).length() <= 1e-3 * lw.length().max(1e-3),
        "{:?} vs {lw:?}",
        fluid_w - w0
    );
    // rapier's step takes the body to the pose the fluid's substeps reached and ends with the
    // fluid's end velocity; the force comes off
    physics.step();
    fluid
        .correct_after_rapier(&mut physics.bodies, &physics.colliders)
        .unwrap();
    let (x1, v1, w1) = (
        physics.bodies[b].center_of_mass(),
        physics.bodies[b].linvel(),
        physics.bodies[b].angvel(),
    );
    println!(
        "rapier: moved {:?} with end velocity {v1:?}; the fluid moved {:?} and left {fluid_v:?}",
        x1 - x0,
        fluid_x - x0
    );
    assert!(
        (v1 - fluid_v).length() <= 1e-4 * fluid_v.length().max(1e-2),
        "rapier {v1:?} vs the fluid's {fluid_v:?}"
    );
    assert!(
        (w1 - fluid_w).length() <= 1e-4 * fluid_w.length().max(1e-2),
        "rapier {w1:?} vs the fluid's {fluid_w:?}"
    );
    assert!(
        (x1 - fluid_x).length() <= 1e-6,
        "rapier moved {:?}, the fluid {:?}",
        x1 - x0,
        fluid_x - x0
    );
    assert_eq!(physics.bodies[b].user_force(), Vector::ZERO);
}

/// Six 1/60 s frames of a 300 kg/m³ box of half extents `half`, started spinning at `w0`
/// under water, stepped as `step_with_rapier`, rapier's step, `correct_after_rapier`. Returns
/// (the most substeps a frame, rapier's largest distance and angle from the fluid's end pose,
/// its largest linear and angular velocity difference from the fluid's end velocity plus the
/// kick of `correct_after_rapier`'s own impulse).
fn rapier_against_fluid(half: Vector, w0: Vector) -> (u32, f32, f32, f32, f32) {
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let b = physics.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.2, 0.1, 0.2))
            .angvel(w0),
    );
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(half.x, half.y, half.z).density(300.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = tank(&physics, 0.4, 0.25, 0.4, Slip::FreeSlip, Slip::FreeSlip);
    let mut worst = (0u32, 0.0f32, 0.0f32, 0.0f32, 0.0f32);
    for _ in 0..6 {
        let dt = physics.integration_parameters.dt;
        let rep = fluid
            .step_with_rapier(physics.gravity, dt, &mut physics.bodies, &physics.colliders)
            .unwrap();
        let r = &fluid.rigids()[0];
        let (x, q, v, w, before) = (r.com, r.rotation, r.linvel, r.angvel, r.impulse);
        physics.step();
        fluid
            .correct_after_rapier(&mut physics.bodies, &physics.colliders)
            .unwrap();
        // the last penetration correction's own kick (carriers rapier's pose left in a gap)
        let r = &fluid.rigids()[0];
        let j: [f32; 6] = std::array::from_fn(|k| (r.impulse[k] - before[k]) as f32);
        let (kv, kw) = r.response(Vector::new(j[0], j[1], j[2]), Vector::new(j[3], j[4], j[5]));
        let (v, w) = (v + kv, w + kw);
        let rb = &physics.bodies[b];
        worst = (
            worst.0.max(rep.substeps),
            worst.1.max((rb.center_of_mass() - x).length()),
            worst
                .2
                .max((q.inverse() * rb.rotation()).to_axis_angle().1.abs()),
            worst.3.max((rb.linvel() - v).length()),
            worst.4.max((rb.angvel() - w).length()),
        );
    }
    worst
}

/// Rapier's step ends where the fluid's substeps left a body: a light cube rising and
/// spinning under water at rapier's 1/60 s (several fluid substeps a frame) is, after rapier's
/// step, at the fluid's pose and velocity to round-off. Rapier moving the body by its end
/// velocity instead put it 1.4–2.6 mm and up to 0.4 rad from where the water had seen it.
/// An unequal box spinning about no principal axis is turned a little further by rapier's
/// gyroscopic terms (the substeps keep ω between the water's pushes), within a milliradian a
/// frame, and keeps the change.
#[test]
fn rapier_ends_the_frame_at_the_fluids_pose() {
    let (substeps, dx, dq, dv, dw) =
        rapier_against_fluid(Vector::splat(0.04), Vector::new(0.0, 0.0, 3.0));
    println!(
        "cube: up to {substeps} substeps a frame; rapier's pose off the fluid's by {dx:.2e} m, \
         {dq:.2e} rad; velocities by {dv:.2e} m/s, {dw:.2e} rad/s"
    );
    assert!(substeps > 1, "the test needs several substeps a frame");
    assert!(dx < 1e-5 && dq < 1e-4, "{dx} m, {dq} rad");
    assert!(dv < 1e-4 && dw < 1e-3, "{dv} m/s, {dw} rad/s");
    let (_, dx, dq, dv, dw) =
        rapier_against_fluid(Vector::new(0.06, 0.03, 0.04), Vector::new(2.0, 1.0, 3.0));
    println!(
        "unequal box: pose off by {dx:.2e} m, {dq:.2e} rad; velocities by {dv:.2e} m/s, \
         {dw:.2e} rad/s"
    );
    assert!(dx < 1e-5 && dq < 1e-3, "{dx} m, {dq} rad");
    assert!(dv < 1e-4 && dw > 1e-4, "{dv} m/s, {dw} rad/s");
}

/// A body the water holds up is at rest in rapier too: a 500 kg/m³ cube placed at its
/// Archimedes draft, at rapier's 1/60 s, keeps a mean vertical velocity under a tenth of
/// `0.375 g Δt` over its last 30 frames and moves less than a quarter spacing in them. With the
/// fluid's impulse handed over at once against gravity spread over rapier's four solver
/// substeps, rapier kept such a body sinking at 0.375 g Δt = 6 cm/s while it stood still, and
/// the water had to stop that phantom every frame (mostly through the velocity constraint,
/// which then carried most of a light body's weight across a thinned layer of water).
#[test]
fn floating_body_has_no_phantom_velocity() {
    let dx = 0.025;
    let cube = ColliderBuilder::cuboid(0.05, 0.05, 0.05).density(500.0);
    let support::BodyInTank {
        mut physics,
        mut fluid,
        body,
    } = support::body_in_tank(
        cube,
        Vector::new(0.2, 0.25, 0.2),
        Slip::FreeSlip,
        0.25,
        false,
        dx,
    );
    let dt = physics.integration_parameters.dt;
    let (mut vs, mut ys) = (Vec::new(), Vec::new());
    for k in 0..90 {
        fluid.step_physics_world(&mut physics).unwrap();
        if k >= 60 {
            vs.push(physics.bodies[body].linvel().y);
            ys.push(physics.bodies[body].translation().y);
        }
    }
    let mean_v = vs.iter().sum::<f32>() / vs.len() as f32;
    let range =
        ys.iter().fold(f32::MIN, |a, &y| a.max(y)) - ys.iter().fold(f32::MAX, |a, &y| a.min(y));
    let phantom = 0.375 * 9.81 * dt;
    println!(
        "mean vertical velocity {mean_v:.4} m/s (phantom {phantom:.4}), height range {range:.4} m"
    );
    assert!(
        mean_v.abs() < 0.1 * phantom,
        "rapier keeps the floating body moving at {mean_v} m/s"
    );
    assert!(range < 0.25 * dx, "the body moved over {range} m");
}

/// Three cubes of density 250, 500 and 750 kg/m³, 8 carriers per side, rotations locked
/// (upright cubes of relative density between 0.21 and 0.79 are statically unstable), stepped
/// with rapier's own 1/60 s (fluid substeps) for 1.5 s. Returns per cube the mean draft over
/// the last 0.5 s as a fraction of the side, measured from the water's actual level away from
/// the cubes, Archimedes' ρ_b/ρ_f, and the range of its bottom's height (bobbing).
fn settle_cubes() -> Vec<(f32, f32, f32)> {
    let side = 8.0 * DX;
    let (w, d, depth) = (7.0 * side, 2.0 * side, 13.0 * DX);
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let dens = [250.0f32, 500.0, 750.0];
    let mut cubes = Vec::new();
    for (k, rho) in dens.iter().enumerate() {
        let y0 = depth + 0.5 * side - rho / 1000.0 * side + 0.02 * side;
        let b = physics.bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(side * (1.0 + 2.0 * k as f32), y0, 0.5 * d))
                .locked_axes(LockedAxes::ROTATION_LOCKED),
        );
        physics.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.5 * side, 0.5 * side, 0.5 * side).density(*rho),
            b,
            &mut physics.bodies,
        );
        cubes.push(b);
    }
    let mut fluid = tank(&physics, w, depth, d, Slip::NoSlip, Slip::FreeSlip);
    let n0 = fluid.fluid().len();
    let mut hist: Vec<Vec<(f32, f32)>> = vec![Vec::new(); 3];
    let mut substeps = 0;
    for k in 0..90 {
        let r = fluid.step_physics_world(&mut physics).unwrap();
        substeps = substeps.max(r.substeps);
        if k >= 60 {
            let centres: Vec<Vector> = cubes
                .iter()
                .map(|b| physics.bodies[*b].translation())
                .collect();
            let level = staggered_fluid::metrics::waterline(
                fluid.fluid().x.iter().copied(),
                &centres,
                0.75 * side,
                DX,
            )
            .expect("water away from the cubes");
            for c in 0..3 {
                let bottom = centres[c].y - 0.5 * side;
                hist[c].push(((level - bottom) / side, bottom));
            }
        }
    }
    assert!(
        substeps >= 2,
        "rapier's step should need fluid substeps here"
    );
    assert_eq!(fluid.fluid().len(), n0, "no fluid carrier lost");
    (0..3)
        .map(|c| {
            let mean = hist[c].iter().map(|h| h.0).sum::<f32>() / hist[c].len() as f32;
            let (lo, hi) = hist[c]
                .iter()
                .fold((f32::INFINITY, f32::NEG_INFINITY), |a, h| {
                    (a.0.min(h.1), a.1.max(h.1))
                });
            println!(
                "ρ {}: submerged {mean:.3} side (Archimedes {:.3}), bottom range {:.4} m",
                dens[c],
                dens[c] / 1000.0,
                hi - lo
            );
            (mean, dens[c] / 1000.0, hi - lo)
        })
        .collect()
}

/// With rapier's own 1/60 s the floating cubes settle: ordered by density, each bobbing by
/// less than a quarter spacing, and no carrier lost.
#[test]
fn floating_cubes_settle_with_large_rapier_steps() {
    let cubes = settle_cubes();
    for (k, &(draft, _, range)) in cubes.iter().enumerate() {
        assert!(range <= 0.25 * DX, "cube {k}: bobbing over {range} m");
        assert!(draft > 0.0 && draft < 1.0, "cube {k}: draft {draft} side");
    }
    assert!(cubes[0].0 < cubes[1].0 && cubes[1].0 < cubes[2].0);
}

/// Archimedes: each cube's draft within 5 % of ρ_b/ρ_f × side against the water's actual level.
///
/// Known failure (issue 18's closing note): the cubes float 0.1–0.5Δx high (drafts 5 / 5 / 8 %
/// short at Δx = 2 cm; 13 / 6 / 6 % before the free-surface extrapolation, then 8 / 3 / 5 %
/// while rapier's phantom velocity let the velocity constraint carry part of their weight). Held at Archimedes'
/// draft a cube gets 4–11 % more force than the fluid's pressure over its bottom: its
/// bottom-edge carriers (diagonal normals) turn pressure from the side into lift. Before the density
/// constraint held the density, this test measured the level from the fluid volume, which the
/// water's 1–2 % compression raised by about as much as the cubes float high, and passed. With
/// `wall_support` (edge pushes along the face normals, the flanks' gradient along gravity
/// restored) the cubes sit 6 / 4 / 3.3 % deep instead.
#[test]
#[ignore = "known failure: bodies float 0.25–0.35 spacings high (edge carriers add lift), see the test's doc"]
fn floating_cubes_match_archimedes_against_the_waterline() {
    for (k, (draft, expect, _)) in settle_cubes().into_iter().enumerate() {
        assert!(
            ((draft - expect) / expect).abs() < 0.05,
            "cube {k}: submerged {draft} side vs {expect}"
        );
    }
}

/// He 2012 Fig. 14 as numbers: a ball spinning at 100 rad/s in water keeps most of its spin
/// under free slip (pressure acts along the normal: no torque about the centre) and loses most
/// of it under no slip within one second.
fn spin_left(slip: Slip) -> f32 {
    let r = 3.0 * DX;
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 0.004;
    let c = Vector::new(0.12, 0.12, 0.12);
    let b = physics.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(c)
            .angvel(Vector::new(0.0, 100.0, 0.0))
            .locked_axes(LockedAxes::TRANSLATION_LOCKED),
    );
    physics.colliders.insert_with_parent(
        ColliderBuilder::ball(r).density(1000.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = tank(&physics, 0.24, 0.24, 0.24, Slip::NoSlip, slip);
    for _ in 0..250 {
        fluid.step_physics_world(&mut physics).unwrap();
    }
    physics.bodies[b].angvel().length() / 100.0
}

#[test]
fn spin_survives_free_slip_and_dies_under_no_slip() {
    let free = spin_left(Slip::FreeSlip);
    let stuck = spin_left(Slip::NoSlip);
    let layer = spin_left(Slip::BoundaryLayer);
    println!(
        "spin left after 1 s: free slip {free:.3}, no slip {stuck:.3}, boundary layer {layer:.3}"
    );
    assert!(free > 0.5, "free slip kept {free} of the spin");
    assert!(stuck < 0.5, "no slip kept {stuck} of the spin");
    // water's own boundary layer brakes the ball, by far less than the pinned layer: a ball
    // of radius r spins down over ρ r² / (15 μ) ≈ 20 s in Stokes flow, so it keeps most of
    // its spin in 1 s, and less than under free slip
    assert!(
        layer < free && layer > 0.5,
        "the boundary layer kept {layer} of the spin"
    );
}

/// Momentum: a sealed hollow box (a compound of six overlapping slabs) half full of water,
/// thrown and spun in zero gravity. Every fluid–solid interaction is an equal and opposite pair,
/// so the centre of mass of box + water moves in a straight line at constant speed.
#[test]
fn thrown_sealed_box_keeps_its_centre_of_mass_on_a_line() {
    let (inner, t) = (0.1f32, 0.1f32);
    let o = inner + t;
    let slab = |c: Vector, h: Vector| {
        (
            Pose::from_translation(c),
            rapier3d::parry::shape::SharedShape::cuboid(h.x, h.y, h.z),
        )
    };
    let m = 0.5 * t + inner;
    let parts = vec![
        slab(Vector::new(0.0, -m, 0.0), Vector::new(o, 0.5 * t, o)),
        slab(Vector::new(0.0, m, 0.0), Vector::new(o, 0.5 * t, o)),
        slab(Vector::new(-m, 0.0, 0.0), Vector::new(0.5 * t, o, o)),
        slab(Vector::new(m, 0.0, 0.0), Vector::new(0.5 * t, o, o)),
        slab(Vector::new(0.0, 0.0, -m), Vector::new(o, o, 0.5 * t)),
        slab(Vector::new(0.0, 0.0, m), Vector::new(o, o, 0.5 * t)),
    ];
    let mut physics = PhysicsWorld::new();
    physics.gravity = Vector::ZERO;
    physics.integration_parameters.dt = 0.004;
    let b = physics.bodies.insert(
        RigidBodyBuilder::dynamic()
            .linvel(Vector::new(0.5, 0.2, 0.0))
            .angvel(Vector::new(0.0, 0.0, 2.0)),
    );
    physics.colliders.insert_with_parent(
        ColliderBuilder::compound(parts).density(100.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: DX,
        domain: Some(([-0.6, -0.6, -0.6], [1.2, 0.9, 0.6])),
        ..Default::default()
    })
    .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::NoSlip)
        .unwrap();
    fluid
        .add_block(
            Vector::new(-inner, -inner, -inner),
            Vector::new(inner, 0.0, inner),
            Vector::ZERO,
        )
        .unwrap();
    let mb = physics.bodies[b].mass() as f64;
    let mf = fluid.fluid_mass();
    let total = mb + mf;
    let com = |fluid: &FluidWorld, physics: &PhysicsWorld| -> [f64; 3] {
        let xb = physics.bodies[b].center_of_mass();
        let mp = fluid.particle_mass() as f64;
        let mut s = [xb.x as f64 * mb, xb.y as f64 * mb, xb.z as f64 * mb];
        for x in &fluid.fluid().x {
            for k in 0..3 {
                s[k] += x[k] as f64 * mp;
            }
        }
        s.map(|v| v / total)
    };
    let x0 = com(&fluid, &physics);
    let vb = physics.bodies[b].linvel();
    let v = [vb.x, vb.y, vb.z].map(|c| c as f64 * mb / total);
    let speed = (v[0] * v[0] + v[1] * v[1]).sqrt();
    let mut worst_line = 0.0f64;
    let mut worst_p = 0.0f64;
    for k in 1..=250 {
        fluid.step_physics_world(&mut physics).unwrap();
        let time = k as f64 * 0.004;
        let x = com(&fluid, &physics);
        let off = (0..3)
            .map(|c| (x[c] - x0[c] - v[c] * time).powi(2))
            .sum::<f64>()
            .sqrt();
        // against the distance travelled over the whole second (fluid positions take a
        // constraint impulse one step after the body does: a lag of one step's transfer)
        worst_line = worst_line.max(off / (speed * 1.0));
        let pf = fluid.fluid_momentum();
        let vb = physics.bodies[b].linvel();
        let p: Vec<f64> = (0..3)
            .map(|c| (pf[c] + vb[c] as f64 * mb) / total - v[c])
            .collect();
        worst_p = worst_p.max((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() / speed);
    }
    assert_eq!(fluid.removed_total(), 0, "water stayed in the domain");
    // the box really carried the water along (it started at rest)
    let pf = fluid.fluid_momentum();
    assert!(
        pf[0] > 0.5 * mf * 0.5 * (mb / total),
        "water momentum {pf:?} after 1 s"
    );
    let r = fluid.last_report();
    println!(
        "box {mb:.2} kg + water {mf:.2} kg: centre of mass off its line by ≤ {:.2} % of the \
         distance travelled in 1 s, momentum within {:.2} %, {} penetration corrections in the last step",
        100.0 * worst_line,
        100.0 * worst_p,
        r.penetrations_corrected
    );
    assert!(worst_p <= 0.02, "total momentum drifted by {worst_p}");
    assert!(
        worst_line <= 0.02,
        "centre of mass left its line by {worst_line}"
    );
    // and the water is still inside the box
    let xb = physics.bodies[b].center_of_mass();
    let rot = physics.bodies[b].rotation();
    for x in &fluid.fluid().x {
        let l = rot.inverse() * (*x - xb);
        assert!(
            l.abs().max_element() < inner,
            "water carrier escaped the box: local {l:?}"
        );
    }
}

/// Bodies no fluid is near are left out of the fluid step (their carriers are not searched),
/// and a sleeping body stays asleep until the fluid pushes it harder than rapier's sleep
/// threshold.
#[test]
fn far_bodies_cost_nothing_and_sleepers_wake_only_when_pushed() {
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 0.004;
    // a cube resting far from the water, and one held deep under water, both asleep
    let far = physics.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(1.5, 0.5, 0.1))
            .gravity_scale(0.0),
    );
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.05, 0.05, 0.05).density(500.0),
        far,
        &mut physics.bodies,
    );
    let deep = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.1, 0.1)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(0.04, 0.04, 0.04).density(300.0),
        deep,
        &mut physics.bodies,
    );
    let mut fluid = tank(&physics, 0.4, 0.24, 0.2, Slip::NoSlip, Slip::FreeSlip);
    let tank_carriers: usize = fluid.solids()[..5].iter().map(|s| s.range.len()).sum();
    let deep_carriers = fluid
        .solid(fluid.solid_of(physics.bodies[deep].colliders()[0]).unwrap())
        .unwrap()
        .range
        .len();
    physics.bodies[far].sleep();
    physics.bodies[deep].sleep();
    let r = fluid.step_physics_world(&mut physics).unwrap();
    // the far cube's carriers are not in the neighbour search
    assert_eq!(r.n_solid, tank_carriers + deep_carriers);
    let far_state = fluid.rigids().iter().find(|r| r.handle == far).unwrap();
    assert!(!far_state.active);
    assert!(
        physics.bodies[far].is_sleeping(),
        "nothing pushed the far cube"
    );
    // buoyancy on the deep light cube is 3.3× its weight: it wakes and rises
    assert!(
        !physics.bodies[deep].is_sleeping(),
        "the water should wake the deep cube"
    );
    for _ in 0..20 {
        fluid.step_physics_world(&mut physics).unwrap();
    }
    assert!(
        physics.bodies[deep].linvel().y > 0.05,
        "{:?}",
        physics.bodies[deep].linvel()
    );
    assert!(physics.bodies[far].is_sleeping());
}

/// A neutrally buoyant ball (1000 kg/m³, radius 3Δx) released at rest under water with a
/// no-slip surface, like a real ball in water, drifts less than one particle spacing per second
/// once the release transient is over (measured from 1 s to 3 s).
///
/// It rises at 0.0196 m/s (b6a09f3; 0.0205, a known failure, before the twenty-eighth
/// session's contacts change), just under the bound: the density constraint's wall push gives
/// a submerged ball of radius 3Δx a little more than ρgV (issue 18; over water's own boundary
/// layer, `Slip::BoundaryLayer`, it rises at 0.043 m/s). `hydrostatic_walls` (below) and
/// `wall_support` (`neutral_ball_stays_put_with_wall_support`) hold it further under.
#[test]
fn neutral_ball_stays_put() {
    neutral_ball_stays_within_a_spacing_a_second(Default::default(), Slip::NoSlip);
}

/// The same ball with [`FluidParams::wall_support`]: the wall push along the ball's normal at
/// each fluid carrier and the flank carriers' gradient along gravity restored, it drifts
/// 0.016 m/s, under the bound (0.0196 without).
#[test]
fn neutral_ball_stays_put_with_wall_support() {
    let params = FluidParams {
        wall_support: true,
        ..Default::default()
    };
    neutral_ball_stays_within_a_spacing_a_second(params, Slip::NoSlip);
}

/// The same ball over water's own boundary layer, which does not hold it, with the
/// hydrostatic wall pressure (`hydrostatic_walls`, Adami et al. 2012): the wall carriers bear
/// their share of the pressure gradient, the ball gets ρgV and stays put. With Eq. 23's
/// mirrored wall pressure it rises at 0.043 m/s (issue 18's excess buoyancy).
#[test]
fn neutral_ball_stays_put_by_buoyancy_alone_with_hydrostatic_walls() {
    let params = FluidParams {
        hydrostatic_walls: true,
        ..Default::default()
    };
    neutral_ball_stays_within_a_spacing_a_second(params, Slip::BoundaryLayer);
}

/// Asserts [`neutral_ball_drift`] under one spacing a second.
fn neutral_ball_stays_within_a_spacing_a_second(params: FluidParams, slip: Slip) {
    let drift = neutral_ball_drift(params, slip);
    println!("neutral ball ({slip:?} surface) drifts {drift:.4} m/s");
    assert!(drift < DX, "neutral ball drifts {drift} m/s");
}

/// Mean speed (m/s) from 1 s to 3 s of a 1000 kg/m³ ball of radius 3Δx released at rest
/// under water in a no-slip tank, its surface of the given slip.
fn neutral_ball_drift(params: FluidParams, slip: Slip) -> f32 {
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 0.004;
    let b = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.14, 0.2)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::ball(3.0 * DX).density(1000.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = tank_with(params, &physics, (0.4, 0.3, 0.4), Slip::NoSlip, slip);
    let mut at = Vec::new();
    for k in 1..=750 {
        fluid.step_physics_world(&mut physics).unwrap();
        if k == 250 || k == 750 {
            at.push(physics.bodies[b].center_of_mass());
        }
    }
    (at[1] - at[0]).length() / 2.0
}

/// A game world's ground is often a half-space or a height field: `couple_all` couples those
/// as grounds (sampled at the first step, within the domain), leaves to rapier what it cannot
/// sample (a segment), says which and why, and couples the rest.
#[test]
fn couple_all_couples_grounds_and_skips_what_it_cannot_sample() {
    let mut physics = PhysicsWorld::new();
    let ground = physics.colliders.insert(ColliderBuilder::new(
        rapier3d::parry::shape::SharedShape::halfspace(Vector::Y),
    ));
    let heights = rapier3d::parry::utils::Array2::new(3, 3, vec![0.0; 9]);
    let field = physics.colliders.insert(ColliderBuilder::heightfield(
        heights,
        Vector::new(1.0, 0.1, 1.0),
    ));
    let rod = physics
        .colliders
        .insert(ColliderBuilder::segment(Vector::ZERO, Vector::X));
    let b = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.2, 0.3, 0.2)));
    let ball = physics.colliders.insert_with_parent(
        ColliderBuilder::ball(0.05).density(500.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: 0.02,
        ..Default::default()
    })
    .unwrap();
    let done = fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    let coupled: Vec<_> = done.coupled.iter().map(|(h, _)| *h).collect();
    assert_eq!(coupled.len(), 3, "{coupled:?}");
    assert!([ground, field, ball].iter().all(|h| coupled.contains(h)));
    assert_eq!(done.skipped.len(), 1);
    assert_eq!(done.skipped[0].0, rod);
    assert!(
        matches!(done.skipped[0].1, FluidError::UnsupportedShape { .. }),
        "{}",
        done.skipped[0].1
    );
    // calling again couples nothing new
    assert_eq!(fluid.solids().len(), 3);
    let again = fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    assert!(again.coupled.is_empty() && again.skipped.len() == 1);
}

/// A static solid keeps world coordinates only: moving its rapier collider moves the carriers
/// rigidly, to where a fresh sampling at the new pose puts them, and an unchanged pose leaves
/// them bit for bit.
#[test]
fn moved_fixed_collider_moves_its_carriers_rigidly() {
    let shape = || ColliderBuilder::cuboid(0.03, 0.1, 0.05);
    let at = Pose::from_translation(Vector::new(0.1, 0.1, 0.1));
    let moved = Pose::from_parts(
        Vector::new(0.3, 0.25, 0.05),
        Rotation::from_scaled_axis(Vector::new(0.1, 0.2, 0.6)),
    );
    let world = |pose: Pose| {
        let mut physics = PhysicsWorld::new();
        let c = physics.colliders.insert(shape().position(pose));
        let mut fluid = FluidWorld::new(FluidParams {
            spacing: DX,
            ..Default::default()
        })
        .unwrap();
        fluid
            .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
            .unwrap();
        (physics, c, fluid)
    };
    let carriers = |fluid: &FluidWorld| -> Vec<(Vector, Vector)> {
        let c = fluid.solid_carriers();
        (0..c.len()).map(|i| (c.x[i], c.n[i])).collect()
    };
    let (mut physics, post, mut fluid) = world(at);
    assert_eq!(fluid.solids()[0].kind, staggered_fluid::SolidKind::Static);
    let before = carriers(&fluid);
    assert!(
        before.len() > 100,
        "a real shell ({} carriers)",
        before.len()
    );
    fluid
        .sync_rapier(&physics.bodies, &physics.colliders)
        .unwrap();
    assert!(
        carriers(&fluid) == before,
        "an unchanged pose moved the carriers"
    );
    physics.colliders.get_mut(post).unwrap().set_position(moved);
    fluid
        .sync_rapier(&physics.bodies, &physics.colliders)
        .unwrap();
    let (_, _, fresh) = world(moved);
    let (now, want) = (carriers(&fluid), carriers(&fresh));
    assert_eq!(now.len(), want.len());
    let mut worst = (0.0f32, 0.0f32);
    for ((x, n), (wx, wn)) in now.iter().zip(&want) {
        worst.0 = worst.0.max((*x - *wx).length());
        worst.1 = worst.1.max((*n - *wn).length());
    }
    // a rigid move of 0.3 m and 0.65 rad: f32 rounding of the two transforms only
    assert!(
        worst.0 < 1e-5 && worst.1 < 1e-5,
        "carriers off by {} m, normals by {}",
        worst.0,
        worst.1
    );
}

/// A program that steps rapier itself (`step_with_rapier`, its own `PhysicsPipeline::step`,
/// `correct_after_rapier`) gets the same physics as `step_physics_world`: body poses and
/// velocities and the fluid bit for bit over 1 s of a floating box and a sinking ball.
#[test]
fn split_step_matches_step_physics_world() {
    let build = || {
        let mut physics = PhysicsWorld::new();
        physics.integration_parameters.dt = 1.0 / 60.0;
        let b = physics
            .bodies
            .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.16, 0.14, 0.12)));
        physics.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.06, 0.03, 0.06).density(500.0),
            b,
            &mut physics.bodies,
        );
        let s = physics
            .bodies
            .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.34, 0.16, 0.12)));
        physics.colliders.insert_with_parent(
            ColliderBuilder::ball(0.04).density(1500.0),
            s,
            &mut physics.bodies,
        );
        let fluid = tank(&physics, 0.48, 0.12, 0.24, Slip::NoSlip, Slip::FreeSlip);
        (physics, fluid, [b, s])
    };
    let (mut pa, mut fa, ha) = build();
    let (mut pb, mut fb, hb) = build();
    let mut corrected = 0;
    for _ in 0..60 {
        let ra = fa.step_physics_world(&mut pa).unwrap();
        // the split path, with rapier's pipeline driven by hand as an engine would
        let g = pb.gravity;
        let dt = pb.integration_parameters.dt;
        fb.step_with_rapier(g, dt, &mut pb.bodies, &pb.colliders)
            .unwrap();
        pb.physics_pipeline.step(
            g,
            &pb.integration_parameters,
            &mut pb.islands,
            &mut pb.broad_phase,
            &mut pb.narrow_phase,
            &mut pb.bodies,
            &mut pb.colliders,
            &mut pb.impulse_joints,
            &mut pb.multibody_joints,
            &mut pb.soft_bodies,
            &mut pb.ccd_solver,
            &(),
            &(),
        );
        corrected += fb
            .correct_after_rapier(&mut pb.bodies, &pb.colliders)
            .unwrap();
        // the reports agree too (a step's report is a value the world can be read beside)
        let rb = fb.last_report().clone();
        assert_eq!(ra.penetrations_corrected, rb.penetrations_corrected);
        assert_eq!(ra.n_fluid, fa.fluid().len());
        for (a, b) in ha.iter().zip(&hb) {
            let (x, y) = (&pa.bodies[*a], &pb.bodies[*b]);
            assert_eq!(x.position(), y.position());
            assert_eq!(x.linvel(), y.linvel());
            assert_eq!(x.angvel(), y.angvel());
        }
    }
    assert_eq!(fa.fluid().x, fb.fluid().x);
    assert_eq!(fa.fluid().v, fb.fluid().v);
    // the box floated and the ball sank: the coupling acted on both
    let (bx, ball) = (&pa.bodies[ha[0]], &pa.bodies[ha[1]]);
    assert!(bx.translation().y > 0.09, "box at {}", bx.translation().y);
    assert!(
        ball.translation().y < 0.1,
        "ball at {}",
        ball.translation().y
    );
    println!("carriers moved out of bodies after rapier's steps: {corrected}");
}

/// Issue 18: a roll-stable floating box (2:1:2, 500 kg/m³, free to turn and drift) in a rapier
/// world stepped at rapier's 1/60 s with default parameters floats at Archimedes' draft within
/// 2 % against the water's actual level, and that level is within Δx/4 of the level an
/// incompressible fluid would have (its rest volume plus the volume the box displaces).
/// Measured with the defaults: 49.16 mm against 50.0, the level 0.4 mm below (with
/// `wall_support: false` 49.91 mm; 50.19 mm on
/// the thirty-second session's defaults, whose lump leaked 10–15 % of a floating body's
/// weight into the water beside it).
#[test]
fn floating_box_matches_archimedes_at_rapier_steps() {
    let (hx, hy, hz) = (0.1f32, 0.05f32, 0.1f32);
    let (w, depth, d) = (0.8f32, 0.2f32, 0.6f32);
    let rho_b = 500.0f32;
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 1.0 / 60.0;
    let draft = 2.0 * hy * rho_b / 1000.0;
    let b = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(
            0.5 * w,
            depth + hy - draft + 0.1 * DX,
            0.5 * d,
        )));
    physics.colliders.insert_with_parent(
        ColliderBuilder::cuboid(hx, hy, hz).density(rho_b),
        b,
        &mut physics.bodies,
    );
    let mut fluid = tank(&physics, w, depth, d, Slip::NoSlip, Slip::FreeSlip);
    let n0 = fluid.fluid().len();
    let mass = physics.bodies[b].mass();
    let incompressible = (n0 as f32 * DX.powi(3) + mass / 1000.0) / (w * d);
    let (mut drafts, mut levels, mut tilt) = (Vec::new(), Vec::new(), 0.0f32);
    for k in 0..120 {
        fluid.step_physics_world(&mut physics).unwrap();
        if k >= 60 {
            let body = &physics.bodies[b];
            let c = body.translation();
            let up = body.rotation() * Vector::Y;
            tilt = tilt.max(up.angle_between(Vector::Y));
            let level =
                staggered_fluid::metrics::waterline(fluid.fluid().x.iter().copied(), &[c], 0.2, DX)
                    .expect("water away from the box");
            drafts.push(level - (c.y - hy));
            levels.push(level);
        }
    }
    assert_eq!(fluid.fluid().len(), n0, "no fluid carrier lost");
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
    let (dr, level) = (mean(&drafts), mean(&levels));
    println!(
        "box draft {:.2} mm (Archimedes {:.2}), level {:.2} mm (incompressible {:.2}), tilt {:.3} rad",
        1e3 * dr,
        1e3 * draft,
        1e3 * level,
        1e3 * incompressible,
        tilt
    );
    assert!(tilt < 0.05, "the box should stay flat: tilted {tilt} rad");
    assert!(
        ((dr - draft) / draft).abs() < 0.02,
        "draft {dr} m vs Archimedes {draft} m"
    );
    assert!(
        (level - incompressible).abs() < 0.25 * DX,
        "level {level} m vs incompressible {incompressible} m"
    );
}

/// The travel limit of a rigid body (an eighth of a spacing a substep, `step::SOLID_SHIFT`)
/// counts only while it can reach the water within the step: a ball thrown down at 6 m/s
/// from 1 m above a pool takes the substeps the CFL limit gives its speed (0.4Δx a substep)
/// while far away, and at least its speed over an eighth of a spacing once it can arrive.
#[test]
fn a_fast_body_costs_substeps_only_where_it_can_reach_the_water() {
    let mut physics = PhysicsWorld::new();
    let dt = 1.0 / 60.0;
    physics.integration_parameters.dt = dt;
    let b = physics.bodies.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.2, 1.2, 0.2))
            .linvel(Vector::new(0.0, -6.0, 0.0)),
    );
    physics.colliders.insert_with_parent(
        ColliderBuilder::ball(0.05).density(2000.0),
        b,
        &mut physics.bodies,
    );
    let mut fluid = tank(&physics, 0.4, 0.2, 0.4, Slip::FreeSlip, Slip::FreeSlip);
    let top = fluid
        .fluid()
        .x
        .iter()
        .map(|p| p.y)
        .fold(f32::NEG_INFINITY, f32::max);
    let h = fluid.params().support_radius();
    let (mut far, mut near) = (None, None);
    for _ in 0..20 {
        let rb = &physics.bodies[b];
        let (v, gap) = (rb.linvel().length(), rb.translation().y - 0.05 - top);
        let rep = fluid.step_physics_world(&mut physics).unwrap();
        let travel = (v * dt / (0.125 * DX)).ceil() as u32;
        if gap > v * dt + 2.0 * h && far.is_none() {
            far = Some((rep.substeps, travel));
        }
        if gap <= v * dt {
            near = Some((rep.substeps, travel));
            break;
        }
    }
    let (far, near) = (far.unwrap(), near.unwrap());
    println!(
        "far: {} substeps (travel limit {}); near: {} (travel limit {})",
        far.0, far.1, near.0, near.1
    );
    assert!(far.0 * 2 < far.1, "far from the water: {far:?}");
    assert!(near.0 >= near.1, "about to hit the water: {near:?}");
}
