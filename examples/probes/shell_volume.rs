//! Diagnostic (issue 18): how much density a sampled solid gives a fluid carrier beside it,
//! against the exact volume integral `∫_solid W`. For a ball (radius `R` spacings, default 3)
//! and a flat wall, fluid points at `δ` spacings from the surface (0.5, 1.0, 1.5) over many
//! directions: the solid's share of the kernel sum with volumes 1 (how static solids are
//! weighted) and with Akinci relative volumes (moving solids), and the exact share
//! (a fine quadrature). A share above the exact one makes the fluid keep further away: the
//! body acts bigger than it is.
//! `cargo run --release --example shell_volume` (`R` the radius in spacings).
use rapier3d::parry::shape::{Ball, Cuboid};
use staggered_fluid::internals::{relative_volumes, sample_shell, signed_distance, CubicSpline};
use staggered_fluid::prelude::*;

fn main() {
    let dx = 1.0f32;
    let h = 2.0 * dx;
    let k = CubicSpline::new(h);
    let rr: f32 = std::env::var("R")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3.0);
    let norm = k.lattice_sum(dx) as f64; // Σ_lattice W Δx³
    let ball = Ball::new(rr * dx);
    let slab = Cuboid::new(Vector::new(20.0 * dx, 5.0 * dx, 20.0 * dx));
    for (name, shape, dirs) in [
        (
            "ball",
            &ball as &dyn rapier3d::parry::shape::Shape,
            sphere_dirs(200),
        ),
        (
            "flat",
            &slab as &dyn rapier3d::parry::shape::Shape,
            vec![Vector::Y],
        ),
    ] {
        let shell = sample_shell(shape, dx, h).unwrap();
        let local: Vec<Vector> = shell.iter().map(|c| c.x).collect();
        let akinci = relative_volumes(shape, &local, &k, dx, h);
        let total_volume: f32 = akinci.iter().sum();
        println!(
            "{name}: {} carriers, Σψ {total_volume:.1} (volumes 1: {})",
            shell.len(),
            shell.len()
        );
        for delta in [0.5f32, 1.0, 1.5] {
            let (mut s1, mut sa, mut ex) = (0.0f64, 0.0f64, 0.0f64);
            for d in &dirs {
                // a point at `delta` outside the surface along d
                let x = if name == "ball" {
                    *d * (rr + delta) * dx
                } else {
                    Vector::new(0.3 * dx, 5.0 * dx + delta * dx, 0.2 * dx)
                };
                for (c, &psi) in shell.iter().zip(&akinci) {
                    let w = k.w((x - c.x).length()) as f64;
                    s1 += w;
                    sa += psi as f64 * w;
                }
                ex += exact(shape, x, &k, h);
            }
            let n = dirs.len() as f64;
            println!(
                "  δ {delta} Δx: share of the kernel sum, volumes 1 {:.4}, Akinci {:.4}, exact {:.4}",
                s1 / n / norm,
                sa / n / norm,
                ex / n / norm
            );
        }
    }
}

fn sphere_dirs(n: usize) -> Vec<Vector> {
    // Fibonacci sphere
    let ga = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).sqrt();
            let t = ga * i as f32;
            Vector::new(r * t.cos(), y, r * t.sin())
        })
        .collect()
}

/// `∫_solid W(x − y) dy` by a midpoint rule on a grid of Δx/8 (in Δx³ units of the sum).
fn exact(shape: &dyn rapier3d::parry::shape::Shape, x: Vector, k: &CubicSpline, h: f32) -> f64 {
    let m = 16;
    let step = h / m as f32;
    let mut s = 0.0f64;
    for a in -m..m {
        for b in -m..m {
            for c in -m..m {
                let o = Vector::new(a as f32 + 0.5, b as f32 + 0.5, c as f32 + 0.5) * step;
                let r = o.length();
                if r >= h {
                    continue;
                }
                if signed_distance(shape, x + o) <= 0.0 {
                    s += k.w(r) as f64;
                }
            }
        }
    }
    s * (step as f64).powi(3)
}
