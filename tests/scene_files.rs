//! Scene files: every asset scene round-trips through the parser and equals the built-in
//! description of the same name; JSON is accepted; broken files are rejected with the file,
//! line and field that are wrong.

use staggered_fluid::scenes;
use staggered_fluid::scenes::SceneFile;
use staggered_fluid::{FluidError, FluidParams};

fn asset(name: &str) -> String {
    let path = format!("{}/assets/scenes/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn every_asset_scene_round_trips_and_matches_its_built_in() {
    let dir = format!("{}/assets/scenes", env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut names: Vec<String> = scenes::NAMES.iter().map(|n| format!("{n}.ron")).collect();
    names.sort();
    assert_eq!(files, names, "one file per built-in scene");
    for name in scenes::NAMES {
        let text = asset(name);
        let spec = SceneFile::parse(&text, name).unwrap();
        let built_in = scenes::spec_by_name(name, None, FluidParams::default()).unwrap();
        assert_eq!(
            spec, built_in,
            "{name}: the asset file differs from the built-in scene"
        );
        // writing it again gives the same text, so the files are what `export` prints
        assert_eq!(spec.to_ron(), text, "{name}: not in canonical form");
        // JSON carries the same scene
        let json = serde_json::to_string_pretty(&spec).unwrap();
        assert_eq!(
            SceneFile::parse(&json, "x.json").unwrap(),
            spec,
            "{name} as JSON"
        );
    }
}

#[test]
fn a_scene_file_builds_the_same_world_as_the_built_in_scene() {
    // the five balls: rapier bodies, a rapier tank and coupled colliders
    let from_file = SceneFile::parse(&asset("five_balls"), "five_balls.ron")
        .unwrap()
        .build()
        .unwrap();
    let built_in = scenes::by_name("five_balls", None).unwrap();
    assert_eq!(from_file.world.fluid().x, built_in.world.fluid().x);
    assert_eq!(
        from_file.world.solid_carriers().x,
        built_in.world.solid_carriers().x
    );
    assert_eq!(from_file.tracked.len(), 5);
    let ph = from_file.physics.as_ref().unwrap();
    // five balls and the five fixed tank cuboids
    assert_eq!(ph.colliders.len(), 10);
    let ball = &ph.bodies[from_file.tracked[0].1];
    let expect = 550.0 * 4.0 / 3.0 * std::f32::consts::PI * 0.06f32.powi(3);
    assert!(
        (ball.mass() - expect).abs() < 1e-3 * expect,
        "{}",
        ball.mass()
    );
}

/// Replaces `from` (which must occur) in the hydrostatic asset and checks the error.
/// `delta`: the error's line relative to the line where `from` starts.
fn broken(base: &str, from: &str, to: &str, file: &str, delta: i64, field: &str, says: &str) {
    let text = asset(base);
    let at = text
        .find(from)
        .unwrap_or_else(|| panic!("`{from}` not in {base}"));
    let line = (text[..at].matches('\n').count() as i64 + 1 + delta) as usize;
    let text = text.replacen(from, to, 1);
    let err = SceneFile::check(&text, file).err().expect("rejected");
    let FluidError::Scene {
        file: f,
        line: l,
        field: fd,
        message,
        ..
    } = &err
    else {
        panic!("not a scene error: {err:?}")
    };
    assert_eq!(f, file, "{err}");
    assert_eq!(*l, line, "{err}");
    assert_eq!(fd, field, "{err}");
    assert!(message.contains(says), "`{says}` not in: {err}");
    let shown = err.to_string();
    assert!(
        shown.starts_with(&format!("{file}:{line}:")),
        "message does not start with file:line: {shown}"
    );
}

#[test]
fn check_names_file_line_and_field_of_broken_files() {
    let h = "hydrostatic";
    // syntax: a missing comma after `dt: 0.002`
    broken(
        h,
        "dt: 0.002,",
        "dt: 0.002",
        "t.ron",
        1,
        "",
        "Expected comma",
    );
    // type: a string where a number goes
    broken(
        h,
        "dt: 0.002",
        "dt: \"fast\"",
        "t.ron",
        0,
        "dt",
        "Expected float",
    );
    // a field that does not exist (a typo)
    broken(
        "tap",
        "        no_stick: true,",
        "        no_stik: true,",
        "t.ron",
        0,
        "params.no_stik",
        "Unexpected field",
    );
    // an impossible parameter
    broken(
        "tap",
        "spacing: 0.01",
        "spacing: -0.01",
        "t.ron",
        0,
        "params.spacing",
        "> 0",
    );
    // a box with its corners swapped
    broken(
        h,
        "max: (0.4, 0.3, 0.4)",
        "max: (0.4, -0.3, 0.4)",
        "t.ron",
        0,
        "fluid[0].max",
        "must exceed min",
    );
    // the fluid block overlaps the floor: found only when building
    broken(
        h,
        "min: (0.0, 0.0, 0.0),\n            max: (0.4, 0.3, 0.4)",
        "min: (0.0, -0.1, 0.0),\n            max: (0.4, 0.3, 0.4)",
        "t.ron",
        -1,
        "fluid[0]",
        "inside solid",
    );
    // a misspelt top-level key
    broken(
        h,
        "    fluid: [",
        "    fluids: [",
        "t.ron",
        0,
        "fluids",
        "Unexpected field",
    );
    // a wall needs a name: the error points at the wall
    broken(
        h,
        "    tanks: [",
        "    walls: [",
        "t.ron",
        1,
        "walls[0]",
        "missing field",
    );
    // the probe measures the first tank's floor: without a tank it is an error
    let text = asset(h)
        .replacen("    tanks: [", "    /* tanks: [", 1)
        .replacen("    fluid: [", "*/\n    fluid: [", 1);
    let probe = text[..text.find("    probe:").unwrap()]
        .matches('\n')
        .count()
        + 1;
    let err = SceneFile::check(&text, "t.ron").err().unwrap().to_string();
    assert!(
        err.starts_with(&format!("t.ron:{probe}:"))
            && err.contains("`probe`")
            && err.contains("add a tank"),
        "{err}"
    );

    // a tap whose outlet lies inside the sphere it pours on
    broken(
        "tap",
        "center: (0.218, 0.45, 0.2)",
        "center: (0.2, 0.25, 0.2)",
        "t.ron",
        0,
        "emitters[0].center",
        "inside solid",
    );

    let b = "five_balls";
    // a ball of negative radius (third ball, line of its collider)
    let text = asset(b);
    let third = text.match_indices("radius: 0.06").nth(2).unwrap().0;
    let line = text[..third].matches('\n').count() + 1;
    let text2 = format!("{}radius: -0.06{}", &text[..third], &text[third + 12..]);
    let err = SceneFile::check(&text2, "b.ron").err().unwrap().to_string();
    assert!(
        err.starts_with(&format!("b.ron:{line}:"))
            && err.contains("bodies[2].colliders[0].shape.radius"),
        "{err}"
    );
    // both density and mass
    broken(
        b,
        "density: 550.0,",
        "density: 550.0, mass: 2.0,",
        "b.ron",
        0,
        "bodies[0].colliders[0].mass",
        "not both",
    );
    // an unknown shape
    broken(
        b,
        "shape: Ball(radius: 0.06), density: 550.0",
        "shape: Torus(radius: 0.06), density: 550.0",
        "b.ron",
        0,
        "bodies[0].colliders[0].shape",
        "Torus",
    );

    let w = "wedge";
    // a hull whose points all lie in one plane
    let text = asset(w);
    let start = text.find("points: [").unwrap();
    let end = start + text[start..].find(']').unwrap() + 1;
    let flat = "points: [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 1.0)]";
    let text = format!("{}{flat}{}", &text[..start], &text[end..]);
    let err = SceneFile::check(&text, "w.ron").err().unwrap().to_string();
    assert!(
        err.contains("bodies[0].colliders[0].shape") && err.contains("span no volume"),
        "{err}"
    );
    assert!(!err.starts_with("w.ron:0:"), "{err}");

    // JSON errors have lines too
    let json = "{\n  \"name\": \"x\",\n  \"dt\": 0.01,\n  \"seconds\": -1.0,\n  \"fluid\": [{\"min\": [0,0,0], \"max\": [1,1,1]}]\n}";
    let err = SceneFile::check(json, "x.json").err().unwrap().to_string();
    assert!(
        err.starts_with("x.json:4:") && err.contains("seconds"),
        "{err}"
    );
    let json = "{\n  \"name\": \"x\",\n  \"dt\": 0.01,\n  \"seconds\": 1.0,\n  \"fluid\": [{\"min\": [0,0,0], \"max\": [1,1]}]\n}";
    let err = SceneFile::check(json, "x.json").err().unwrap().to_string();
    assert!(
        err.starts_with("x.json:5:") && err.contains("fluid[0].max"),
        "{err}"
    );
}

#[test]
fn a_scene_without_fluid_or_emitter_is_an_error() {
    let text =
        "(name: \"empty\", dt: 0.01, seconds: 1.0,\n tanks: [(min: (0, 0, 0), max: (1, 1, 1))])";
    let err = SceneFile::check(text, "e.ron").err().unwrap().to_string();
    assert!(err.contains("no fluid"), "{err}");
}

#[test]
fn a_scene_built_in_code_names_the_scene_and_field() {
    let bad = FluidParams {
        density_relaxation: -1.0,
        ..FluidParams::default()
    };
    let err = scenes::hydrostatic(0.2, 0.1, 0.05, bad)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.starts_with("scene hydrostatic: field `params.density_relaxation`"),
        "{err}"
    );
}

/// Every parameter, changed alone, is the one `changed_fields` names (so a scene file written
/// with only the changed parameters cannot drop one), and it survives the file round trip.
#[test]
fn each_changed_parameter_is_named_and_written() {
    let d = serde_json::to_value(FluidParams::default()).unwrap();
    let keys: Vec<String> = d.as_object().unwrap().keys().cloned().collect();
    assert!(keys.len() >= 30, "{keys:?}");
    for k in &keys {
        // a different value of the field's type (enums: another variant)
        let candidates: Vec<serde_json::Value> = match &d[k] {
            serde_json::Value::Bool(b) => vec![(!b).into()],
            serde_json::Value::Number(n) => match n.as_u64() {
                Some(i) => vec![(2 * i + 1).into()],
                None => [0.5, 1.5, 2.0]
                    .iter()
                    .map(|f| (n.as_f64().unwrap() * f).into())
                    .collect(),
            },
            serde_json::Value::Null => vec![serde_json::json!([[0, 0, 0], [1, 1, 1]])],
            serde_json::Value::String(_) => {
                ["BlockSsor", "ConjugateGradient", "Pcisph", "Paper", "Warn"]
                    .iter()
                    .map(|s| serde_json::Value::from(*s))
                    .collect()
            }
            other => panic!("{k}: {other}"),
        };
        let p = candidates
            .into_iter()
            .find_map(|v| {
                let mut o = d.clone();
                o[k] = v;
                serde_json::from_value::<FluidParams>(o)
                    .ok()
                    .filter(|p| p.validate().is_ok())
            })
            .unwrap_or_else(|| panic!("no other value for {k}"));
        assert_eq!(p.changed_fields(), [k.as_str()], "{k}");
        let mut spec = scenes::spec_by_name("hydrostatic", None, FluidParams::default()).unwrap();
        spec.params = p.clone();
        let text = spec.to_ron();
        assert!(text.contains(&format!("{k}:")), "{k} not written: {text}");
        assert_eq!(SceneFile::parse(&text, "t.ron").unwrap().params, p, "{k}");
    }
}

/// A collider that cannot be coupled is named by its body's name in the file, not by rapier's
/// collider index.
#[test]
fn coupling_errors_name_the_body() {
    let text = asset("five_balls").replacen("Ball(radius: 0.06)", "Ball(radius: 60.0)", 1);
    let err = SceneFile::check(&text, "t.ron")
        .err()
        .expect("rejected")
        .to_string();
    assert!(
        err.contains("ball 550") && !err.contains("collider 5"),
        "{err}"
    );
}

/// A scene file holds deformable bodies (issue 23): built and run, a jelly dropped over the
/// water falls into it; it survives the round trip through RON; a bad material is rejected
/// naming the file, line and field.
#[test]
fn scene_files_hold_deformable_bodies() {
    let text = r#"(
    name: "jelly",
    dt: 0.01,
    seconds: 0.3,
    params: (spacing: 0.025),
    tanks: [(min: (0.0, 0.0, 0.0), max: (0.4, 0.4, 0.4))],
    deformables: [
        (
            name: "jelly",
            shape: Cuboid(half_extents: (0.05, 0.05, 0.05)),
            position: (0.2, 0.3, 0.2),
            material: (density: 600.0, stiffness: 0.5),
        ),
    ],
    fluid: [(min: (0.0, 0.0, 0.0), max: (0.4, 0.15, 0.4))],
)"#;
    let spec = SceneFile::parse(text, "j.ron").unwrap();
    assert_eq!(SceneFile::parse(&spec.to_ron(), "k.ron").unwrap(), spec);
    let mut sc = spec.build().unwrap();
    sc.run(0.3, |_, _| {}).unwrap();
    let y = sc.world.deformables()[0].center_of_mass().y;
    println!("the jelly's centre at {y:.3} m (dropped from 0.3)");
    // free fall to the water (0.1 m) takes 0.14 s; it floats at about 0.15 + 0.05 − 0.06
    assert!(y < 0.22, "the jelly did not fall: {y}");
    let bad = text.replace("stiffness: 0.5", "stiffness: 1.5");
    let err = SceneFile::check(&bad, "j.ron").err().unwrap().to_string();
    assert!(
        err.contains("j.ron:") && err.contains("deformables[0]") && err.contains("stiffness"),
        "{err}"
    );
}

/// Shao et al. 2014's deformable scenes run from their shipped files: a third of a second of
/// each with no fluid lost, no guard tripped, and the melting scene's ice above the water
/// it floats in; the stream reaches the cloth, the box and the blob.
#[test]
fn shao_scenes_run_from_their_files() {
    for name in ["melting", "cloth", "elastic_box", "elastic_blob"] {
        let text = asset(name);
        let mut scene = SceneFile::parse(&text, name).unwrap().build().unwrap();
        let mut lost = 0;
        scene
            .run(0.35, |_, r| {
                lost += r.removed_outside;
                assert!(r.warnings.is_empty(), "{name}: {:?}", r.warnings);
            })
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(lost, 0, "{name}: fluid lost");
        let w = &scene.world;
        let b = &w.deformables()[0];
        let lowest = b
            .positions()
            .iter()
            .map(|p| p.y)
            .fold(f32::INFINITY, f32::min);
        let near = w
            .fluid()
            .x
            .iter()
            .filter(|x| {
                b.positions()
                    .iter()
                    .any(|p| (*p - **x).length() < 2.0 * 0.02)
            })
            .count();
        assert!(
            lowest > 0.0 && near > 10,
            "{name}: lowest point {lowest}, {near} carriers near"
        );
    }
}

/// A deformable body from a closed triangle mesh in a scene file: a cube as twelve
/// outward-facing triangles gives the body a cuboid of the same size gives (the same lattice
/// points, the same mass); a triangle naming a missing vertex, and an open mesh, are
/// rejected naming the field.
#[test]
fn a_scene_file_makes_a_deformable_body_from_a_triangle_mesh() {
    let mesh = "TriMesh(vertices: [(-0.05, -0.05, -0.05), (0.05, -0.05, -0.05), \
        (0.05, 0.05, -0.05), (-0.05, 0.05, -0.05), (-0.05, -0.05, 0.05), (0.05, -0.05, 0.05), \
        (0.05, 0.05, 0.05), (-0.05, 0.05, 0.05)], indices: [(0, 2, 1), (0, 3, 2), (4, 5, 6), \
        (4, 6, 7), (0, 1, 5), (0, 5, 4), (3, 7, 6), (3, 6, 2), (0, 4, 7), (0, 7, 3), (1, 2, 6), \
        (1, 6, 5)])";
    let scene = |shape: &str| {
        format!(
            r#"(
    name: "mesh",
    dt: 0.01,
    seconds: 0.1,
    params: (spacing: 0.025),
    tanks: [(min: (0.0, 0.0, 0.0), max: (0.4, 0.4, 0.4))],
    deformables: [(name: "cube", shape: {shape}, position: (0.2, 0.3, 0.2))],
    fluid: [(min: (0.0, 0.0, 0.0), max: (0.4, 0.15, 0.4))],
)"#
        )
    };
    let from_mesh = SceneFile::parse(&scene(mesh), "m.ron").unwrap();
    assert_eq!(
        SceneFile::parse(&from_mesh.to_ron(), "m2.ron").unwrap(),
        from_mesh
    );
    let from_mesh = from_mesh.build().unwrap();
    let from_box = SceneFile::parse(&scene("Cuboid(half_extents: (0.05, 0.05, 0.05))"), "b.ron")
        .unwrap()
        .build()
        .unwrap();
    let (a, b) = (
        &from_mesh.world.deformables()[0],
        &from_box.world.deformables()[0],
    );
    assert_eq!(a.rest_positions(), b.rest_positions());
    assert!(
        (a.mass() - b.mass()).abs() < 1e-4 * b.mass(),
        "{} vs {}",
        a.mass(),
        b.mass()
    );
    let missing = scene(&mesh.replace("(1, 6, 5)", "(1, 6, 9)"));
    let err = SceneFile::check(&missing, "m.ron")
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("deformables[0].shape.indices[11]"), "{err}");
    let open = scene(&mesh.replace(", (1, 2, 6), (1, 6, 5)", ""));
    let err = SceneFile::check(&open, "m.ron").err().unwrap().to_string();
    assert!(
        err.contains("m.ron:") && err.contains("deformables[0]"),
        "{err}"
    );
}
