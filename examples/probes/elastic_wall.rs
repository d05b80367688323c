//! Probe (issue 23): the water's push on a wall of the elastic box of `tests/deformable.rs`
//! against hydrostatic ½ρgH²W, per variant: `PIN=all` pins every lattice point (the box as a
//! static deformable), `RIGID=1` builds the same compound as a fixed solid. Prints per
//! 0.1 s: the push on the +x walls (gross impulses / dt), the wall SBPs' rms speed, and the
//! mean pressure of the fluid carriers within a spacing of the +x wall's inner face against
//! ρg·depth.
//! At the end: the net forces (the solids' `force`, what the water beside a deformable body
//! got back deducted) on the +x half against hydrostatic and on the whole box against the
//! water's weight, and the carriers' gross push split into floor, +x wall and ±z walls;
//! `PROFILE=1` adds the +x wall's gross push per 2 cm layer; `DAMPING` sets the box's
//! internal damping ζ (default 0); `PIN_AFTER=t` pins every lattice point where it is at
//! time t (the deformed box frozen).
//!
//! `W=2 ALPHA=1 DT=0.016667 SECONDS=1 cargo run --release --example elastic_wall`
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::deform::DeformableParams;
use staggered_fluid::prelude::*;

const DX: f32 = 0.02;

fn env<T: std::str::FromStr>(k: &str, d: T) -> T {
    std::env::var(k)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(d)
}

fn main() {
    let w: u32 = env("W", 2);
    let alpha: f32 = env("ALPHA", 1.0);
    let dt: f32 = env("DT", 1.0 / 60.0);
    let seconds: f32 = env("SECONDS", 1.0);
    let pin_all = std::env::var("PIN").map(|v| v == "all").unwrap_or(false);
    let rigid = env("RIGID", 0) == 1;
    let g = Vector::new(0.0, -9.81, 0.0);
    let (inner, wall, height) = (0.1f32, 2.0 * DX, 0.16f32);
    let depth = 0.12f32;
    let part = |c: Vector, h: Vector| {
        (
            Pose::from_translation(c),
            SharedShape::cuboid(h.x, h.y, h.z),
        )
    };
    let o = inner + wall;
    let shape = SharedShape::compound(vec![
        part(
            Vector::new(0.0, 0.5 * wall, 0.0),
            Vector::new(o, 0.5 * wall, o),
        ),
        part(
            Vector::new(inner + 0.5 * wall, wall + 0.5 * height, 0.0),
            Vector::new(0.5 * wall, 0.5 * height, o),
        ),
        part(
            Vector::new(-inner - 0.5 * wall, wall + 0.5 * height, 0.0),
            Vector::new(0.5 * wall, 0.5 * height, o),
        ),
        part(
            Vector::new(0.0, wall + 0.5 * height, inner + 0.5 * wall),
            Vector::new(inner, 0.5 * height, 0.5 * wall),
        ),
        part(
            Vector::new(0.0, wall + 0.5 * height, -inner - 0.5 * wall),
            Vector::new(inner, 0.5 * height, 0.5 * wall),
        ),
    ]);
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: DX,
        wall_support: env("WALL_SUPPORT", 0) == 1,
        solver: if env("PCISPH", 0) == 1 {
            Solver::Pcisph
        } else {
            Solver::Staggered
        },
        hydrostatic_walls: env("HYDRO", 0) == 1,
        on_failure: if env("LENIENT", 0) == 1 {
            staggered_fluid::OnFailure::Warn
        } else {
            staggered_fluid::OnFailure::Error
        },
        ..Default::default()
    })
    .unwrap();
    let mut dh = None;
    if env("TANK", 0) == 1 {
        fluid
            .add_open_tank(
                Vector::new(-inner, wall, -inner),
                Vector::new(inner, wall + height, inner),
                Slip::FreeSlip,
            )
            .unwrap();
    } else if rigid {
        fluid
            .add_static_solid("box", shape.clone(), Pose::IDENTITY, Slip::FreeSlip)
            .unwrap();
    } else {
        let h = fluid
            .add_deformable(
                "elastic box",
                shape.clone(),
                Pose::IDENTITY,
                DeformableParams {
                    density: 1000.0,
                    stiffness: alpha,
                    half_width: w,
                    damping: env("DAMPING", 0.0),
                    ..Default::default()
                },
            )
            .unwrap();
        let n = fluid
            .pin_deformable(h, |p| pin_all || p.y < 0.5 * DX + 1e-4)
            .unwrap();
        println!("pinned {n}");
        dh = Some(h);
    }
    let lo = Vector::new(-inner, wall, -inner);
    fluid
        .add_block(
            lo,
            lo + Vector::new(2.0 * inner, depth, 2.0 * inner),
            Vector::ZERO,
        )
        .unwrap();
    if env("DUMP", 0) == 1 {
        let c = fluid.solid_carriers();
        println!("solid carriers {}", c.x.len());
        for i in 0..c.x.len() {
            if c.x[i].y < 0.07 && (c.x[i].z - 0.01).abs() < 0.001 && c.x[i].x > 0.07 {
                println!("  x {:?} n {:?} vol {}", c.x[i], c.n[i], c.volume[i]);
            }
        }
    }
    let hydro = 0.5 * 1000.0 * 9.81 * depth * depth * 2.0 * inner;
    let steps = (seconds / dt).round() as usize;
    let every = ((0.1 / dt).round() as usize).max(1);
    let (mut push, mut n, mut tot, mut ntot) = (0.0f64, 0, 0.0f64, 0);
    let mut parts = [0.0f64; 3];
    let mut net_wall = 0.0f64;
    let (mut fy, mut comp, mut level) = (0.0f64, 0.0f64, 0.0f64);
    let (mut prof, mut xs, mut xn) = ([0.0f64; 10], [0.0f64; 10], [0usize; 10]);
    let (mut prel, mut np, mut pd, mut pv) = (0.0f64, 0, 0.0f64, 0.0f64);
    let pin_after: f32 = env("PIN_AFTER", f32::INFINITY);
    for k in 0..steps {
        if let Some(h) = dh.filter(|_| (k as f32 * dt - pin_after).abs() < 0.5 * dt) {
            // the deformed box frozen: every lattice point pinned where it is
            let n = fluid.pin_deformable(h, |_| true).unwrap();
            println!("pinned all {n} at t {:.3}", k as f32 * dt);
        }
        let rep = fluid.step(g, dt).unwrap();
        let c = fluid.solid_carriers();
        let solids: Vec<_> = match dh {
            Some(h) => fluid.deformable(h).unwrap().solids(),
            None => (0..fluid.solids().len() as u32).map(SolidHandle).collect(),
        };
        let (mut f, mut v2, mut nv) = (0.0f64, 0.0f64, 0);
        for &sh in &solids {
            // the net force (what the water beside a deformable body got back deducted)
            let s = fluid.solid(sh).unwrap();
            if k >= steps / 2 {
                fy += s.force.y as f64;
                let n = s.range.len().max(1) as f32;
                if s.range.clone().map(|i| c.x[i].x).sum::<f32>() / n > 0.0 {
                    net_wall += s.force.x as f64;
                }
            }
        }
        for sh in solids {
            let s = fluid.solid(sh).unwrap();
            for i in s.range.clone() {
                if c.x[i].x > 0.0 {
                    f += c.f[i].x as f64;
                    let part = if c.x[i].y < wall {
                        0
                    } else if c.x[i].x > inner - 0.01 * DX {
                        1
                    } else {
                        2
                    };
                    parts[part] += c.f[i].x as f64;
                    if part == 1 && k >= steps / 2 {
                        let b = (((c.x[i].y - wall) / DX).floor().max(0.0) as usize).min(9);
                        prof[b] += c.f[i].x as f64;
                        xs[b] += c.x[i].x as f64;
                        xn[b] += 1;
                    }
                }
                if c.x[i].x > inner && c.x[i].y > wall {
                    v2 += c.u[i].length_squared() as f64;
                    nv += 1;
                }
            }
        }
        let t = (k + 1) as f32 * dt;
        if t > env("FROM", 9.0) && t < env("TO", 0.0) {
            println!(
                "  t {t:.3} substeps {} density it {} pcg {} maxv {:.3} comp max {:.4} pen {} push {:.3} wall rms {:.3e}",
                rep.substeps, rep.density_iterations, rep.pcg_iterations, rep.max_speed,
                rep.compression_max, rep.penetrations_corrected, f / hydro as f64, (v2 / nv.max(1) as f64).sqrt()
            );
            for w in &rep.warnings {
                println!("    warning: {w}");
            }
        }
        push += f;
        n += 1;
        if k >= steps / 2 {
            tot += f;
            ntot += 1;
        }
        let fl = fluid.fluid();
        let top = fl.x.iter().map(|p| p.y).fold(f32::MIN, f32::max) + 0.5 * DX;
        if k >= steps / 2 {
            comp += rep.compression_mean;
            level += (top - wall) as f64;
        }
        // fluid carriers next to the +x wall: pressure against hydrostatic
        for i in 0..fl.len() {
            if fl.x[i].x > inner - DX && fl.x[i].y > wall + 2.0 * DX && fl.x[i].y < top - 2.0 * DX {
                let p = fl.p_density[i] + fl.p_velocity[i];
                let ph = 1000.0 * 9.81 * (top - fl.x[i].y);
                prel += (p / ph) as f64;
                if k >= steps / 2 {
                    pd += (fl.p_density[i] / ph) as f64;
                    pv += (fl.p_velocity[i] / ph) as f64;
                }
                np += 1;
            }
        }
        if (k + 1) % every == 0 {
            println!(
                "t {:.2}  push {:.3} of hydrostatic  wall rms speed {:.2e} m/s  p/ρgd beside the wall {:.3}",
                (k + 1) as f32 * dt,
                push / n as f64 / hydro as f64,
                (v2 / nv.max(1) as f64).sqrt(),
                prel / np.max(1) as f64
            );
            (push, n, prel) = (0.0, 0, 0.0);
            if k < steps / 2 {
                np = 0;
            }
        }
    }
    if env("PROFILE", 0) == 1 {
        for b in 0..10 {
            let y0 = b as f32 * DX;
            let d0 = (depth - y0).max(0.0);
            let d1 = (depth - y0 - DX).max(0.0);
            let h = 0.5 * 1000.0 * 9.81 * (d0 * d0 - d1 * d1) * 2.0 * inner;
            println!(
                "  layer {b} (y {:.2}..{:.2} above the floor): push {:.3} N of {:.3} hydrostatic, carriers' mean x {:.5}",
                y0,
                y0 + DX,
                prof[b] / ntot as f64,
                h,
                xs[b] / xn[b].max(1) as f64
            );
        }
    }
    let weight = 1000.0 * 9.81 * depth as f64 * (2.0 * inner as f64).powi(2);
    println!(
        "second half: net forces: the +x half's {:.3} of hydrostatic, the box's vertical {:.3} of the water's weight; mean compression {:.4} %, level {:.4} m (filled to {depth})",
        net_wall / ntot as f64 / hydro as f64,
        -fy / ntot as f64 / weight,
        100.0 * comp / ntot as f64,
        level / ntot as f64
    );
    println!(
        "second half: push {:.3} of hydrostatic (floor {:.3}, +x wall {:.3}, ±z walls {:.3} over the run); beside the wall p^d {:.3} p^v {:.3} of ρgd",
        tot / ntot as f64 / hydro as f64,
        parts[0] / steps as f64 / hydro as f64,
        parts[1] / steps as f64 / hydro as f64,
        parts[2] / steps as f64 / hydro as f64,
        pd / np as f64,
        pv / np as f64
    );
}
