//! Checksums of every fluid position and velocity (and every tracked body's pose and velocity)
//! after fixed runs, to prove that a behaviour-preserving change is one: the dam break for 400
//! steps with the staggered solver and with PCISPH, and the five balls for 2 s.
//!
//! `cargo run --release --example checksum [dam|pcisph|balls]...` (all three by default;
//! `PARAMS` overrides parameters as JSON). `melting` (120 frames), `cloth` and `elastic_box`
//! (30 frames) run those scenes, fluid temperatures and the deformable bodies' points included.
use staggered_fluid::scenes::{self, Scene};
use staggered_fluid::{FluidParams, Solver};

/// FNV-1a over the bit patterns of the fluid state and the rapier bodies.
fn checksum(sc: &Scene) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    let mut eat = |bits: u32| {
        for b in bits.to_le_bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x100000001b3);
        }
    };
    let fl = sc.world.fluid();
    for (x, v) in fl.x.iter().zip(&fl.v) {
        for k in 0..3 {
            eat(x[k].to_bits());
            eat(v[k].to_bits());
        }
    }
    for t in &fl.temperature {
        eat(t.to_bits());
    }
    for b in sc.world.deformables() {
        for (x, v) in b.positions().iter().zip(b.velocities()) {
            for k in 0..3 {
                eat(x[k].to_bits());
                eat(v[k].to_bits());
            }
        }
        for t in b.temperatures() {
            eat(t.to_bits());
        }
    }
    if let Some(ph) = &sc.physics {
        for (_, h) in &sc.tracked {
            let rb = &ph.bodies[*h];
            let c = rb.center_of_mass();
            let v = rb.linvel();
            let w = rb.angvel();
            for k in 0..3 {
                eat(c[k].to_bits());
                eat(v[k].to_bits());
                eat(w[k].to_bits());
            }
        }
    }
    h
}

fn steps(sc: &mut Scene, n: usize) {
    for _ in 0..n {
        match sc.physics.as_mut() {
            Some(ph) => {
                sc.world.step_physics_world(ph).unwrap();
            }
            None => {
                sc.world.step(sc.gravity, sc.dt).unwrap();
            }
        }
    }
}

fn main() {
    let mut which: Vec<String> = std::env::args().skip(1).collect();
    if which.is_empty() {
        which = vec!["dam".into(), "pcisph".into(), "balls".into()];
    }
    // `PARAMS='{"density_solver": "Paper"}'` overrides the parameters of every run
    let base = FluidParams::default().with_env_overrides("PARAMS").unwrap();
    for w in which {
        let (mut sc, n) = match w.as_str() {
            "dam" => (
                scenes::by_name_with("dam_break", None, base.clone()).unwrap(),
                400,
            ),
            "pcisph" => (
                scenes::by_name_with(
                    "dam_break",
                    None,
                    FluidParams {
                        solver: Solver::Pcisph,
                        ..base.clone()
                    },
                )
                .unwrap(),
                400,
            ),
            "balls" => {
                let sc = scenes::by_name_with("five_balls", None, base.clone()).unwrap();
                let n = (2.0 / sc.dt as f64).round() as usize;
                (sc, n)
            }
            // (the ice starts melting after a second)
            "melting" => (scenes::by_name_with(&w, None, base.clone()).unwrap(), 120),
            "cloth" | "elastic_box" => (scenes::by_name_with(&w, None, base.clone()).unwrap(), 30),
            other => {
                panic!("unknown run `{other}` (dam, pcisph, balls, melting, cloth, elastic_box)")
            }
        };
        if matches!(w.as_str(), "dam" | "pcisph" | "balls") {
            steps(&mut sc, n);
        } else {
            // (the scene's own run: its emitters pour)
            let seconds = n as f64 * sc.dt as f64;
            sc.run(seconds, |_, _| {}).unwrap();
        }
        println!(
            "{w}: {n} steps, {} fluid carriers, checksum {:016x}",
            sc.world.fluid().len(),
            checksum(&sc)
        );
    }
}
