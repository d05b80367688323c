//! A scene built in code rather than read from a file: a tank of water with a floating box
//! (a dynamic rapier body) and a tap pouring into it, run for one second. The same
//! description can be written out as RON (`spec.to_ron()`) and run with the CLI.
//!
//! `cargo run --release --example scene_in_code`
use staggered_fluid::emitter::{EmitterSpec, OutletSpec};
use staggered_fluid::scenes::{
    BlockSpec, BodyKind, BodySpec, ColliderSpec, OutputSpec, ProbeSpec, SceneFile, ShapeSpec,
    TankSpec,
};
use staggered_fluid::{FluidParams, Slip};

fn main() -> Result<(), staggered_fluid::FluidError> {
    let spec = SceneFile {
        name: "box_under_a_tap".into(),
        description: "a floating box in a tank, a tap pouring beside it".into(),
        gravity: [0.0, -9.81, 0.0],
        dt: 1.0 / 120.0,
        seconds: 1.0,
        settle: None,
        params: FluidParams {
            spacing: 0.025,
            ..Default::default()
        },
        heat: None,
        tanks: vec![TankSpec {
            min: [0.0; 3],
            max: [0.6, 0.5, 0.4],
            slip: Slip::FreeSlip,
            floor_slip: None,
            rapier: true,
        }],
        walls: vec![],
        bodies: vec![BodySpec {
            name: "box".into(),
            kind: BodyKind::Dynamic,
            position: [0.2, 0.25, 0.2],
            rotation: [0.0; 3],
            linvel: [0.0; 3],
            angvel: [0.0; 3],
            lock_translation: [false; 3],
            lock_rotation: false,
            track: true,
            colliders: vec![ColliderSpec {
                shape: ShapeSpec::Cuboid {
                    half_extents: [0.06, 0.04, 0.06],
                },
                offset: [0.0; 3],
                density: Some(500.0),
                mass: None,
                friction: 0.5,
                restitution: 0.0,
                couple: Some(Slip::FreeSlip),
                stick: false,
            }],
        }],
        deformables: Vec::new(),
        cloths: Vec::new(),
        fluid: vec![BlockSpec {
            min: [0.0; 3],
            max: [0.6, 0.2, 0.4],
            velocity: [0.0; 3],
            around_bodies: true,
        }],
        emitters: vec![EmitterSpec {
            center: [0.45, 0.4, 0.2],
            velocity: [0.0, -1.0, 0.0],
            outlet: OutletSpec::Disc { radius: 0.04 },
            start: 0.0,
            stop: Some(0.5),
        }],
        sinks: vec![],
        probe: ProbeSpec::Bodies,
        output: OutputSpec::default(),
    };
    let mut scene = spec.build()?;
    let report = scene.run(spec.seconds as f64, |s, r| {
        if r.step % 30 == 0 {
            println!(
                "t = {:.2} s: {} fluid carriers, E {:.1e}, largest speed {:.2} m/s",
                r.time,
                s.world.fluid().len(),
                r.error,
                r.max_speed
            );
        }
    })?;
    let track = &report.bodies[0];
    let last = track.samples.last().expect("a tracked body");
    println!(
        "after {:.1} s: {} carriers ({} emitted), the box's centre at y = {:.3} m, \
         {:.1} wall s per simulated s",
        report.simulated_seconds,
        report.n_fluid,
        report.emitted,
        last.position[1],
        report.wall_per_simulated_second
    );
    Ok(())
}
