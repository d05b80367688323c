//! Stability probe: a fluid block at rest with zero gravity, in configurations chosen by argv[1].
use staggered_fluid::prelude::*;
fn main() {
    let mode = std::env::args().nth(1).unwrap_or("free".into());
    let mut pj = serde_json::to_value(FluidParams::default()).unwrap();
    if let Ok(o) = std::env::var("PARAMS") {
        let o: serde_json::Value = serde_json::from_str(&o).unwrap();
        for (k, v) in o.as_object().unwrap() { pj[k] = v.clone(); }
    }
    let p: FluidParams = serde_json::from_value(pj).unwrap();
    let mut w = FluidWorld::new(p).unwrap();
    let s = 0.3;
    match mode.as_str() {
        "free" => {}
        "tank" => { w.add_open_tank(Vector::ZERO, Vector::new(s, s, s), Slip::FreeSlip).unwrap(); }
        "floor" => { w.add_static_box("floor", Vector::new(-0.2, -0.1, -0.2), Vector::new(s + 0.2, 0.0, s + 0.2), Slip::FreeSlip).unwrap(); }
        "closed" => {
            w.add_open_tank(Vector::ZERO, Vector::new(s, s, s), Slip::FreeSlip).unwrap();
            w.add_static_box("lid", Vector::new(-0.1, s, -0.1), Vector::new(s + 0.1, s + 0.1, s + 0.1), Slip::FreeSlip).unwrap();
        }
        _ => panic!(),
    }
    let top = if mode == "closed" { s } else { s * 0.75 };
    w.add_block(Vector::ZERO, Vector::new(s, top, s), Vector::ZERO).unwrap();
    let g: f32 = std::env::var("G").ok().map(|v| v.parse().unwrap()).unwrap_or(0.0);
    for k in 0..150 {
        let r = w.step(Vector::new(0.0, -g, 0.0), 0.002).unwrap().clone();
        if k % 15 == 14 || k < 15 {
            let f = w.fluid();
            let (i, _) = f.v.iter().enumerate().fold((0, 0.0f32), |(bk, bv), (k, v)| if v.length() > bv { (k, v.length()) } else { (bk, bv) });
            println!("t={:.3} vmax={:.2e} it={} surf={} E0={:.2e} at {:?} v={:?} pv={} pd={} rho={} n={}", r.time, r.max_speed, r.pcg_iterations, r.n_surface, r.initial_error, f.x[i], f.v[i], f.p_velocity[i], f.p_density[i], f.density[i], f.neighbors[i]);
        }
    }
}
