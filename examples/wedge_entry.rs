//! Wedge water entry (issue 4): the downward velocity of a wedge dropped into still water, with
//! the von Kármán and Wagner momentum bounds.
//!
//! `cargo run --release --example wedge_entry -- [yettou|zhao|zhao241] [spacing m] [layers]`
//! (`PARAMS` overrides parameters). `yettou` (default) also prints the Yettou et al. 2006
//! measurements and the mean deviation from them over 0–40 ms; `zhao` is He 2012 §7.2's set-up
//! (Zhao et al. 1996, 141 kg as He prints it, 25 ms), `zhao241` the same with the 241 kg much
//! of the literature quotes. No measurement of Zhao's drop is available here.
//! `EVERY=n` prints every n-th frame's velocity; `TRACE=1` each frame's substeps, surface
//! carriers, density iterations, compression, penetrations and E.
use staggered_fluid::{scenes, FluidParams};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map(String::as_str).unwrap_or("yettou");
    let (drop, secs, default_dx) = match case {
        "zhao" => (scenes::ZHAO_1996, 0.025, 0.01),
        "zhao241" => (
            scenes::WedgeDrop {
                mass_per_length: 241.0,
                ..scenes::ZHAO_1996
            },
            0.025,
            0.01,
        ),
        _ => (scenes::YETTOU_2006, 0.04, 0.02),
    };
    let dx: f32 = args
        .get(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(default_dx);
    let layers: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(4);
    let p = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut sc = scenes::wedge(drop, dx, layers, p).unwrap();
    println!(
        "{case}: {:?}; fluid {} solid {} solver {:?}",
        drop,
        sc.world.fluid().len(),
        sc.world.solid_carriers().len(),
        sc.world.params().solver
    );
    let trace = std::env::var("TRACE").is_ok();
    let r = sc
        .run(secs, |s, rep| {
            if trace {
                let ph = s.physics.as_ref().unwrap();
                let v = ph.bodies[s.tracked[0].1].linvel().y;
                println!(
                    "t {:.1} ms v {:.3} sub {} surface {} dens_it {} cmax {:.3} cmean {:.4} pen {} E {:.1e}",
                    1e3 * s.world.time(),
                    -v,
                    rep.substeps,
                    rep.n_surface,
                    rep.density_iterations,
                    rep.compression_max,
                    rep.compression_mean,
                    rep.penetrations_corrected,
                    rep.error
                );
            }
        })
        .unwrap();
    let sim: Vec<(f64, f64)> = r.bodies[0]
        .samples
        .iter()
        .map(|s| (s.t, -s.velocity[1] as f64))
        .collect();
    let exp = if case == "yettou" {
        scenes::yettou_velocity()
    } else {
        Vec::new()
    };
    let vk = scenes::wedge_momentum_model(drop, false, secs + 1e-3, 1e-5);
    let wa = scenes::wedge_momentum_model(drop, true, secs + 1e-3, 1e-5);
    let at = |c: &[(f64, f64)], t: f64| {
        c.iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .map(|s| s.1)
            .unwrap_or(f64::NAN)
    };
    println!("| t ms | simulated v | measured | von Kármán | Wagner |");
    println!("|---|---|---|---|---|");
    let every = std::env::var("EVERY")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or((sim.len() / 10).max(1));
    for &(t, v) in sim.iter().step_by(every) {
        println!(
            "| {:.1} | {:.3} | {:.3} | {:.3} | {:.3} |",
            1e3 * t,
            v,
            at(&exp, t),
            at(&vk, t),
            at(&wa, t)
        );
    }
    if !exp.is_empty() {
        let dev = exp
            .iter()
            .map(|&(t, v)| ((at(&sim, t) - v) / v).abs())
            .sum::<f64>()
            / exp.len() as f64;
        println!(
            "mean |v − v_exp|/v_exp over the measured window: {:.2} %",
            100.0 * dev
        );
    }
    println!(
        "wall {:.1} s ({:.0} s per simulated s, {:.2} µs/particle-step)",
        r.wall_seconds, r.wall_per_simulated_second, r.us_per_particle_step
    );
}
