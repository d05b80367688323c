//! Diagnostic: the five balls at rapier's 1/60 s (`DT` overrides), `SECS` seconds (2), printed
//! every `EVERY` seconds (0.25): carriers the penetration correction moved per frame, the
//! water's rms and largest speed, the balls' heights and the floating balls' drafts against
//! Archimedes (far-field waterline). The water that never rests sits beside the floor balls.
//! `FIX=gap` (mm) holds the two floor balls fixed that far over the floor (from the start, or
//! with `FIX_AFTER=1` after 1 s, where they are if `gap` is negative).
//! `WEDGE=1` prints, at the end, the water within 1.5Δx of the floor balls by height.
//! `PARAMS='{..}' DT=0.0041667 cargo run --release --example rest_noise`
use staggered_fluid::metrics::{sphere_draft, waterline};
use staggered_fluid::{scenes, FluidParams};

fn env<T: std::str::FromStr>(k: &str, d: T) -> T {
    std::env::var(k)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

fn main() {
    let p = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut spec = scenes::five_balls_spec(0.02, p);
    spec.dt = env("DT", 1.0 / 60.0);
    // FIX=gap (mm): the two floor balls fixed that far over the floor from the start; with
    // FIX_AFTER they fall as usual and are held after 1 s
    let fix: Option<f32> = std::env::var("FIX").ok().and_then(|v| v.parse().ok());
    let after = std::env::var("FIX_AFTER").is_ok();
    if let (Some(gap), false) = (fix, after) {
        for b in &mut spec.bodies[3..] {
            b.kind = staggered_fluid::scenes::BodyKind::Fixed;
            b.position[1] = 0.06 + 1e-3 * gap;
        }
        spec.fluid[0].around_bodies = true;
    }
    let (secs, every): (f64, f64) = (env("SECS", 2.0), env("EVERY", 0.25));
    let mut sc = spec.build().unwrap();
    let handles: Vec<_> = sc.tracked.iter().map(|t| t.1).collect();
    let arch = [0.55, 0.775].map(|s| sphere_draft(0.06, s));
    let (mut frames, mut corr, mut subs, mut next) = (0u64, 0u64, 0u64, every);
    let (mut rms_sum, mut drafts, mut n_drafts) = (0.0f64, [0.0f64; 2], 0usize);
    let mut rings = [0.0f64; 2];
    let t0 = std::time::Instant::now();
    let mut each = |s: &scenes::Scene, rep: &staggered_fluid::StepReport| {
        frames += 1;
        corr += rep.penetrations_corrected;
        subs += rep.substeps as u64;
        let fl = s.world.fluid();
        let ms = fl.v.iter().map(|v| v.length_squared() as f64).sum::<f64>() / fl.len() as f64;
        rms_sum += ms.sqrt();
        let ph = s.physics.as_ref().unwrap();
        let c: Vec<_> = handles
            .iter()
            .map(|h| ph.bodies[*h].translation())
            .collect();
        if s.world.time() > 1.0 {
            let level = waterline(fl.x.iter().copied(), &c, 0.12, 0.02).unwrap();
            for k in 0..2 {
                drafts[k] += (level - (c[k].y - 0.06)) as f64;
                rings[k] += (ring_level(&fl.x, c[k]) - level) as f64;
            }
            n_drafts += 1;
        }
        if s.world.time() + 1e-9 >= next {
            next += every;
            let heights: Vec<String> = c
                .iter()
                .map(|c| format!("{:.4}(x {:.3} z {:.3})", c.y, c.x, c.z))
                .collect();
            let spins: Vec<String> = handles
                .iter()
                .map(|h| {
                    let w = ph.bodies[*h].angvel();
                    format!("{:.2}({:+.1},{:+.1},{:+.1})", w.length(), w.x, w.y, w.z)
                })
                .collect();
            println!(
                    "t {:.2} corrections/frame {:6.1} substeps/frame {:.2} rms {:.2} cm/s max {:.3} m/s heights {} spins {} rad/s",
                    s.world.time(),
                    corr as f64 / frames as f64,
                    subs as f64 / frames as f64,
                    100.0 * rms_sum / frames as f64,
                    rep.max_speed,
                    heights.join(" "),
                    spins.join(" ")
                );
            (frames, corr, subs, rms_sum) = (0, 0, 0, 0.0);
        }
    };
    let r = match fix.filter(|_| after) {
        Some(gap) => {
            sc.run(1.0, &mut each).unwrap();
            let ph = sc.physics.as_mut().unwrap();
            for h in &handles[3..] {
                let b = &mut ph.bodies[*h];
                let mut t = b.translation();
                if gap >= 0.0 {
                    t.y = 0.06 + 1e-3 * gap;
                }
                b.set_body_type(rapier3d::dynamics::RigidBodyType::Fixed, true);
                b.set_translation(t, true);
            }
            sc.run(secs - 1.0, &mut each).unwrap()
        }
        None => sc.run(secs, &mut each).unwrap(),
    };
    let wall = t0.elapsed().as_secs_f64();
    if std::env::var("WEDGE").is_ok() {
        let ph = sc.physics.as_ref().unwrap();
        let fl = sc.world.fluid();
        for h in &handles[3..] {
            let c = ph.bodies[*h].translation();
            let mut rows = [(0usize, 0usize, 0.0f64); 8];
            for i in 0..fl.len() {
                let d = (fl.x[i] - c).length() - 0.06;
                if !(0.0..=0.03).contains(&d) {
                    continue;
                }
                let k = ((fl.x[i].y / 0.01) as usize).min(7);
                rows[k].0 += 1;
                rows[k].2 += fl.density[i] as f64;
                if fl.density[i] > 1050.0 {
                    rows[k].1 += 1;
                }
            }
            println!("ball at y {:.4}: within 1.5Δx of its surface, by height (1 cm bands): count / over 5 % / mean density", c.y);
            for (k, r) in rows.iter().enumerate() {
                println!(
                    "  {}–{} cm: {} / {} / {:.1}",
                    k,
                    k + 1,
                    r.0,
                    r.1,
                    r.2 / r.0.max(1) as f64
                );
            }
        }
    }
    let d = drafts.map(|d| d / n_drafts.max(1) as f64);
    let ring = rings.map(|d| 1e3 * d / n_drafts.max(1) as f64);
    println!(
        "drafts over t > 1 s: {:+.2} % / {:+.2} % of Archimedes; removed {}; {:.2} wall s per simulated s",
        100.0 * (d[0] - arch[0]) / arch[0],
        100.0 * (d[1] - arch[1]) / arch[1],
        r.removed_outside,
        wall / secs
    );
    let t = &r.stage_seconds;
    println!(
        "stage seconds: neighbours {:.2} p^d {:.2} surface {:.2} staggered {:.2} assembly {:.2} solve {:.2} other {:.2} deformable {:.2}; stages {:.2} of {:.2} wall",
        t.neighbors, t.density, t.surface, t.staggered, t.assembly, t.solve, t.other, t.deformable, t.total(), wall
    );
    println!(
        "water within 1–2.5 spacings of the floating balls' rims over the far field: {:+.2} / {:+.2} mm",
        ring[0], ring[1]
    );
}

/// The water's level (top carrier + Δx/2, median over 2 cm columns) in the ring of columns
/// whose centres are 1–2.5 spacings outside a ball's rim (radius 6 cm).
fn ring_level(x: &[staggered_fluid::math::Vector], c: staggered_fluid::math::Vector) -> f32 {
    let dx = 0.02f32;
    let mut tops = std::collections::HashMap::new();
    for p in x {
        let key = ((p.x / dx).floor() as i64, (p.z / dx).floor() as i64);
        let (cx, cz) = ((key.0 as f32 + 0.5) * dx, (key.1 as f32 + 0.5) * dx);
        let r = (cx - c.x).hypot(cz - c.z);
        if (0.06 + dx..=0.06 + 2.5 * dx).contains(&r) {
            let t = tops.entry(key).or_insert(f32::NEG_INFINITY);
            *t = t.max(p.y);
        }
    }
    let mut ys: Vec<f32> = tops.into_values().collect();
    ys.sort_by(f32::total_cmp);
    ys.get(ys.len() / 2).map_or(f32::NAN, |y| y + 0.5 * dx)
}
