//! Where a still tank is not still: runs the hydrostatic scene and classifies the carriers
//! faster than 2 % of √(gH) by where they sit (bulk, beside one wall, at an edge, surface).
//! `cargo run --release --example stillness -- 2` (`SLIP=free` or `SLIP=layer` for the walls)
use staggered_fluid::scenes;
fn main() {
    let secs: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse().unwrap())
        .unwrap_or(2.0);
    let p = staggered_fluid::FluidParams::default()
        .with_env_overrides("PARAMS")
        .unwrap();
    let (side, height) = (0.4f32, 0.3f32);
    let mut spec = scenes::hydrostatic_spec(side, height, 0.02, p);
    // SLIP=free or SLIP=layer: the tank's walls free-slip or boundary-layer (no slip by default)
    match std::env::var("SLIP").as_deref() {
        Ok("free") => spec.tanks[0].slip = staggered_fluid::Slip::FreeSlip,
        Ok("layer") => spec.tanks[0].slip = staggered_fluid::Slip::BoundaryLayer,
        _ => {}
    }
    let mut sc = spec.build().unwrap();
    if let Ok(dt) = std::env::var("DT") {
        sc.dt = dt.parse().unwrap();
    }
    let limit = 0.02 * (9.81 * height).sqrt();
    let mut prev: Vec<bool> = Vec::new();
    let mut flips = 0usize;
    let mut corrected = 0u64;
    let r = sc
        .run(secs, |s, rep| {
            let f = s.world.fluid();
            let mut now = vec![false; f.id.iter().map(|&i| i as usize + 1).max().unwrap_or(0)];
            for (&id, &sf) in f.id.iter().zip(&f.surface) {
                now[id as usize] = sf;
            }
            if prev.len() == now.len() {
                flips += now.iter().zip(&prev).filter(|(a, b)| a != b).count();
            }
            prev = now;
            corrected += rep.penetrations_corrected;
            if rep.step % 100 == 0 {
                let f = s.world.fluid();
                let h = 0.04;
                let mut classes = [0usize; 4];
                let mut vmax = [0.0f32; 4];
                let mut vy = [0.0f64; 4];
                let mut cnt = [0usize; 4];
                for (x, v) in f.x.iter().zip(&f.v) {
                    let near = |c: f32| c < h || c > side - h;
                    let walls = near(x.x) as usize + near(x.z) as usize;
                    let k = if x.y > height - h { 3 } else { walls.min(2) };
                    if v.length() > limit {
                        classes[k] += 1;
                    }
                    vmax[k] = vmax[k].max(v.length());
                    vy[k] += v.y as f64;
                    cnt[k] += 1;
                }
                let mean: Vec<String> = (0..4)
                    .map(|k| format!("{:.3}", vy[k] / cnt[k].max(1) as f64))
                    .collect();
                println!(
                    "  surface flag flips per step: {:.1}, wall penetrations corrected: {}",
                    flips as f64 / 100.0,
                    corrected
                );
                corrected = 0;
                flips = 0;
                println!(
                    "t={:.2} fast(>{limit:.3}) bulk/wall/edge/top = {:?} vmax {:?} mean v_y {:?}",
                    rep.time, classes, vmax, mean
                );
            }
        })
        .unwrap();
    let f = sc.world.fluid();
    let mut idx: Vec<usize> = (0..f.len()).collect();
    idx.sort_by(|&a, &b| f.v[b].length().partial_cmp(&f.v[a].length()).unwrap());
    for &i in idx.iter().take(8) {
        println!(
            "  x {:?} v {:?} surf {} rho {:.1} n {} pd {:.0} pv {:.0}",
            f.x[i],
            f.v[i],
            f.surface[i],
            f.density[i],
            f.neighbors[i],
            f.p_density[i],
            f.p_velocity[i]
        );
    }
    println!("{}", serde_json::to_string(&r.comparison).unwrap());
}
