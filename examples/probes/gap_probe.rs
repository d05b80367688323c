//! Diagnostic for floating bodies: the coupling test's three cubes (250/500/750 kg/m³) at
//! rapier's 1/60 s. Every few frames: the far-field pressure fit (dp/dy, where it reaches zero
//! against the waterline), the first fluid layer's distance from the tank's floor and wall and
//! from each cube's bottom and side (carriers within 1Δx of the face; a wider window takes in
//! part of the disordered second layer), their density and pressures, each cube's draft, its
//! force against its weight and against the far-field pressure over its bottom (`F/∫p`), and
//! the vertical force by carrier facing (bottom, edges, sides). `MODE=fixed` holds the cubes at
//! Archimedes' draft. `cargo run --release --example gap_probe` (`PARAMS` overrides).
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::prelude::*;

fn main() {
    let dx = 0.02f32;
    let side = 8.0 * dx;
    let (w, d, depth) = (7.0 * side, 2.0 * side, 13.0 * dx);
    let fixed = std::env::var("MODE").map(|m| m == "fixed").unwrap_or(false);
    let frames: usize = std::env::var("FRAMES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(90);
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = std::env::var("DT")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0 / 60.0);
    let dens = [250.0f32, 500.0, 750.0];
    let mut cubes = Vec::new();
    for (k, rho) in dens.iter().enumerate() {
        let y0 = depth + 0.5 * side - rho / 1000.0 * side + if fixed { 0.0 } else { 0.02 * side };
        let b = physics.bodies.insert(
            if fixed {
                RigidBodyBuilder::fixed()
            } else {
                RigidBodyBuilder::dynamic()
            }
            .translation(Vector::new(side * (1.0 + 2.0 * k as f32), y0, 0.5 * d))
            .locked_axes(LockedAxes::ROTATION_LOCKED),
        );
        physics.colliders.insert_with_parent(
            ColliderBuilder::cuboid(0.5 * side, 0.5 * side, 0.5 * side).density(*rho),
            b,
            &mut physics.bodies,
        );
        cubes.push(b);
    }
    let params = FluidParams {
        spacing: dx,
        ..Default::default()
    }
    .with_env_overrides("PARAMS")
    .unwrap();
    let mut fluid = FluidWorld::new(params).unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(w, 2.0 * depth, d), Slip::NoSlip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(w, depth, d),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let rest = fluid.params().rest_density;
    for k in 0..frames {
        let r = fluid.step_physics_world(&mut physics).unwrap();
        if k % 10 != 0 && k + 1 != frames {
            continue;
        }
        let centres: Vec<Vector> = cubes
            .iter()
            .map(|b| physics.bodies[*b].translation())
            .collect();
        let level = staggered_fluid::metrics::waterline(
            fluid.fluid().x.iter().copied(),
            &centres,
            0.75 * side,
            dx,
        )
        .unwrap();
        // the level an incompressible fluid of this volume would have, the cubes straddling it
        let bottoms: f32 = centres.iter().map(|c| c.y - 0.5 * side).sum();
        let vol_level = (fluid.fluid().len() as f32 * dx.powi(3) - side * side * bottoms)
            / (w * d - 3.0 * side * side);
        let mut line = format!(
            "t {:.3} sub {} cm {:.4}% lvl {:.4} vol-lvl {:.4} |",
            r.time,
            r.substeps,
            100.0 * r.compression_mean,
            level,
            vol_level
        );
        let f = fluid.fluid();
        let pfit: Option<staggered_fluid::metrics::HydrostaticFit>;
        {
            // the tank's floor and its x = 0 wall, away from the cubes
            let (mut nf, mut gf, mut nw, mut gw) = (0usize, 0.0f32, 0usize, 0.0f32);
            let (mut rf, mut rw) = (0.0f32, 0.0f32);
            for i in 0..f.len() {
                let x = f.x[i];
                let far = centres
                    .iter()
                    .all(|c| (x.x - c.x).abs() > 0.5 * side + 2.0 * dx);
                if far
                    && x.y < 1.0 * dx
                    && x.x > 2.0 * dx
                    && x.x < w - 2.0 * dx
                    && x.z > 2.0 * dx
                    && x.z < d - 2.0 * dx
                {
                    nf += 1;
                    gf += x.y;
                    rf += f.density[i];
                }
                if x.x < 1.0 * dx
                    && x.y > 2.0 * dx
                    && x.y < level - 2.0 * dx
                    && x.z > 2.0 * dx
                    && x.z < d - 2.0 * dx
                {
                    nw += 1;
                    gw += x.x;
                    rw += f.density[i];
                }
            }
            // far-field pressure fit p = a + b y (inner carriers away from cubes and walls)
            let fit = staggered_fluid::metrics::hydrostatic_fit((0..f.len()).filter_map(|i| {
                let x = f.x[i];
                let far = centres
                    .iter()
                    .all(|c| (x.x - c.x).abs() > 0.5 * side + 3.0 * dx);
                (far && !f.surface[i]
                    && x.y > 3.0 * dx
                    && x.y < level - 3.0 * dx
                    && x.x > 3.0 * dx
                    && x.x < w - 3.0 * dx)
                    .then(|| (x.y as f64, (f.p_density[i] + f.p_velocity[i]) as f64))
            }))
            .unwrap();
            let (b, y0) = (-fit.gradient, fit.zero_level);
            pfit = Some(fit);
            line += &format!(
                " dp/dy {:.3}ρg p0-level {:+.2}Δx",
                -b / (rest as f64 * 9.81),
                (y0 - level as f64) / dx as f64
            );
            line += &format!(
                " floor gap {:.2} ρ {:.4} wall gap {:.2} ρ {:.4} |",
                gf / nf.max(1) as f32 / dx,
                rf / nf.max(1) as f32 / rest,
                gw / nw.max(1) as f32 / dx,
                rw / nw.max(1) as f32 / rest
            );
        }
        for (c, cen) in centres.iter().enumerate() {
            let bottom = cen.y - 0.5 * side;
            let (mut n, mut gap, mut rho, mut pd, mut pv, mut surf) =
                (0usize, 0.0f32, 0.0f32, 0.0f32, 0.0f32, 0usize);
            let (mut ns, mut gaps) = (0usize, 0.0f32);
            for i in 0..f.len() {
                let x = f.x[i];
                let inside =
                    (x.x - cen.x).abs() < 0.5 * side - dx && (x.z - cen.z).abs() < 0.5 * side - dx;
                let g = bottom - x.y;
                if inside && g > -0.5 * dx && g < 1.0 * dx {
                    n += 1;
                    gap += g;
                    rho += f.density[i];
                    pd += f.p_density[i];
                    pv += f.p_velocity[i];
                    surf += f.surface[i] as usize;
                }
                // beside the side faces, at mid depth of the submerged part
                let sidef = (x.x - cen.x).abs() - 0.5 * side;
                if sidef > -0.5 * dx
                    && sidef < 1.0 * dx
                    && (x.z - cen.z).abs() < 0.5 * side - dx
                    && x.y < level - 2.0 * dx
                    && x.y > bottom + dx
                {
                    ns += 1;
                    gaps += sidef;
                }
            }
            let nn = n.max(1) as f32;
            let fy = fluid
                .solid(
                    fluid
                        .solid_of(physics.bodies[cubes[c]].colliders()[0])
                        .unwrap(),
                )
                .unwrap()
                .force
                .y;
            let weight = dens[c] * side.powi(3) * 9.81;
            let fit: staggered_fluid::metrics::HydrostaticFit = pfit.unwrap();
            let f_field = fit.gradient * (fit.zero_level - bottom as f64) * (side * side) as f64;
            line += &format!(" F/∫p {:.3}", fy as f64 / f_field);
            // the vertical force by where the cube's carriers face: bottom, edges, sides
            let sh = fluid
                .solid_of(physics.bodies[cubes[c]].colliders()[0])
                .unwrap();
            let sc = fluid.solid_carriers();
            let mut parts = [0.0f32; 3];
            for k in fluid.solid(sh).unwrap().range.clone() {
                let n = sc.n[k];
                let part = if n.y < -0.9 {
                    0
                } else if n.y < -0.1 {
                    1
                } else {
                    2
                };
                parts[part] += sc.f[k].y;
            }
            line += &format!(
                " (bottom {:.2} edges {:.2} sides {:.2} of W)",
                parts[0] / weight,
                parts[1] / weight,
                parts[2] / weight
            );
            line += &format!(
                " ρ{} draft {:.3}/{:.3} gap {:.2} side {:.2} ρ/ρ̄ {:.4} pd {:.0} pv {:.0} surf {}/{} F/W {:.3} |",
                dens[c],
                (level - bottom) / side,
                dens[c] / 1000.0,
                gap / nn / dx,
                gaps / ns.max(1) as f32 / dx,
                rho / nn / rest,
                pd / nn,
                pv / nn,
                surf,
                n,
                fy / weight
            );
        }
        println!("{line}");
    }
}
