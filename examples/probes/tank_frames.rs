//! Diagnostic: the still tank (0.4 × 0.3 m, Δx 2 cm) at rapier's 1/60 s, per frame: substeps, mean and
//! largest compression, the water's centre of mass and kinetic energy per unit mass; `SECS`
//! (1), `PARAMS`. `cargo run --release --example tank_frames`
use staggered_fluid::{scenes, FluidParams};
fn main() {
    let p = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut sc = scenes::hydrostatic(0.4, 0.3, 0.02, p).unwrap();
    sc.dt = 1.0 / 60.0;
    let secs: f64 = std::env::var("SECS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0);
    let mut total = 0;
    sc.run(secs, |s, rep| {
        total += rep.substeps;
        let fl = s.world.fluid();
        let n = fl.len() as f64;
        let com = fl.x.iter().map(|x| x.y as f64).sum::<f64>() / n;
        let ke: f64 =
            fl.v.iter()
                .map(|v| 0.5 * v.length_squared() as f64)
                .sum::<f64>();
        println!(
            "t {:.3} substeps {} mean {:.4} % max {:.2} % com {:.5} ke {:.5}",
            s.world.time(),
            rep.substeps,
            100.0 * rep.compression_mean,
            100.0 * rep.compression_max,
            com,
            ke
        );
    })
    .unwrap();
    println!("total substeps {total}");
}
