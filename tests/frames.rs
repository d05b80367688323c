//! Frames written by a program of its own (a `FluidWorld` and a rapier body set, no scene):
//! they read back with the world's counts, integer ids, the `.pvd` series' simulated times and
//! the tracked body's poses.
use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use staggered_fluid::frames::{FrameFormats, FrameWriter};
use staggered_fluid::prelude::*;
use staggered_fluid::preview::{ColorBy, PreviewOptions, View};

#[test]
fn frames_from_a_fluid_world_read_back() {
    let dir = std::env::temp_dir().join(format!("sf_frames_{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    let mut physics = PhysicsWorld::new();
    physics.integration_parameters.dt = 0.01;
    let ball = physics
        .bodies
        .insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.25, 0.3, 0.25)));
    physics.colliders.insert_with_parent(
        ColliderBuilder::ball(0.08).density(500.0),
        ball,
        &mut physics.bodies,
    );
    let mut fluid = FluidWorld::new(FluidParams {
        spacing: 0.05,
        ..Default::default()
    })
    .unwrap();
    fluid
        .add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip)
        .unwrap();
    fluid
        .couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip)
        .unwrap();
    fluid
        .add_block_around(
            Vector::ZERO,
            Vector::new(0.5, 0.2, 0.5),
            Vector::ZERO,
            &physics.colliders,
        )
        .unwrap();
    let formats = FrameFormats {
        vtk: true,
        ply: true,
        png: true,
        surface: false,
    };
    let preview = PreviewOptions {
        view: View::Front,
        color: ColorBy::Density,
        ..Default::default()
    };
    let mut frames = FrameWriter::new(&dir, formats)
        .unwrap()
        .with_preview(preview);
    let tracked = vec![("ball".to_string(), ball)];
    let mut times = Vec::new();
    let mut ids = Vec::new();
    for _ in 0..3 {
        fluid.step_physics_world(&mut physics).unwrap();
        frames
            .write_world(&fluid, Some((&physics.bodies, &tracked)))
            .unwrap();
        times.push(fluid.time());
        ids.push(fluid.fluid().id.clone());
    }
    assert_eq!(frames.frames(), 3);
    let n = fluid.fluid().len();

    // the last VTK frame: one vertex per carrier, the world's ids as UInt32
    let vtk = vtkio::Vtk::import(dir.join("fluid_00002.vtp")).unwrap();
    let vtkio::model::DataSet::PolyData { pieces, .. } = vtk.data else {
        panic!("not poly data")
    };
    let vtkio::model::Piece::Inline(piece) = &pieces[0] else {
        panic!("not inline")
    };
    assert_eq!(piece.num_points(), n);
    let id = piece
        .data
        .point
        .iter()
        .find_map(|a| match a {
            vtkio::model::Attribute::DataArray(d) if d.name == "id" => Some(d.data.clone()),
            _ => None,
        })
        .unwrap();
    let vtkio::IOBuffer::U32(id) = id else {
        panic!("ids are not UInt32: {id:?}")
    };
    assert_eq!(id, ids[2]);
    // the ball's carriers are a series of their own; the walls a file once
    assert!(dir.join("solid_00002.vtp").exists() && dir.join("walls.vtp").exists());
    assert!(!dir.join("walls_00001.vtp").exists());

    // the series' times are the world's, to the microsecond
    for (kind, series) in [("fluid", 3usize), ("solid", 3)] {
        let pvd = std::fs::read_to_string(dir.join(format!("{kind}.pvd"))).unwrap();
        let stamps: Vec<f64> = pvd
            .split("timestep=\"")
            .skip(1)
            .map(|s| s[..s.find('"').unwrap()].parse().unwrap())
            .collect();
        assert_eq!(stamps.len(), series, "{pvd}");
        for (a, b) in stamps.iter().zip(&times) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }

    // PLY: the id is an integer property
    let mut f = std::fs::File::open(dir.join("fluid_00001.ply")).unwrap();
    let ply = ply_rs_bw::parser::Parser::<ply_rs_bw::ply::DefaultElement>::new()
        .read_ply(&mut f)
        .unwrap();
    assert_eq!(ply.payload["vertex"].len(), n);
    let first: Vec<u32> = ply.payload["vertex"]
        .iter()
        .map(|e| match e["id"] {
            ply_rs_bw::ply::Property::UInt(i) => i,
            ref p => panic!("id as {p:?}"),
        })
        .collect();
    assert_eq!(first, ids[1]);

    // the tracked ball, one row per frame, at rapier's pose
    let csv = std::fs::read_to_string(dir.join("bodies.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 3);
    let y: f32 = rows[2].split(',').nth(4).unwrap().parse().unwrap();
    assert_eq!(y, physics.bodies[ball].translation().y);
    let png = std::fs::read(dir.join("preview_00002.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    std::fs::remove_dir_all(&dir).ok();
}
