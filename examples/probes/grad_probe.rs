//! Diagnostic: the still tank (0.4 × 0.3 m, Δx 2 cm) after 1.5 s at step `DT` (1/60 s): the
//! slopes of p^d, p^v and their sum with height over ρ̄g (least squares over the inner carriers
//! more than 2Δx from the walls and floor and 3Δx below the level, as
//! `tests/incompressibility.rs` fits them), the inner carriers' mean SPH density and their mean
//! kernel moment `M = Σ_j V (x_i − x_j)(x_i − x_j)ᵀ |∇W|/r` (diagonal; the symmetric pressure
//! force takes a linear pressure's gradient times `M`).
//! `DT=0.0041667 PARAMS='{..}' cargo run --release --example grad_probe`
use staggered_fluid::metrics::{hydrostatic_fit, waterline};
use staggered_fluid::{scenes, FluidParams};
fn main() {
    let dx = 0.02f32;
    let dt: f32 = std::env::var("DT")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0 / 60.0);
    let p = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let mut sc = scenes::hydrostatic(0.4, 0.3, dx, p).unwrap();
    let steps = (1.5 / dt).round() as usize;
    for _ in 0..steps {
        sc.world.step(sc.gravity, dt).unwrap();
    }
    let level = waterline(sc.world.fluid().x.iter().copied(), &[], 0.0, dx).unwrap();
    let f = sc.world.fluid();
    let rho_g = 1000.0 * 9.81f64;
    let inner: Vec<usize> = (0..f.len())
        .filter(|&i| {
            let x = f.x[i];
            !f.surface[i]
                && x.x > 2.0 * dx
                && x.x < 0.4 - 2.0 * dx
                && x.z > 2.0 * dx
                && x.z < 0.4 - 2.0 * dx
                && x.y > 2.0 * dx
                && x.y < level - 3.0 * dx
        })
        .collect();
    let fit = |g: &dyn Fn(usize) -> f64| {
        hydrostatic_fit(inner.iter().map(|&i| (f.x[i].y as f64, g(i)))).map(|h| h.gradient / rho_g)
    };
    let rho_mean = inner.iter().map(|&i| f.density[i] as f64).sum::<f64>() / inner.len() as f64;
    println!(
        "level {level:.4}: slopes p^d {:?} p^v {:?} total {:?}; inner rho mean {rho_mean:.3}",
        fit(&|i| f.p_density[i] as f64),
        fit(&|i| f.p_velocity[i] as f64),
        fit(&|i| (f.p_density[i] + f.p_velocity[i]) as f64)
    );
    let ys: Vec<f32> = inner.iter().map(|&i| f.x[i].y).collect();
    let (lo, hi) = ys
        .iter()
        .fold((1e9f32, -1e9f32), |(a, b), &y| (a.min(y), b.max(y)));
    println!("inner carriers {} between {lo:.4} and {hi:.4}", ys.len());
    // the symmetric pressure force's moment M = Σ_j m/ρ̄ (x_i − x_j)⊗(x_i − x_j) |W'|/r over the
    // fluid neighbours: the factor by which it takes a linear pressure's gradient
    let k = sc.world.kernel();
    let (h, vol) = (k.support(), sc.world.particle_mass() / 1000.0);
    let mut m = [0.0f64; 3];
    for &i in &inner {
        for j in 0..f.len() {
            let d = f.x[i] - f.x[j];
            let r = d.length();
            if r < h && r > 1e-9 {
                let c = (vol * k.grad_mag(r) / r) as f64;
                m[0] += c * (d.x * d.x) as f64;
                m[1] += c * (d.y * d.y) as f64;
                m[2] += c * (d.z * d.z) as f64;
            }
        }
    }
    let nn = inner.len() as f64;
    println!(
        "moment M xx {:.4} yy {:.4} zz {:.4}",
        m[0] / nn,
        m[1] / nn,
        m[2] / nn
    );
}
