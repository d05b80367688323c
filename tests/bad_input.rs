//! Bad input is a clear error value, never a panic or a NaN.
use staggered_fluid::prelude::*;
use staggered_fluid::FluidError;

fn world() -> FluidWorld {
    FluidWorld::new(FluidParams {
        spacing: 0.05,
        ..Default::default()
    })
    .unwrap()
}

#[test]
fn non_positive_parameters_are_rejected() {
    for (sp, rho) in [
        (0.0, 1000.0),
        (-0.1, 1000.0),
        (f32::NAN, 1000.0),
        (0.05, 0.0),
        (0.05, -5.0),
    ] {
        let e = FluidWorld::new(FluidParams {
            spacing: sp,
            rest_density: rho,
            ..Default::default()
        })
        .err();
        assert!(
            matches!(e, Some(FluidError::NonPositive { .. })),
            "{sp} {rho}: {e:?}"
        );
    }
    for v in [0.0, -0.2, f32::NAN] {
        let e = FluidWorld::new(FluidParams {
            body_force_limit: v,
            ..Default::default()
        })
        .err();
        assert!(
            matches!(
                e,
                Some(FluidError::NonPositive {
                    name: "body_force_limit",
                    ..
                })
            ),
            "{v}: {e:?}"
        );
    }
    let mut w = world();
    w.add_block(Vector::ZERO, Vector::splat(0.2), Vector::ZERO)
        .unwrap();
    for dt in [0.0, -0.01, f32::NAN] {
        assert!(matches!(
            w.step(Vector::new(0.0, -9.81, 0.0), dt),
            Err(FluidError::NonPositive { name: "dt", .. })
        ));
    }
}

#[test]
fn nan_positions_and_velocities_are_rejected() {
    let mut w = world();
    let e = w.add_particles(
        &[Vector::ZERO, Vector::new(f32::NAN, 0.0, 0.0)],
        Vector::ZERO,
    );
    assert!(matches!(e, Err(FluidError::NonFinite { .. })), "{e:?}");
    assert!(w.fluid().is_empty(), "nothing is added on error");
    let e = w.add_particles(&[Vector::ZERO], Vector::new(0.0, f32::INFINITY, 0.0));
    assert!(matches!(e, Err(FluidError::NonFinite { .. })));
    assert!(matches!(
        w.step(Vector::new(0.0, f32::NAN, 0.0), 0.01),
        Err(FluidError::NonFinite { .. })
    ));
}

#[test]
fn empty_fluid_is_an_error() {
    let mut w = world();
    assert_eq!(
        w.step(Vector::new(0.0, -9.81, 0.0), 0.01).err(),
        Some(FluidError::EmptyFluid)
    );
    let e = w.add_block(Vector::ZERO, Vector::splat(0.01), Vector::ZERO);
    assert!(matches!(e, Err(FluidError::EmptyBlock { .. })), "{e:?}");
    assert!(matches!(
        w.add_particles(&[], Vector::ZERO),
        Err(FluidError::EmptyFluid)
    ));
}

#[test]
fn fluid_overlapping_a_wall_is_rejected_either_way() {
    let mut w = world();
    w.add_static_box(
        "wall",
        Vector::new(0.0, 0.0, 0.0),
        Vector::new(0.2, 0.1, 0.2),
        Slip::FreeSlip,
    )
    .unwrap();
    let e = w.add_block(
        Vector::new(0.0, 0.05, 0.0),
        Vector::new(0.2, 0.3, 0.2),
        Vector::ZERO,
    );
    assert!(
        matches!(e, Err(FluidError::FluidOverlapsSolid { ref solid, .. }) if solid == "wall"),
        "{e:?}"
    );
    let mut w = world();
    w.add_block(Vector::ZERO, Vector::splat(0.2), Vector::ZERO)
        .unwrap();
    let e = w.add_static_box(
        "late wall",
        Vector::splat(0.1),
        Vector::splat(0.3),
        Slip::NoSlip,
    );
    assert!(
        matches!(e, Err(FluidError::FluidOverlapsSolid { .. })),
        "{e:?}"
    );
    assert!(
        w.solids().is_empty() && w.solid_carriers().is_empty(),
        "a rejected solid leaves no carriers"
    );
}

#[test]
fn degenerate_and_absurd_requests_are_rejected() {
    let mut w = world();
    let e = w.add_static_box(
        "flat",
        Vector::ZERO,
        Vector::new(0.2, 0.0, 0.2),
        Slip::FreeSlip,
    );
    assert!(
        matches!(e, Err(FluidError::DegenerateShape { .. })),
        "{e:?}"
    );
    let e = w.add_block(Vector::ZERO, Vector::splat(1.0e4), Vector::ZERO);
    assert!(matches!(e, Err(FluidError::TooMany { .. })), "{e:?}");
    // a half-space is a ground: static, it waits for the domain; moving, it is refused
    let e = w.add_kinematic_solid(
        "ground",
        rapier3d::parry::shape::SharedShape::halfspace(Vector::Y),
        Pose::IDENTITY,
        Slip::FreeSlip,
    );
    assert!(
        matches!(e, Err(FluidError::UnsupportedShape { .. })),
        "{e:?}"
    );
    let e = w.add_static_solid(
        "ground",
        rapier3d::parry::shape::SharedShape::halfspace(Vector::Y),
        Pose::from_translation(Vector::new(f32::NAN, 0.0, 0.0)),
        Slip::FreeSlip,
    );
    assert!(matches!(e, Err(FluidError::NonFinite { .. })), "{e:?}");
    w.add_static_solid(
        "ground",
        rapier3d::parry::shape::SharedShape::halfspace(Vector::Y),
        Pose::IDENTITY,
        Slip::FreeSlip,
    )
    .unwrap();
    let e = FluidWorld::new(FluidParams {
        ssor_omega: 2.5,
        ..Default::default()
    })
    .err();
    assert!(matches!(
        e,
        Some(FluidError::OutOfRange {
            name: "ssor_omega",
            ..
        })
    ));
}
