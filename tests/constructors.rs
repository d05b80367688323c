//! Issue 20: property tests of the API's constructors. Whatever numbers a caller passes —
//! huge, tiny, negative, NaN, infinite — `FluidParams::validate`, `FluidWorld::new`,
//! `add_block`, `add_particles`, the solid constructors and `step` return Ok or an error value:
//! never a panic, never an allocation beyond the documented limits, never a NaN kept.
use proptest::prelude::*;
use rapier3d::parry::shape::SharedShape;
use staggered_fluid::prelude::*;

/// Any f32, weighted toward the values that break arithmetic.
fn wild() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => -10.0f32..10.0,
        1 => Just(0.0f32),
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(-f32::INFINITY),
        1 => Just(1e30f32),
        1 => Just(-1e30f32),
        1 => Just(1e-30f32),
        1 => Just(f32::MAX),
        1 => -1e7f32..1e7,
    ]
}

fn vec3() -> impl Strategy<Value = Vector> {
    (wild(), wild(), wild()).prop_map(|(x, y, z)| Vector::new(x, y, z))
}

fn world() -> FluidWorld {
    FluidWorld::new(FluidParams {
        spacing: 0.05,
        ..Default::default()
    })
    .unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn params_validate_or_refuse(spacing in wild(), support in wild(), cfl in wild(),
                                  visc in wild(), iters in any::<u32>(), tol in wild()) {
        let p = FluidParams {
            spacing,
            support_factor: support,
            max_cfl: cfl,
            viscosity: visc,
            density_iterations: iters,
            density_mean_tolerance: tol,
            ..Default::default()
        };
        if p.validate().is_ok() {
            prop_assert!(spacing.is_finite() && spacing > 0.0);
            prop_assert!(iters <= 10_000);
            // a valid set builds a world
            let _ = FluidWorld::new(p);
        } else {
            prop_assert!(FluidWorld::new(p).is_err());
        }
    }

    #[test]
    fn blocks_fill_or_refuse(a in vec3(), b in vec3(), v in vec3()) {
        let mut w = world();
        match w.add_block(a, b, v) {
            Ok(n) => {
                prop_assert!(n as u64 <= staggered_fluid::params::MAX_PARTICLES);
                prop_assert!(w.fluid().x.iter().chain(&w.fluid().v).all(|p| p.is_finite()));
            }
            Err(e) => prop_assert!(!e.to_string().contains("NaN"), "{}", e),
        }
    }

    #[test]
    fn particles_are_added_or_refused(p in vec3(), v in vec3()) {
        let mut w = world();
        if w.add_particles(&[p], v).is_ok() {
            prop_assert!(p.is_finite() && v.is_finite());
        }
    }

    #[test]
    fn solids_sample_or_refuse(r in wild(), hx in wild(), at in vec3(), kinematic in any::<bool>()) {
        let mut w = world();
        let pose = Pose::from_translation(at);
        for shape in [SharedShape::ball(r), SharedShape::cuboid(hx, r, hx)] {
            let res = if kinematic {
                w.add_kinematic_solid("s", shape, pose, Slip::FreeSlip)
            } else {
                w.add_static_solid("s", shape, pose, Slip::FreeSlip)
            };
            if let Err(e) = res {
                prop_assert!(!e.to_string().contains("NaN, NaN"), "{}", e);
            }
        }
    }

    #[test]
    fn steps_run_or_refuse(g in vec3(), dt in wild(), v in vec3()) {
        let mut w = world();
        w.add_block(Vector::ZERO, Vector::splat(0.2), Vector::ZERO).unwrap();
        let _ = w.add_particles(&[Vector::new(0.1, 0.3, 0.1)], v);
        for _ in 0..2 {
            if w.step(g, dt).is_err() {
                break;
            }
            prop_assert!(w.fluid().x.iter().chain(&w.fluid().v).all(|p| p.is_finite()));
        }
    }
}
