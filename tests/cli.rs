//! The binary end to end: `check` accepts the asset scenes and rejects a broken file with its
//! line; `run --output` writes VTK/PLY frames that re-read with the right counts and fields,
//! PNG previews, the report and plots; the progress bar never writes to a non-terminal;
//! `resume` continues a snapshot.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_staggered-fluid"))
}

/// Runs `cmd`, asserts it succeeded (showing its stderr if not); returns stdout and stderr.
fn succeeds(cmd: &mut Command) -> (String, Vec<u8>) {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        out.stderr,
    )
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("sf_cli_{name}_{}", std::process::id()));
    std::fs::remove_dir_all(&d).ok();
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn check_accepts_assets_and_rejects_a_broken_file() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let (text, _) = succeeds(
        bin()
            .arg("check")
            .arg(dir.join("five_balls.ron"))
            .arg(dir.join("tap.ron")),
    );
    assert!(
        text.contains("five_balls.ron: ok") && text.contains("1 emitters"),
        "{text}"
    );

    let d = tmp("check");
    let bad = d.join("bad.ron");
    let src = std::fs::read_to_string(dir.join("five_balls.ron")).unwrap();
    std::fs::write(&bad, src.replacen("density: 775.0", "density: -775.0", 1)).unwrap();
    let out = bin().arg("check").arg(&bad).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    let line = src
        .lines()
        .position(|l| l.contains("density: 775.0"))
        .unwrap()
        + 1;
    assert!(
        err.contains(&format!("bad.ron:{line}:")) && err.contains("bodies[1].colliders[0].density"),
        "{err}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// Count, property names and `pressure` values of a PLY file's `vertex` element.
fn read_ply(path: &Path) -> (usize, Vec<String>, Vec<f32>) {
    use ply_rs_bw::parser::Parser;
    use ply_rs_bw::ply::DefaultElement;
    let mut f = std::fs::File::open(path).unwrap();
    let ply = Parser::<DefaultElement>::new().read_ply(&mut f).unwrap();
    let v = &ply.payload["vertex"];
    let names = ply.header.elements["vertex"]
        .properties
        .keys()
        .cloned()
        .collect();
    let pressure = v
        .iter()
        .map(|e| match e["pressure"] {
            ply_rs_bw::ply::Property::Float(p) => p,
            _ => panic!("pressure is not a float"),
        })
        .collect();
    (v.len(), names, pressure)
}

#[test]
fn run_writes_frames_that_read_back_and_no_progress_bar_to_a_pipe() {
    let d = tmp("run");
    let snap = d.join("snap.bin");
    let (stdout, stderr) = succeeds(
        bin()
            .args([
                "run",
                "hydrostatic",
                "--spacing",
                "0.04",
                "--seconds",
                "0.1",
            ])
            .arg("--output")
            .arg(&d)
            .arg("--snapshot")
            .arg(&snap),
    );
    // stderr is a pipe here: the progress bar must not write to it
    assert!(
        stderr.is_empty(),
        "stderr: {:?}",
        String::from_utf8_lossy(&stderr)
    );
    assert!(stdout.contains("t  0.1000 s"), "{stdout}");
    // 10 × 7.5 × 10 carriers at Δx = 4 cm in a 0.4 × 0.3 × 0.4 m block
    let n = 10 * 7 * 10;
    assert!(stdout.contains(&format!("{n} fluid")), "{stdout}");
    // 30 frames per second over 0.1 s at 2 ms steps: the start and steps 17 and 34
    for k in 0..3 {
        for ext in ["vtp", "ply"] {
            assert!(
                d.join(format!("fluid_{k:05}.{ext}")).exists(),
                "frame {k} {ext}"
            );
        }
        assert!(d.join(format!("preview_{k:05}.png")).exists());
    }
    assert!(!d.join("fluid_00003.vtp").exists());
    for f in [
        "walls.vtp",
        "walls.ply",
        "report.json",
        "metric.png",
        "error.png",
        "pcg.png",
    ] {
        assert!(d.join(f).exists(), "{f}");
    }
    // PNG files are PNG
    let png = std::fs::read(d.join("preview_00002.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");

    // VTK: one vertex per fluid carrier, the named fields with the right sizes
    let vtk = vtkio::Vtk::import(d.join("fluid_00002.vtp")).unwrap();
    let vtkio::model::DataSet::PolyData { pieces, .. } = vtk.data else {
        panic!("not poly data")
    };
    let vtkio::model::Piece::Inline(piece) = &pieces[0] else {
        panic!("not inline")
    };
    assert_eq!(piece.num_points(), n);
    let fields: Vec<(String, usize)> = piece
        .data
        .point
        .iter()
        .map(|a| match a {
            vtkio::model::Attribute::DataArray(d) => (d.name.clone(), d.data.len()),
            vtkio::model::Attribute::Field { name, .. } => (name.clone(), 0),
        })
        .collect();
    for (name, len) in [
        ("velocity", 3 * n),
        ("pressure", n),
        ("density", n),
        ("surface", n),
        ("id", n),
    ] {
        assert!(
            fields.contains(&(name.to_string(), len)),
            "{name}: {fields:?}"
        );
    }
    let array = |name: &str| -> Vec<f32> {
        piece
            .data
            .point
            .iter()
            .find_map(|a| match a {
                vtkio::model::Attribute::DataArray(d) if d.name == name => {
                    d.data.clone().cast_into()
                }
                _ => None,
            })
            .unwrap()
    };
    // ids and flags are integers, not floats
    for name in ["id", "surface"] {
        let int = piece.data.point.iter().any(|a| {
            matches!(a, vtkio::model::Attribute::DataArray(d)
                if d.name == name && matches!(d.data, vtkio::IOBuffer::U32(_)))
        });
        assert!(int, "{name} is not stored as UInt32");
    }
    // every carrier once: the ids are 0..n
    let mut ids: Vec<u32> = array("id").iter().map(|i| *i as u32).collect();
    ids.sort();
    assert_eq!(ids, (0..n as u32).collect::<Vec<_>>());
    let vtk_pressure = array("pressure");

    // PLY: the same count, position, velocity components and fields, and the same values
    let (count, names, pressure) = read_ply(&d.join("fluid_00002.ply"));
    assert_eq!(count, n);
    for p in [
        "x",
        "y",
        "z",
        "velocity_x",
        "velocity_z",
        "pressure",
        "density",
        "surface",
    ] {
        assert!(names.iter().any(|q| q == p), "{p} in {names:?}");
    }
    assert_eq!(pressure, vtk_pressure);
    assert!(
        pressure.iter().any(|p| *p > 0.0),
        "the water carries pressure"
    );

    // ParaView's series: the frames with their simulated times
    let pvd = std::fs::read_to_string(d.join("fluid.pvd")).unwrap();
    for (k, t) in [(0, "0"), (1, "0.034"), (2, "0.068")] {
        assert!(
            pvd.contains(&format!(
                r#"timestep="{t}" group="" part="0" file="fluid_{k:05}.vtp""#
            )),
            "{pvd}"
        );
    }

    // resume the snapshot from the command line; its speed is over the resumed part only
    let report = d.join("resumed.json");
    let (stdout, _) = succeeds(
        bin()
            .arg("resume")
            .arg(&snap)
            .args(["--seconds", "0.02", "--quiet", "--report"])
            .arg(&report),
    );
    assert!(
        stdout.contains("from t = 0.1000 s")
            && stdout.contains("done: 10 steps, 0.020 s simulated"),
        "{stdout}"
    );
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let f = |k: &str| r[k].as_f64().unwrap();
    assert!((f("simulated_seconds") - 0.02).abs() < 1e-6, "{r}");
    assert!((f("end_time") - 0.12).abs() < 1e-6, "{r}");
    let per = f("wall_seconds") / f("simulated_seconds");
    assert!(
        (f("wall_per_simulated_second") / per - 1.0).abs() < 1e-9,
        "{r}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// `run --settle` lets the water settle before the run and says what that did, in its output
/// and in the JSON report; the run then starts at t = 0.
#[test]
fn run_settle_settles_first() {
    let d = tmp("settle");
    let report = d.join("report.json");
    let (text, _) = succeeds(
        bin()
            .args([
                "run",
                "hydrostatic",
                "--spacing",
                "0.05",
                "--settle",
                "0.1",
                "--seconds",
                "0.01",
                "--quiet",
                "--report",
            ])
            .arg(&report),
    );
    assert!(text.contains("settled 0.1 s first (50 steps"), "{text}");
    assert!(text.contains("from t = 0.0000 s"), "{text}");
    assert!(text.contains("0.010 s simulated"), "{text}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(json["settled"]["steps"], 50, "{}", json["settled"]);
    std::fs::remove_dir_all(&d).ok();
}

/// `run --games` takes the settings for games, and says which parameters that changed.
#[test]
fn run_games_takes_the_game_settings() {
    let (text, _) = succeeds(bin().args([
        "run",
        "hydrostatic",
        "--spacing",
        "0.05",
        "--games",
        "--seconds",
        "0.01",
        "--quiet",
    ]));
    let line = text
        .lines()
        .find(|l| l.starts_with("parameters changed from the defaults"))
        .unwrap_or_else(|| panic!("{text}"));
    for p in ["density_mean_tolerance", "density_max_tolerance"] {
        assert!(line.contains(p), "{line}");
    }
}

#[test]
fn bad_arguments_are_clear_errors() {
    for args in [
        vec!["run", "no_such_scene"],
        vec!["run", "hydrostatic", "--seconds", "-1"],
        vec!["run", "/nonexistent/scene.ron"],
        vec!["resume", "/nonexistent/snapshot.bin"],
        vec!["run", "hydrostatic", "--settle", "-1", "--spacing", "0.05"],
        vec!["run", "elastic_box", "--settle", "1"],
        vec![
            "run",
            "hydrostatic",
            "--surface",
            "--seconds",
            "0.01",
            "--spacing",
            "0.05",
        ],
    ] {
        let out = bin().args(&args).output().unwrap();
        if args.contains(&"--surface") && cfg!(feature = "surface") {
            assert!(out.status.success());
            continue;
        }
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: ") && !err.contains("panicked"),
            "{args:?}: {err}"
        );
    }
}

/// The water surface of a still block is a closed mesh enclosing about the block's volume.
#[cfg(feature = "surface")]
#[test]
fn surface_mesh_of_a_still_block_encloses_its_volume() {
    let sc = staggered_fluid::scenes::hydrostatic(0.4, 0.3, 0.02, Default::default()).unwrap();
    let mesh = staggered_fluid::surface::reconstruct(&sc.world).unwrap();
    let v = mesh.volume();
    // 0.4 × 0.3 × 0.4 m = 0.048 m³; the iso-surface rounds the block's edges and sits within
    // about one radius of the outer carriers
    assert!((v - 0.048).abs() < 0.1 * 0.048, "volume {v} m³");
    let d = tmp("surface");
    staggered_fluid::surface::write_obj(&sc.world, &d.join("s.obj")).unwrap();
    let text = std::fs::read_to_string(d.join("s.obj")).unwrap();
    assert_eq!(
        text.lines().filter(|l| l.starts_with("f ")).count(),
        mesh.triangles.len()
    );
    std::fs::remove_dir_all(&d).ok();
}

/// A scene file that asks for surface meshes gets one OBJ per frame (with the feature).
#[cfg(feature = "surface")]
#[test]
fn a_scene_file_can_ask_for_surface_meshes() {
    let mut spec = staggered_fluid::scenes::spec_by_name(
        "hydrostatic",
        Some(0.04),
        staggered_fluid::FluidParams::default(),
    )
    .unwrap();
    spec.output.surface = true;
    spec.output.ply = false;
    let d = tmp("surface_file");
    let file = d.join("tank.ron");
    std::fs::write(&file, spec.to_ron()).unwrap();
    succeeds(
        bin()
            .arg("run")
            .arg(&file)
            .args(["--seconds", "0.04", "--quiet", "--output"])
            .arg(d.join("out")),
    );
    // frames at the start and at step 17 of 20 (30 per second at 2 ms)
    for k in 0..2 {
        let obj = std::fs::read_to_string(d.join(format!("out/surface_{k:05}.obj"))).unwrap();
        assert!(obj.lines().filter(|l| l.starts_with("f ")).count() > 100);
    }
    assert!(!d.join("out/fluid_00000.ply").exists());
    std::fs::remove_dir_all(&d).ok();
}

/// `run --set` changes parameters of a built-in (and says so); unknown or invalid ones are
/// clear errors; `--formats` chooses the files.
#[test]
fn run_set_overrides_parameters_and_formats_choose_files() {
    let d = tmp("set");
    let (stdout, _) = succeeds(
        bin()
            .args([
                "run",
                "hydrostatic",
                "--spacing",
                "0.05",
                "--seconds",
                "0.02",
            ])
            .args([
                "--set",
                "xsph=0",
                "--set",
                "solver=Pcisph",
                "--set",
                "max_cfl=0.3",
            ])
            .args(["--formats", "vtk", "--quiet"])
            .arg("--output")
            .arg(&d),
    );
    assert!(
        stdout.contains("parameters changed from the defaults: spacing, solver, xsph, max_cfl"),
        "{stdout}"
    );
    assert!(d.join("fluid_00000.vtp").exists() && d.join("fluid.pvd").exists());
    assert!(!d.join("fluid_00000.ply").exists() && !d.join("preview_00000.png").exists());
    for (set, says) in [
        ("nonsense=1", "unknown field `nonsense`"),
        ("xsph=-1", "xsph"),
        ("xsph", "KEY=VALUE"),
    ] {
        let out = bin()
            .args([
                "run",
                "hydrostatic",
                "--spacing",
                "0.05",
                "--seconds",
                "0.01",
                "--set",
                set,
            ])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{set}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error: --set") && err.contains(says),
            "{set}: {err}"
        );
    }
    std::fs::remove_dir_all(&d).ok();
}

/// `list` says what each built-in shows and how big it is.
#[test]
fn list_describes_every_scene() {
    let (stdout, _) = succeeds(bin().arg("list"));
    for name in staggered_fluid::scenes::NAMES {
        assert!(stdout.contains(name), "{name}: {stdout}");
    }
    for words in ["Martin & Moyce", "Archimedes", "Fig. 13", "10800"] {
        assert!(stdout.contains(words), "{words}: {stdout}");
    }
}

/// The summary states the result against the scene's reference: the dam break's front
/// against Martin & Moyce, the still tank's floor force and density, floating drafts against
/// Archimedes; stage times as Table 3 columns.
#[test]
fn summaries_state_the_result_against_the_reference() {
    let (dam, _) = succeeds(bin().args([
        "run",
        "dam_break",
        "--spacing",
        "0.01",
        "--seconds",
        "0.06",
        "--quiet",
    ]));
    assert!(
        dam.contains("against Martin & Moyce 1952")
            && dam.contains("Z reference")
            && dam.contains("result: surge front within"),
        "{dam}"
    );
    assert!(dam.contains("solve (t_solving)") && dam.contains("µs per particle-step"));
    let (tank, _) = succeeds(bin().args([
        "run",
        "hydrostatic",
        "--spacing",
        "0.05",
        "--seconds",
        "0.05",
    ]));
    assert!(
        tank.contains("result: floor carries") && tank.contains("compressed"),
        "{tank}"
    );
    // per-frame lines name every figure with its unit
    let line = tank.lines().find(|l| l.starts_with("t ")).unwrap();
    for part in [
        "E ",
        "compression ",
        "substeps",
        "vmax",
        "m/s",
        "floor ",
        " N (",
    ] {
        assert!(line.contains(part), "{part}: {line}");
    }
    // a floating ball in a small tank: its draft against Archimedes
    let d = tmp("float");
    let file = d.join("float.ron");
    std::fs::write(
        &file,
        r#"(
    name: "float",
    dt: 0.01,
    seconds: 0.3,
    params: (spacing: 0.04),
    tanks: [(min: (0, 0, 0), max: (0.6, 0.6, 0.6), slip: FreeSlip, rapier: true)],
    bodies: [(name: "cork", kind: Dynamic, position: (0.3, 0.2, 0.3),
        colliders: [(shape: Ball(radius: 0.1), density: 500.0, couple: FreeSlip)])],
    fluid: [(min: (0, 0, 0), max: (0.6, 0.2, 0.6), around_bodies: true)],
    probe: Bodies,
)"#,
    )
    .unwrap();
    let (float, _) = succeeds(bin().arg("run").arg(&file).arg("--quiet"));
    assert!(
        float.contains("against Archimedes")
            && float.contains("│ cork")
            && float.contains("result: floating bodies' drafts within"),
        "{float}"
    );
    std::fs::remove_dir_all(&d).ok();
}

/// `export` writes only the parameters that differ from the defaults, numbers without f32
/// noise, and a scene that runs; an export that would not run is refused.
#[test]
fn export_writes_what_differs_and_refuses_what_would_not_run() {
    let (text, _) = succeeds(bin().args(["export", "dam_break", "--set", "xsph=0.05"]));
    assert!(text.contains("xsph: 0.05"), "{text}");
    assert!(
        !text.contains("support_factor") && !text.contains("krylov"),
        "{text}"
    );
    // no number carries more than six significant digits
    for tok in text.split(|c: char| !(c.is_ascii_digit() || c == '.')) {
        let digits = tok.trim_start_matches(['0', '.']).replace('.', "");
        assert!(digits.len() <= 6, "`{tok}` in {text}");
    }
    let d = tmp("export");
    let file = d.join("dam.ron");
    std::fs::write(&file, &text).unwrap();
    let (ok, _) = succeeds(bin().arg("check").arg(&file));
    assert!(ok.contains("dam.ron: ok (dam_break: 10800 fluid"), "{ok}");
    let out = bin()
        .args(["export", "dam_break", "--spacing", "0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty(), "nothing printed for a refused scene");
    std::fs::remove_dir_all(&d).ok();
}
