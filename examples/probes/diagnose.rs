//! Diagnostic run of a built-in scene: prints E, PCG iterations, surface count, max speed
//! and the fastest particle every few steps.
//! `PARAMS='{"remap":"Paper"}' DT=0.001 cargo run --release --example diagnose -- hydrostatic 1`
use staggered_fluid::scenes;
fn main() {
    let name = std::env::args().nth(1).unwrap_or("hydrostatic".into());
    let secs: f64 = std::env::args()
        .nth(2)
        .map(|s| s.parse().unwrap())
        .unwrap_or(1.0);
    let p = staggered_fluid::FluidParams::default()
        .with_env_overrides("PARAMS")
        .unwrap();
    let sp = std::env::var("SPACING").ok().map(|s| s.parse().unwrap());
    let mut sc = scenes::by_name_with(&name, sp, p).unwrap();
    if let Ok(g) = std::env::var("G") {
        sc.gravity = staggered_fluid::prelude::Vector::new(0.0, -g.parse::<f32>().unwrap(), 0.0);
    }
    if let Ok(d) = std::env::var("DT") {
        sc.dt = d.parse().unwrap();
    }
    let every: u64 = std::env::var("EVERY")
        .ok()
        .map(|s| s.parse().unwrap())
        .unwrap_or(((0.05 / sc.dt as f64).round() as u64).max(1));
    let r = sc.run(secs, |s, rep| {
        if rep.step % every == 0 {
            let m = s.sample();
            let f = s.world.fluid();
            let (k, _) = f.v.iter().enumerate().fold((0, 0.0f32), |(bk, bv), (k, v)| if v.length() > bv { (k, v.length()) } else { (bk, bv) });
            let nfast = f.v.iter().filter(|v| v.length() > 0.1).count();
            println!("  fastest at {:?} v={:?} n={} rho={} surf={} pd={} nfast={}", f.x[k], f.v[k], f.neighbors[k], f.density[k], f.surface[k], f.p_density[k], nfast);
            println!("t={:.3} E={:.4} E0={:.4} it={} surf={} n={} vmax={:.3} dev={:.4} metric={:.4} ({:.4})", rep.time, rep.error, rep.initial_error, rep.pcg_iterations, rep.n_surface, rep.n_fluid, rep.max_speed, rep.density_deviation, m.value, m.normalized);
        }
    }).unwrap();
    println!("{}", serde_json::to_string_pretty(&r.comparison).unwrap());
    println!(
        "wall {:.2}s  us/particle-step {:.2} stages {:?}",
        r.wall_seconds, r.us_per_particle_step, r.stage_seconds
    );
}
