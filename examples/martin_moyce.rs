//! Speed against error on the dam break: the surge front against Martin & Moyce 1952 at two
//! resolutions of the same quasi-3-D slab (a = 0.1 m, 20 mm thick, free-slip sides, no-slip
//! floor). Prints one row per resolution: carriers, wall time, µs per particle-step and the
//! largest |Z − Z_MM|/Z_MM over the tabulated T ∈ [1, 3.3].
//! `cargo run --release --example martin_moyce` (`PARAMS='{"xsph": 0}'` overrides parameters,
//! `RES=0.005:4,0.0025:8` chooses spacing:thickness-in-carriers pairs, `ROWS=1` prints every
//! tabulated T)
use staggered_fluid::scenes;

fn main() {
    let a = 0.1f32;
    let scale = (2.0 * 9.81 / a as f64).sqrt();
    println!(
        "| Δx mm | fluid | steps | wall s | µs/particle-step | front error range | max |error| | mean PCG it |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let params = staggered_fluid::FluidParams::default()
        .with_env_overrides("PARAMS")
        .unwrap();
    let res: Vec<(f32, usize)> = std::env::var("RES")
        .unwrap_or_else(|_| "0.005:4,0.0025:8".into())
        .split(',')
        .map(|p| {
            let (dx, n) = p.split_once(':').expect("RES pairs are spacing:layers");
            (dx.parse().expect("spacing"), n.parse().expect("layers"))
        })
        .collect();
    let rows = std::env::var("ROWS").is_ok();
    for (dx, layers) in res {
        let mut sc = scenes::dam_break(a, dx, layers, params.clone()).unwrap();
        let r = sc.run(3.35 / scale, |_, _| {}).unwrap();
        let errs: Vec<f64> = scenes::martin_moyce_front()
            .into_iter()
            .filter(|(t, _)| (1.0..=3.3).contains(t))
            .map(|(t, z)| {
                let k = r.metric.iter().position(|m| m.t >= t / scale).unwrap();
                (r.metric[k].normalized - z) / z
            })
            .collect();
        if rows {
            println!("{}", r.comparison);
        }
        let lo = errs.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = errs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        println!(
            "| {:.1} | {} | {} | {:.1} | {:.2} | {:+.1} … {:+.1} % | {:.1} % | {:.1} |",
            dx * 1000.0,
            r.n_fluid,
            r.steps,
            r.wall_seconds,
            r.us_per_particle_step,
            100.0 * lo,
            100.0 * hi,
            100.0 * lo.abs().max(hi.abs()),
            r.mean_pcg_iterations
        );
    }
}
