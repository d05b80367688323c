//! Issue 23: heat and melting (Shao et al. 2014 §3.4.2, Eq. 20).
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::deform::{DeformableHandle, DeformableParams, Melting};
use staggered_fluid::internals::fill_box;
use staggered_fluid::prelude::*;
use staggered_fluid::{FluidHeat, HeatSource};
use std::collections::HashSet;

const DX: f32 = 0.02;
const G: Vector = Vector::new(0.0, -9.81, 0.0);
const HALF: f32 = 0.05;
const FRAME: f32 = 1.0 / 60.0;

/// A 0.4 m tank with water 0.25 m deep at `water_t` (conductivity `kf`) and a cube of ice
/// (density 900, side 0.1 m, 5³ lattice points) at `ice_t` floating in it.
fn ice_in_water(water_t: f32, kf: f32, melting: Melting) -> (FluidWorld, DeformableHandle) {
    let c = Vector::new(0.2, 0.25 + HALF - 0.09, 0.2);
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        ..Default::default()
    })
    .unwrap();
    w.add_open_tank(Vector::ZERO, Vector::splat(0.4), Slip::FreeSlip)
        .unwrap();
    let clear = Vector::splat(HALF + 0.5 * DX * (1.0 - 1e-3));
    let pts: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.4, 0.25, 0.4), DX)
        .into_iter()
        .filter(|p| ((*p - c).abs() - clear).max_element() >= 0.0)
        .collect();
    w.add_particles(&pts, Vector::ZERO).unwrap();
    w.set_fluid_heat(FluidHeat {
        temperature: water_t,
        conductivity: kf,
    })
    .unwrap();
    let h = w
        .add_deformable(
            "ice",
            SharedShape::cuboid(HALF, HALF, HALF),
            Pose::from_translation(c),
            DeformableParams {
                density: 900.0,
                melting: Some(melting),
                ..Default::default()
            },
        )
        .unwrap();
    (w, h)
}

/// Mass of fluid, body and its melt pool, kg.
fn mass(w: &FluidWorld, h: DeformableHandle) -> f64 {
    let b = w.deformable(h).unwrap();
    w.fluid().len() as f64 * w.particle_mass() as f64 + b.mass() + b.melt_pending()
}

/// The lattice cells of a body's points (its rest positions on the lattice of spacing DX).
fn cells(w: &FluidWorld, h: DeformableHandle) -> Vec<[i32; 3]> {
    let b = w.deformable(h).unwrap();
    b.rest_positions()
        .iter()
        .map(|p| (*p / DX + Vector::splat(0.5)).floor().as_ivec3().to_array())
        .collect()
}

fn full_ring(c: [i32; 3], at: &HashSet<[i32; 3]>) -> bool {
    (0..27)
        .map(|k| [k % 3 - 1, (k / 3) % 3 - 1, k / 9 - 1])
        .all(|o| at.contains(&[c[0] + o[0], c[1] + o[1], c[2] + o[2]]))
}

/// Ice already at its melting point throughout melts from the outside in, one layer of its
/// lattice a step (Shao §3.4.2's surface-first rule): every point that melts had an open
/// one-ring the step before, so the 5³ cube goes 125 → 27 → 1 → 0 points, where melting
/// every point at its melting point would take it all in the first step.
#[test]
fn ice_melts_from_the_surface_in() {
    let melting = Melting {
        temperature: 0.0,
        melting_point: 0.0,
        conductivity: 1e-3,
        latent_heat: 0.0,
    };
    let (mut w, h) = ice_in_water(40.0, 0.0, melting);
    let mut counts = vec![cells(&w, h).len()];
    for _ in 0..4 {
        let before: HashSet<[i32; 3]> = cells(&w, h).into_iter().collect();
        let r = w.step(G, FRAME).unwrap();
        let after: HashSet<[i32; 3]> = cells(&w, h).into_iter().collect();
        for c in before.difference(&after) {
            assert!(!full_ring(*c, &before), "a covered point {c:?} melted");
        }
        assert_eq!(r.melted as usize, before.len() - after.len());
        counts.push(after.len());
    }
    assert_eq!(counts, [125, 27, 1, 0, 0]);
}

/// A cube of ice at −2 °C in water at 60 °C melts away within a second, and the water's mass
/// plus the ice's (and its melt pool's) stays what it was, to round-off, every step: the melt
/// becomes water carriers of the fluid's mass, the remainder waits in the pool.
#[test]
fn melting_ice_keeps_the_mass() {
    let melting = Melting {
        temperature: -2.0,
        melting_point: 0.0,
        conductivity: 2e-3,
        latent_heat: 0.0,
    };
    let (mut w, h) = ice_in_water(60.0, 1e-3, melting);
    let m0 = mass(&w, h);
    let n_fluid = w.fluid().len();
    let mut made = 0;
    for _ in 0..60 {
        let r = w.step(G, FRAME).unwrap();
        made += r.melt_carriers as usize;
        let m = mass(&w, h);
        assert!((m - m0).abs() <= 1e-9 * m0, "mass {m0} → {m} kg");
        assert_eq!(w.fluid().len(), n_fluid + made);
    }
    let b = w.deformable(h).unwrap();
    assert!(
        b.positions().is_empty(),
        "{} points left",
        b.positions().len()
    );
    // 125 points of 7.2 g made 112 carriers of 8 g; 4 g wait in the pool
    assert_eq!(made, 112);
    assert!((b.melt_pending() - 0.004).abs() < 1e-6);
}

/// Melted mass over 30 frames for an ice conductivity `k` (m²/s) and latent heat `latent`
/// (°C).
fn melted_after(k: f32, latent: f32) -> f64 {
    let melting = Melting {
        temperature: -5.0,
        melting_point: 0.0,
        conductivity: k,
        latent_heat: latent,
    };
    let (mut w, h) = ice_in_water(30.0, 0.0, melting);
    let m0 = w.deformable(h).unwrap().mass();
    for _ in 0..30 {
        w.step(G, FRAME).unwrap();
    }
    m0 - w.deformable(h).unwrap().mass()
}

/// The same ice in the same warm water melts faster when it conducts heat better: it warms
/// to its melting point sooner (Fig. 11b's four conductivities). A latent heat slows it: the
/// points at their melting point must take that much more heat first.
#[test]
fn ice_melts_faster_with_a_higher_conductivity_and_slower_with_a_latent_heat() {
    let (slow, fast) = (melted_after(2e-4, 0.0), melted_after(2e-3, 0.0));
    assert!(slow > 0.0, "nothing melted at K = 2e-4");
    assert!(
        fast > 2.0 * slow,
        "melted {fast} kg at K = 2e-3, {slow} kg at 2e-4"
    );
    let latent = melted_after(2e-3, 80.0);
    assert!(
        latent < 0.5 * fast,
        "melted {latent} kg with a latent heat, {fast} kg without"
    );
}

/// Without heat sources the exchange moves heat, it does not make it: the sum of the
/// temperatures over water and ice is kept (every particle holds one cell's heat), none
/// leaves the range it started in (implicit diffusion has a maximum principle), and the ice
/// warms while the water beside it cools.
#[test]
fn heat_exchange_conserves_heat_within_bounds() {
    let melting = Melting {
        temperature: -20.0,
        melting_point: 100.0, // never melts
        conductivity: 1e-3,
        latent_heat: 0.0,
    };
    let (mut w, h) = ice_in_water(40.0, 1e-3, melting);
    let sum = |w: &FluidWorld| -> f64 {
        w.fluid().temperature.iter().map(|&t| t as f64).sum::<f64>()
            + w.deformable(h)
                .unwrap()
                .temperatures()
                .iter()
                .map(|&t| t as f64)
                .sum::<f64>()
    };
    let s0 = sum(&w);
    for _ in 0..20 {
        let r = w.step(G, FRAME).unwrap();
        assert!(r.heat_sweeps > 0);
    }
    let s1 = sum(&w);
    assert!((s1 - s0).abs() <= 1e-5 * s0.abs(), "heat {s0} → {s1}");
    let b = w.deformable(h).unwrap();
    let all = w.fluid().temperature.iter().chain(b.temperatures());
    assert!(all.clone().all(|t| (-20.0..=40.0).contains(t)));
    let ice = b.temperatures().iter().sum::<f32>() / b.temperatures().len() as f32;
    let coldest_water = w.fluid().temperature.iter().copied().fold(40.0, f32::min);
    assert!(ice > -15.0, "the ice's mean {ice} °C");
    assert!(
        coldest_water < 30.0,
        "the water's coldest {coldest_water} °C"
    );
}

/// A hot plate on the floor of still water warms the water above it and nothing else: no
/// carrier gets hotter than the plate, the water's heat grows, and it is warmer near the
/// plate than far from it.
#[test]
fn a_hot_plate_warms_the_water_beside_it() {
    let mut w = FluidWorld::new(FluidParams {
        spacing: DX,
        ..Default::default()
    })
    .unwrap();
    w.add_open_tank(Vector::ZERO, Vector::new(0.4, 0.3, 0.2), Slip::FreeSlip)
        .unwrap();
    // a plate 4 cm thick on the floor, water 12 cm deep around and over it
    let (c, half) = (Vector::new(0.1, 0.02, 0.1), Vector::new(0.05, 0.02, 0.1));
    let clear = half + Vector::splat(0.5 * DX * (1.0 - 1e-3));
    let pts: Vec<Vector> = fill_box(Vector::ZERO, Vector::new(0.4, 0.12, 0.2), DX)
        .into_iter()
        .filter(|p| ((*p - c).abs() - clear).max_element() >= 0.0)
        .collect();
    w.add_particles(&pts, Vector::ZERO).unwrap();
    let plate = w
        .add_static_solid(
            "plate",
            SharedShape::cuboid(half.x, half.y, half.z),
            Pose::from_translation(c),
            Slip::FreeSlip,
        )
        .unwrap();
    let src = HeatSource {
        temperature: 80.0,
        conductivity: 2e-3,
    };
    w.set_heat_source(plate, Some(src)).unwrap();
    assert_eq!(w.fluid_heat(), Some(FluidHeat::default()));
    for _ in 0..30 {
        w.step(G, FRAME).unwrap();
    }
    let fl = w.fluid();
    let mean = |keep: &dyn Fn(Vector) -> bool| {
        let t: Vec<f32> = (0..fl.len())
            .filter(|&i| keep(fl.x[i]))
            .map(|i| fl.temperature[i])
            .collect();
        t.iter().sum::<f32>() / t.len() as f32
    };
    let near = mean(&|x| x.x < 0.15 && x.y < 0.07);
    let far = mean(&|x| x.x > 0.3);
    assert!(fl.temperature.iter().all(|&t| (20.0..=80.0).contains(&t)));
    assert!(near > 22.0, "water over the plate at {near} °C");
    assert!((far - 20.0).abs() < 0.5, "water far from it at {far} °C");
}

/// Bad heat settings are errors that name the field, and change nothing.
#[test]
fn bad_heat_input_is_a_clear_error() {
    let mut w = FluidWorld::new(FluidParams::default()).unwrap();
    let bad = [
        (
            Melting {
                conductivity: -1.0,
                ..Default::default()
            },
            "Melting::conductivity",
        ),
        (
            Melting {
                melting_point: f32::NAN,
                ..Default::default()
            },
            "melting_point",
        ),
    ];
    for (melting, says) in bad {
        let e = w
            .add_deformable(
                "ice",
                SharedShape::cuboid(0.1, 0.1, 0.1),
                Pose::IDENTITY,
                DeformableParams {
                    melting: Some(melting),
                    ..Default::default()
                },
            )
            .unwrap_err();
        assert!(e.to_string().contains(says), "{e}");
    }
    assert!(w.deformables().is_empty() && w.solids().is_empty());
    let e = w
        .set_fluid_heat(FluidHeat {
            temperature: 20.0,
            conductivity: -0.5,
        })
        .unwrap_err();
    assert!(e.to_string().contains("FluidHeat::conductivity"), "{e}");
    assert_eq!(w.fluid_heat(), None);
    let wall = w
        .add_static_solid(
            "wall",
            SharedShape::cuboid(0.1, 0.1, 0.1),
            Pose::IDENTITY,
            Slip::FreeSlip,
        )
        .unwrap();
    let e = w
        .set_heat_source(
            wall,
            Some(HeatSource {
                temperature: f32::INFINITY,
                conductivity: 1.0,
            }),
        )
        .unwrap_err();
    assert!(e.to_string().contains("HeatSource::temperature"), "{e}");
    assert!(w.solids()[0].heat.is_none());
}

/// A melting world resumes from its state bit for bit, temperatures, melt pool and the
/// lattice left of the ice included, through a serialised copy as well.
#[test]
fn a_melting_world_resumes_exactly() {
    let melting = Melting {
        temperature: -1.0,
        melting_point: 0.0,
        conductivity: 2e-3,
        latent_heat: 5.0,
    };
    let (mut w, h) = ice_in_water(40.0, 1e-3, melting);
    for _ in 0..6 {
        w.step(G, FRAME).unwrap();
    }
    let json = serde_json::to_string(&w.state()).unwrap();
    let mut copy = FluidWorld::from_state(serde_json::from_str(&json).unwrap()).unwrap();
    let mut melted = 0;
    for _ in 0..6 {
        melted += w.step(G, FRAME).unwrap().melted;
        copy.step(G, FRAME).unwrap();
    }
    assert!(melted > 0, "nothing melted after the copy");
    assert_eq!(w.fluid().x, copy.fluid().x);
    assert_eq!(w.fluid().temperature, copy.fluid().temperature);
    let (a, b) = (w.deformable(h).unwrap(), copy.deformable(h).unwrap());
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.temperatures(), b.temperatures());
    assert_eq!(a.absorbed_heat(), b.absorbed_heat());
    assert_eq!(a.melt_pending(), b.melt_pending());
}
