use staggered_fluid::scenes;
use staggered_fluid::math::Vector;
fn main() {
    let secs: f64 = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(0.5);
    let mut sc = scenes::by_name("hydrostatic", None).unwrap();
    sc.run(secs, |_, _| {}).unwrap();
    let w = &sc.world;
    let f = w.fluid();
    let s = w.solid_carriers();
    let k = w.kernel();
    let h = k.support();
    let dx = w.params().spacing;
    // per layer stats
    let mut rows = vec![];
    for i in 0..f.len() {
        let xi = f.x[i];
        let mut m = Vector::ZERO; let mut ws = k.w(0.0); let mut divr = 0.0;
        for (xj, _) in f.x.iter().map(|x| (*x, 0)).chain(s.x.iter().map(|x| (*x, 1))) {
            let d = xj - xi; let r = d.length();
            if r > 0.0 && r < h { let wv = k.w(r); m += d * wv; ws += wv; divr += dx*dx*dx * k.grad_mag(r) * r; }
        }
        rows.push((xi.y, (m.length() / ws) / h, f.density[i] / 1000.0, divr, f.surface[i]));
    }
    rows.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
    for chunk in rows.chunks(400).take(5) {
        let n = chunk.len() as f32;
        let ay: f32 = chunk.iter().map(|r| r.0).sum::<f32>() / n;
        let asy_min = chunk.iter().map(|r| r.1).fold(9.0f32, f32::min);
        let asy_mean = chunk.iter().map(|r| r.1).sum::<f32>() / n;
        let asy_max = chunk.iter().map(|r| r.1).fold(0.0f32, f32::max);
        let rmin = chunk.iter().map(|r| r.2).fold(9.0f32, f32::min);
        let rmax = chunk.iter().map(|r| r.2).fold(0.0f32, f32::max);
        let dmin = chunk.iter().map(|r| r.3).fold(9.0f32, f32::min);
        let dmax = chunk.iter().map(|r| r.3).fold(0.0f32, f32::max);
        let surf = chunk.iter().filter(|r| r.4).count();
        println!("y~{ay:.3} asy[{asy_min:.3} {asy_mean:.3} {asy_max:.3}] rho[{rmin:.3} {rmax:.3}] divr[{dmin:.2} {dmax:.2}] surf {surf}");
    }
}
