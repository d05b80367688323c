//! Scratch: the still tank's interior arrangement — per carrier the pressure operator's
//! second moments G_aa = (m/ρ̄) Σ |W'| d_a²/r and its zeroth moment S_y = Σ |W'| d_y/r.
use staggered_fluid::internals::CubicSpline;
use staggered_fluid::metrics::waterline;
use staggered_fluid::prelude::*;
use staggered_fluid::scenes;

fn main() {
    let dx = 0.02f32;
    let dt: f32 = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0 / 240.0);
    let secs: f32 = std::env::var("SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.5);
    let params = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    let h = params.support_radius();
    let rho0 = params.rest_density;
    let mut sc = scenes::hydrostatic(0.4, 0.3, dx, params).unwrap();
    let m = sc.world.particle_mass();
    let k = CubicSpline::new(h);
    let steps = (secs / dt).round() as usize;
    for s in 0..steps {
        sc.world.step(sc.gravity, dt).unwrap();
        if s + 1 != steps && (s + 1) % (steps / 5) != 0 {
            continue;
        }
        let f = sc.world.fluid();
        let level = waterline(f.x.iter().copied(), &[], 0.0, dx).unwrap();
        let (mut gx, mut gy, mut gz, mut sy, mut ay, mut n) = (0f64, 0f64, 0f64, 0f64, 0f64, 0);
        let mut rows = Vec::new();
        for i in 0..f.len() {
            let x = f.x[i];
            let e = 2.5 * dx;
            if !(x.x > e
                && x.x < 0.4 - e
                && x.z > e
                && x.z < 0.4 - e
                && x.y > e
                && x.y < level - 3.0 * dx)
            {
                continue;
            }
            let (mut a, mut b, mut c, mut d0, mut fy) = (0f64, 0f64, 0f64, 0f64, 0f64);
            let pri = f.p_density[i] / (f.density[i] * f.density[i]);
            for j in 0..f.len() {
                let d = f.x[j] - x;
                let r = d.length();
                if r <= 0.0 || r >= h {
                    continue;
                }
                let g = (k.grad_mag(r) / r) as f64;
                a += g * (d.x * d.x) as f64;
                b += g * (d.y * d.y) as f64;
                c += g * (d.z * d.z) as f64;
                d0 += g * d.y as f64;
                let prj = f.p_density[j] / (f.density[j] * f.density[j]);
                fy -= (m * (pri + prj)) as f64 * g * d.y as f64;
            }
            let s = (m / rho0) as f64;
            gx += a * s;
            gy += b * s;
            gz += c * s;
            sy += d0 * s;
            ay += fy;
            n += 1;
            rows.push((x.y as f64, f.p_density[i] as f64, f.p_velocity[i] as f64));
        }
        let n = n as f64;
        let fit = |k: usize| {
            let (my, mp) = rows.iter().fold((0.0, 0.0), |a, r| {
                (a.0 + r.0, a.1 + if k == 0 { r.1 } else { r.1 + r.2 })
            });
            let (my, mp) = (my / n, mp / n);
            let (sxy, sxx) = rows.iter().fold((0.0, 0.0), |a, r| {
                let p = if k == 0 { r.1 } else { r.1 + r.2 };
                (a.0 + (r.0 - my) * (p - mp), a.1 + (r.0 - my) * (r.0 - my))
            });
            -sxy / sxx / (9.81 * rho0 as f64)
        };
        println!("  dp^d/dy {:.4} d(p^d+p^v)/dy {:.4} (ρ̄g)", fit(0), fit(1));
        println!("t {:.2} interior {} G_xx {:.4} G_yy {:.4} G_zz {:.4} mean S_y·V {:.3e} 1/m  a_y(p^d) {:.3} m/s²", sc.world.time(), n, gx / n, gy / n, gz / n, sy / n, ay / n);
    }
}
