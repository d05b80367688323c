//! The same scenes in salva3d 0.11 (DFSPH, Akinci boundaries; `--features salva`). The tank
//! walls are fixed rapier cuboid colliders sampled with salva's own surface ray sampling at its
//! particle radius Δx/2; the fluid starts on the same lattice as ours. salva substeps itself
//! (its CFL time-step manager) inside each step of the scene's Δt. Dynamic bodies (the balls,
//! the wedge) are rapier bodies coupled through salva's own `ColliderCouplingSet` (it applies
//! the fluid's impulses to them); a rapier `PhysicsWorld` step follows every salva step.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use salva3d::integrations::rapier::{ColliderSampling, FluidsPipeline};
use salva3d::object::interaction_groups::InteractionGroups;
use salva3d::object::{Boundary, Fluid};
use staggered_fluid::math::Vector as V;

type SVec = salva3d::math::Vector<f32>;

struct SalvaScene {
    fluids: FluidsPipeline,
    physics: PhysicsWorld,
    /// Whether rapier has dynamic bodies to move.
    dynamic: bool,
}

/// An open tank `[0, size]` (walls 0.1 m thick outside it) filled with fluid over
/// `[0, fill]`, at spacing `dx`.
fn tank(size: V, fill: V, dx: f32) -> SalvaScene {
    let r = 0.5 * dx;
    let mut fluids = FluidsPipeline::new(r, 2.0);
    let mut physics = PhysicsWorld::new();
    physics.gravity = Vector::new(0.0, -9.81, 0.0);
    let (bodies, colliders) = (&mut physics.bodies, &mut physics.colliders);
    let t = 0.1;
    let boxes = [
        (V::new(-t, -t, -t), V::new(size.x + t, 0.0, size.z + t)),
        (V::new(-t, 0.0, -t), V::new(0.0, size.y, size.z + t)),
        (
            V::new(size.x, 0.0, -t),
            V::new(size.x + t, size.y, size.z + t),
        ),
        (V::new(0.0, 0.0, -t), V::new(size.x, size.y, 0.0)),
        (V::new(0.0, 0.0, size.z), V::new(size.x, size.y, size.z + t)),
    ];
    for (lo, hi) in boxes {
        let half = (hi - lo) * 0.5;
        let body = bodies.insert(RigidBodyBuilder::fixed().translation((lo + hi) * 0.5));
        let shape = SharedShape::cuboid(half.x, half.y, half.z);
        let samples = salva3d::sampling::shape_surface_ray_sample(&*shape, r).unwrap_or_default();
        let co = colliders.insert_with_parent(ColliderBuilder::new(shape), body, bodies);
        let b = fluids
            .liquid_world
            .add_boundary(Boundary::new(Vec::new(), InteractionGroups::default()));
        fluids
            .coupling
            .register_coupling(b, co, ColliderSampling::StaticSampling(samples));
    }
    let n = |e: f32| ((e / dx) + 1e-4).floor() as usize;
    let mut pts = Vec::new();
    for i in 0..n(fill.x) {
        for j in 0..n(fill.y) {
            for k in 0..n(fill.z) {
                pts.push(SVec::new(
                    (i as f32 + 0.5) * dx,
                    (j as f32 + 0.5) * dx,
                    (k as f32 + 0.5) * dx,
                ));
            }
        }
    }
    fluids
        .liquid_world
        .add_fluid(Fluid::new(pts, r, 1000.0, InteractionGroups::default()));
    SalvaScene {
        fluids,
        physics,
        dynamic: false,
    }
}

impl SalvaScene {
    fn step(&mut self, dt: f32) {
        let ph = &mut self.physics;
        self.fluids
            .step(&ph.gravity, dt, &ph.colliders, &mut ph.bodies);
        if self.dynamic {
            ph.integration_parameters.dt = dt;
            ph.step();
        }
    }

    /// Adds a dynamic body with collider `co`, coupled two-way through salva's surface samples
    /// of its shape (in the collider's frame).
    fn add_dynamic(&mut self, body: RigidBodyBuilder, co: ColliderBuilder) -> RigidBodyHandle {
        let r = self.fluids.liquid_world.particle_radius();
        let samples =
            salva3d::sampling::shape_surface_ray_sample(&*co.shape, r).unwrap_or_default();
        let ph = &mut self.physics;
        let b = ph.bodies.insert(body);
        let c = ph.colliders.insert_with_parent(co, b, &mut ph.bodies);
        let boundary = self
            .fluids
            .liquid_world
            .add_boundary(Boundary::new(Vec::new(), InteractionGroups::default()));
        self.fluids.coupling.register_coupling(
            boundary,
            c,
            ColliderSampling::StaticSampling(samples),
        );
        self.dynamic = true;
        b
    }

    fn particles(&self) -> (Vec<SVec>, Vec<SVec>) {
        let mut x = Vec::new();
        let mut v = Vec::new();
        for (_, f) in self.fluids.liquid_world.fluids().iter() {
            x.extend_from_slice(&f.positions);
            v.extend_from_slice(&f.velocities);
        }
        (x, v)
    }
}

/// The surge front as in `scenes::surge_front`: the farthest carrier with at least 4 others
/// within 2Δx, plus Δx/2.
fn front(x: &[SVec], dx: f32) -> f32 {
    let mut order: Vec<usize> = (0..x.len()).collect();
    order.sort_by(|&a, &b| x[b].x.total_cmp(&x[a].x));
    for &i in &order {
        // sorted by decreasing x: every neighbour within 2Δx comes before x_i − 2Δx
        let near = order
            .iter()
            .take_while(|&&j| x[j].x > x[i].x - 2.0 * dx)
            .filter(|&&j| j != i && (x[j] - x[i]).norm() < 2.0 * dx)
            .count();
        if near >= 4 {
            return x[i].x + 0.5 * dx;
        }
    }
    f32::NAN
}

/// Particles outside the box `[0, size]` (through a wall, or thrown out).
fn outside(x: &[SVec], size: V) -> usize {
    x.iter()
        .filter(|p| {
            p.x < 0.0 || p.x > size.x || p.z < 0.0 || p.z > size.z || p.y < 0.0 || p.y > size.y
        })
        .count()
}

/// Dam break as `scenes::dam_break` at `dam_resolution()`: (wall s per simulated s, max front
/// error against Martin & Moyce over T ∈ [1, 3.3], fluid particles, particles outside the
/// tank).
pub fn dam_break(dt: f32) -> (f64, f64, usize, usize, String) {
    let (a, dx, layers) = super::dam_resolution();
    let w = layers as f32 * dx;
    let size = V::new(5.0 * a, 3.0 * a, w);
    let mut sc = tank(size, V::new(a, 2.0 * a, w), dx);
    let n = sc.particles().0.len();
    let scale = (2.0 * 9.81 / a as f64).sqrt();
    let table: Vec<(f64, f64)> = staggered_fluid::scenes::martin_moyce_front()
        .into_iter()
        .filter(|(t, _)| (1.0..=3.3).contains(t))
        .collect();
    let steps = ((3.35 / scale) / dt as f64).round() as usize;
    let start = std::time::Instant::now();
    let mut samples = Vec::new();
    for k in 1..=steps {
        sc.step(dt);
        let t = k as f64 * dt as f64 * scale;
        if table
            .iter()
            .any(|(tt, _)| (tt - t).abs() < 0.5 * dt as f64 * scale + 1e-9)
            || k == steps
        {
            samples.push((t, front(&sc.particles().0, dx) as f64 / a as f64));
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let err = table
        .iter()
        .map(|(t, z)| {
            let s = samples
                .iter()
                .find(|(ts, _)| *ts >= t - 0.5 * dt as f64 * scale - 1e-9)
                .unwrap_or(samples.last().unwrap());
            ((s.1 - z) / z).abs()
        })
        .fold(0.0, f64::max);
    let out = outside(&sc.particles().0, size);
    (
        wall / (steps as f64 * dt as f64),
        err,
        n,
        out,
        String::new(),
    )
}

/// Still tank as `scenes::hydrostatic(0.4, 0.3, 0.02, _)` for 1 s: (wall s per simulated s,
/// largest speed over √(gH), fluid particles, particles that left the tank).
pub fn still_tank(dt: f32) -> (f64, f64, usize, usize, String) {
    let (side, height, dx) = (0.4f32, 0.3f32, 0.02f32);
    let size = V::new(side, height + 0.15, side);
    let mut sc = tank(size, V::new(side, height, side), dx);
    let steps = (1.0 / dt).round() as usize;
    let start = std::time::Instant::now();
    for _ in 0..steps {
        sc.step(dt);
    }
    let wall = start.elapsed().as_secs_f64();
    let (x, v) = sc.particles();
    let vmax = v.iter().map(|v| v.norm()).fold(0.0f32, f32::max) as f64;
    let out = outside(&x, V::new(side, f32::INFINITY, side));
    (
        wall / (steps as f64 * dt as f64),
        vmax / (9.81 * height as f64).sqrt(),
        x.len(),
        out,
        String::new(),
    )
}

/// Five balls as `scenes::five_balls(0.02, _)` (He 2012 Fig. 15: balls of radius 0.06 m and
/// 550…1450 kg/m³ dropped into 0.3 m of water in a 1 × 0.3 m tank), 2 s at rapier step `dt`:
/// (wall s per simulated s, mean draft error of the two floating balls, fluid particles,
/// particles outside the tank, note). Draft and waterline as in the example's `five_balls`.
pub fn five_balls(dt: f32) -> (f64, f64, usize, usize, String) {
    let (dx, radius, w, depth, d) = (0.02f32, 0.06f32, 1.0f32, 0.3f32, 0.3f32);
    let size = V::new(w, 2.0 * depth, d);
    let mut sc = tank(size, V::new(w, depth, d), dx);
    let densities = [550.0f32, 775.0, 1000.0, 1225.0, 1450.0];
    let balls: Vec<RigidBodyHandle> = densities
        .iter()
        .enumerate()
        .map(|(k, &rho)| {
            sc.add_dynamic(
                RigidBodyBuilder::dynamic().translation(Vector::new(
                    0.1 + 0.2 * k as f32,
                    depth + radius + 0.06,
                    0.5 * d,
                )),
                ColliderBuilder::ball(radius).density(rho).friction(0.3),
            )
        })
        .collect();
    let n = sc.particles().0.len();
    let steps = (2.0 / dt).round() as usize;
    let start = std::time::Instant::now();
    let mut drafts = [Vec::new(), Vec::new()];
    for k in 1..=steps {
        sc.step(dt);
        if (k as f32) * dt < 1.7 {
            continue;
        }
        let centres: Vec<[f32; 3]> = balls
            .iter()
            .map(|h| sc.physics.bodies[*h].translation().to_array())
            .collect();
        let (x, _) = sc.particles();
        let d = super::ball_drafts(x.iter().map(|p| [p.x, p.y, p.z]), &centres, radius, dx);
        for b in 0..2 {
            drafts[b].push(d[b]);
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let mut errs = Vec::new();
    let mut notes = Vec::new();
    for b in 0..2 {
        let dm = drafts[b].iter().sum::<f64>() / drafts[b].len().max(1) as f64;
        let h = staggered_fluid::metrics::sphere_draft(radius as f64, densities[b] as f64 / 1000.0);
        errs.push(((dm - h) / h).abs());
        notes.push(format!(
            "ρ {}: draft {:.1} mm vs {:.1} mm",
            densities[b],
            1e3 * dm,
            1e3 * h
        ));
    }
    let out = outside(&sc.particles().0, V::new(w, f32::INFINITY, d));
    (
        wall / (steps as f64 * dt as f64),
        (errs[0] + errs[1]) / 2.0,
        n,
        out,
        notes.join(", "),
    )
}

/// The Yettou et al. 2006 wedge as `scenes::wedge_yettou(0.02, 4, _)` (quasi-2-D slab 4Δx
/// thick; salva's walls have no slip condition to choose), 40 ms at rapier step `dt`:
/// (wall s per simulated s, mean |v − v_exp|/v_exp, fluid particles, particles outside the
/// tank, note). A wedge thrown upward or sped up beyond 2 V0 counts as diverged (NaN).
pub fn wedge(dt: f32) -> (f64, f64, usize, usize, String) {
    let drop = staggered_fluid::scenes::YETTOU_2006;
    let dx = 0.02f32;
    let d = 4.0 * dx;
    let size = V::new(drop.width, drop.depth + drop.rise() + 0.1, d);
    let mut sc = tank(size, V::new(drop.width, drop.depth, d), dx);
    let wedge = sc.add_dynamic(
        RigidBodyBuilder::dynamic()
            .translation(V::new(0.5 * drop.width, drop.depth, 0.0))
            .linvel(V::new(0.0, -drop.speed, 0.0))
            .locked_axes(
                LockedAxes::TRANSLATION_LOCKED_X
                    | LockedAxes::TRANSLATION_LOCKED_Z
                    | LockedAxes::ROTATION_LOCKED,
            ),
        ColliderBuilder::convex_hull(&drop.hull(d))
            .expect("wedge hull")
            .density(drop.mass_per_length * d / drop.volume(d)),
    );
    let n = sc.particles().0.len();
    let steps = (0.04 / dt).round() as usize;
    let start = std::time::Instant::now();
    let mut sim = Vec::new();
    for k in 1..=steps {
        sc.step(dt);
        sim.push((
            k as f64 * dt as f64,
            -sc.physics.bodies[wedge].linvel().y as f64,
        ));
    }
    let wall = start.elapsed().as_secs_f64();
    let v0 = drop.speed as f64;
    let at = |t: f64| {
        sim.iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .map(|s| s.1)
            .unwrap_or(f64::NAN)
    };
    let exp = staggered_fluid::scenes::yettou_velocity();
    let dev = if sim.iter().any(|&(_, v)| !(0.0..=2.0 * v0).contains(&v)) {
        f64::NAN
    } else {
        exp.iter()
            .map(|&(t, v)| ((at(t) - v) / v).abs())
            .sum::<f64>()
            / exp.len() as f64
    };
    let out = outside(&sc.particles().0, V::new(drop.width, f32::INFINITY, d));
    let note = format!("v(40 ms) {:.3} m/s (measured 1.777)", at(0.04));
    (wall / (steps as f64 * dt as f64), dev, n, out, note)
}
