//! Diagnostic for the five-ball draft error (ARCHITECTURE.md, "Small floating balls sit too
//! high"): runs `scenes::five_balls` for 2 s and measures the two floating balls' drafts
//! against two waterlines, the top fluid carrier + Δx/2 (what `speed_vs_error` uses) and the
//! level where the far-field pressure `p^d + p^v`, fitted linearly in height, reaches zero;
//! then prints the fitted pressure gradient against ρ̄g and the far-field density and
//! pressures by depth. `cargo run --release --example draft_probe`
//! (`PARAMS` overrides parameters, `DT` sets the step, s).
use staggered_fluid::metrics::sphere_draft;
use staggered_fluid::{scenes, FluidParams};

fn main() {
    let (dx, radius) = (0.02f32, 0.06f32);
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut sc = scenes::five_balls(dx, params).unwrap();
    if let Some(dt) = std::env::var("DT").ok().and_then(|v| v.parse().ok()) {
        sc.dt = dt;
        // a coupled scene steps at rapier's step
        if let Some(ph) = sc.physics.as_mut() {
            ph.integration_parameters.dt = dt;
        }
    }
    // drafts against the top carriers + Δx/2, averaged over every step of the last second
    let mut avg = [(0.0f64, 0usize); 2];
    let mut late = [(0.0f64, 0usize); 2];
    let run = sc
        .run(2.0, |s, _| {
            if s.world.time() < 1.0 {
                return;
            }
            let ph = s.physics.as_ref().unwrap();
            let centres: Vec<_> = s
                .tracked
                .iter()
                .map(|t| ph.bodies[t.1].translation())
                .collect();
            if let Some(level) = staggered_fluid::metrics::waterline(
                s.world.fluid().x.iter().copied(),
                &centres,
                2.0 * radius,
                dx,
            ) {
                for k in 0..2 {
                    avg[k].0 += (level - (centres[k].y - radius)) as f64;
                    avg[k].1 += 1;
                    if s.world.time() >= 1.7 {
                        late[k].0 += (level - (centres[k].y - radius)) as f64;
                        late[k].1 += 1;
                    }
                }
            }
        })
        .unwrap();
    println!(
        "step {:.5} s: {:.1} wall s per simulated s, {:.2} substeps a step; compression mean {:.3} %, \
         largest {:.2} %; E mean {:.1e}; {:.1} PCG iterations a step; {} steps beyond the density \
         tolerances of {}",
        run.dt,
        run.wall_per_simulated_second,
        run.steps_log.iter().map(|l| l.substeps as f64).sum::<f64>() / run.steps.max(1) as f64,
        100.0 * run.mean_compression,
        100.0 * run.max_compression,
        run.mean_error,
        run.mean_pcg_iterations,
        run.steps_off_density,
        run.steps
    );
    for (what, mean) in [("mean draft over 1-2 s", avg), ("last 0.3 s", late)] {
        for (k, a) in mean.iter().enumerate() {
            let archimedes = sphere_draft(radius as f64, [0.55, 0.775][k]);
            let d = a.0 / a.1.max(1) as f64;
            println!(
                "ball {k}: {what} {:.1} mm (Archimedes {:.1} mm, {:+.1} %)",
                1e3 * d,
                1e3 * archimedes,
                100.0 * (d / archimedes - 1.0)
            );
        }
    }
    let ph = sc.physics.as_ref().unwrap();
    let fl = sc.world.fluid();
    // waterline far from balls
    let centres: Vec<_> = sc
        .tracked
        .iter()
        .map(|t| ph.bodies[t.1].translation())
        .collect();
    let level =
        staggered_fluid::metrics::waterline(fl.x.iter().copied(), &centres, 2.0 * radius, dx)
            .expect("columns clear of the balls");
    // pressure-zero level: least squares p = a + b y over carriers farther than R + 2dx (horizontally)
    // from every ball and more than 2dx below the level
    let fit = staggered_fluid::metrics::hydrostatic_fit((0..fl.len()).filter_map(|k| {
        let x = fl.x[k];
        (level - x.y > 2.0 * dx
            && centres
                .iter()
                .all(|c| ((x.x - c.x).powi(2) + (x.z - c.z).powi(2)).sqrt() > radius + 2.0 * dx))
        .then(|| (x.y as f64, (fl.p_density[k] + fl.p_velocity[k]) as f64))
    }))
    .expect("far-field carriers");
    let (b, y0, n) = (-fit.gradient, fit.zero_level, fit.samples);
    for (k, t) in sc.tracked.iter().enumerate().take(2) {
        let c = ph.bodies[t.1].translation();
        let archimedes = 1e3 * sphere_draft(radius as f64, [0.55, 0.775][k]);
        println!(
            "{}: draft {:.1} mm below the top carriers + Δx/2, {:.1} mm below the zero-pressure \
             level (Archimedes {archimedes:.1} mm)",
            t.0,
            1e3 * (level - (c.y - radius)),
            1e3 * (y0 as f32 - (c.y - radius)),
        );
    }
    println!(
        "zero-pressure level {y0:.4} m, top carriers + Δx/2 {level:.4} m; far-field dp/dy \
         {:.0} Pa/m against ρ̄g = 9810 ({n} carriers)",
        -b
    );
    let (x0, x1, z0, z1) =
        fl.x.iter()
            .fold((f32::MAX, f32::MIN, f32::MAX, f32::MIN), |a, x| {
                (a.0.min(x.x), a.1.max(x.x), a.2.min(x.z), a.3.max(x.z))
            });
    for band in 0..3 {
        let (lo, hi) = (band as f32 * dx, (band + 1) as f32 * dx);
        let (mut near, mut far, mut rn, mut rf) = (0, 0, 0.0, 0.0);
        for k in 0..fl.len() {
            let x = fl.x[k];
            let depth = level - x.y;
            if depth < lo
                || depth >= hi
                || !centres
                    .iter()
                    .all(|c| ((x.x - c.x).powi(2) + (x.z - c.z).powi(2)).sqrt() > radius + 2.0 * dx)
            {
                continue;
            }
            let w = (x.x - x0).min(x1 - x.x).min(x.z - z0).min(z1 - x.z);
            if w < 1.6 * dx {
                near += 1;
                rn += fl.density[k];
            } else {
                far += 1;
                rf += fl.density[k];
            }
        }
        println!(
            "band {band}: within 2 layers of a wall {near} (ρ {:.0}), further {far} (ρ {:.0})",
            rn / near.max(1) as f32,
            rf / far.max(1) as f32
        );
    }
    // far field pressure at same depths
    println!("far field (> R + 2Δx from every ball) by depth below the top carriers + Δx/2:");
    for band in 0..8 {
        let (lo, hi) = (band as f32 * dx, (band + 1) as f32 * dx);
        let (mut n, mut pd, mut pv, mut hy, mut rho) = (0, 0.0, 0.0, 0.0, 0.0);
        for k in 0..fl.len() {
            let x = fl.x[k];
            let depth = level - x.y;
            if depth >= lo
                && depth < hi
                && centres
                    .iter()
                    .all(|c| ((x.x - c.x).powi(2) + (x.z - c.z).powi(2)).sqrt() > radius + 2.0 * dx)
            {
                n += 1;
                pd += fl.p_density[k];
                pv += fl.p_velocity[k];
                hy += 1000.0 * 9.81 * depth;
                rho += fl.density[k];
            }
        }
        let m = n.max(1) as f32;
        println!(
            "depth {lo:.2}-{hi:.2} m: {n} carriers, ρ {:.1}, p^d {:.0} Pa, p^v {:.0} Pa, ρ̄g·depth {:.0} Pa",
            rho / m,
            pd / m,
            pv / m,
            hy / m
        );
    }
}
