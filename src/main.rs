//! `staggered-fluid`: runs a built-in scene or a scene file end to end, with a progress bar,
//! per-frame lines, frames (VTK with a `.pvd` time series, PLY, PNG, surface meshes), a JSON
//! report, plots and a summary against the scene's reference; checks scene files; lists and
//! exports the built-in scenes; resumes from snapshots.

use clap::{Args, Parser, Subcommand, ValueEnum};
use comfy_table::CellAlignment;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use staggered_fluid::frames::{FrameFormats, FrameWriter};
use staggered_fluid::preview::{self, ColorBy, PreviewOptions, View};
use staggered_fluid::scenes::{self, RunReport, Scene, SceneFile};
use staggered_fluid::snapshot::Snapshot;
use staggered_fluid::FluidParams;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[path = "cli/print.rs"]
mod print;
use print::{print_step, settle, summary, table};

#[derive(Parser)]
#[command(
    name = "staggered-fluid",
    version,
    about = "He 2012 staggered meshless SPH fluid for rapier3d worlds",
    after_help = "Without a command: runs the dam break (30 carriers across) and compares its \
                  front with Martin & Moyce 1952."
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a built-in scene (see `list`) or a scene file (.ron or .json).
    Run {
        /// Built-in scene name or path to a scene file.
        scene: String,
        /// Particle spacing in metres (built-in scenes only; default: the scene's own).
        #[arg(long)]
        spacing: Option<f32>,
        /// Set a fluid parameter, e.g. `--set xsph=0 --set solver=Pcisph` (repeatable; any
        /// field of FluidParams, the value as JSON or a bare word).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Let the water settle this many simulated seconds first, bodies held still, its
        /// velocities then cleared (the scene's `settle` field; 0 turns it off).
        #[arg(long, value_name = "SECONDS")]
        settle: Option<f32>,
        /// The settings for games (`FluidParams::for_games`: the density held to 0.5 % mean
        /// compression instead of 0.1 %, longer substeps: two of a 1/60 s frame for 0.3 m of
        /// water at Δx 2 cm), applied before any `--set`.
        #[arg(long)]
        games: bool,
        #[command(flatten)]
        opts: RunOpts,
    },
    /// Continue a run from a snapshot written by `run --snapshot`.
    Resume {
        /// The snapshot file.
        snapshot: PathBuf,
        #[command(flatten)]
        opts: RunOpts,
    },
    /// Validate scene files without running them (parse, check values, build).
    Check {
        /// Scene files.
        #[arg(required = true)]
        files: Vec<PathBuf>,
    },
    /// List the built-in scenes with what they show and their size.
    List,
    /// Print a built-in scene as a scene file (RON) to start your own from: parameters only
    /// where they differ from the defaults.
    Export {
        /// Built-in scene name.
        scene: String,
        /// Particle spacing in metres (default: the scene's own).
        #[arg(long)]
        spacing: Option<f32>,
        /// Set a fluid parameter (as for `run`).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// The settings for games (as for `run`).
        #[arg(long)]
        games: bool,
    },
}

#[derive(Args, Default)]
struct RunOpts {
    /// Simulated seconds (default: the scene's own duration).
    #[arg(long)]
    seconds: Option<f64>,
    /// Write frames, the report and plots here (frames as the scene's `output` section or
    /// `--formats` say).
    #[arg(long)]
    output: Option<PathBuf>,
    /// Frame formats, comma-separated: vtk, ply, png, surface, or none (default: the scene's).
    #[arg(long, value_name = "LIST")]
    formats: Option<String>,
    /// The axis PNG previews look along.
    #[arg(long, value_enum, default_value_t = ViewArg::Side)]
    view: ViewArg,
    /// What the fluid's colour shows in PNG previews.
    #[arg(long, value_enum, default_value_t = ColorArg::Speed)]
    color: ColorArg,
    /// Write the JSON run report here.
    #[arg(long)]
    report: Option<PathBuf>,
    /// Also write a water surface mesh per frame (OBJ; needs the `surface` feature).
    #[arg(long)]
    surface: bool,
    /// Save a snapshot at the end of the run (resume it with `resume`).
    #[arg(long)]
    snapshot: Option<PathBuf>,
    /// No per-frame lines (the progress bar still shows on a terminal).
    #[arg(long)]
    quiet: bool,
}

#[derive(Clone, Copy, ValueEnum, Default)]
enum ViewArg {
    /// Along −z: x right, y up.
    #[default]
    Side,
    /// Along −x: z right, y up.
    Front,
    /// Down −y: x right, z up.
    Top,
}

#[derive(Clone, Copy, ValueEnum, Default)]
enum ColorArg {
    /// Speed, m/s.
    #[default]
    Speed,
    /// Pressure p^d + p^v, Pa.
    Pressure,
    /// SPH density, kg/m³.
    Density,
}

/// `params` with the `KEY=VALUE` settings applied (a value that is not JSON is a string, so
/// enum variants need no quotes), validated.
fn apply_sets(params: &FluidParams, sets: &[String]) -> Result<FluidParams, String> {
    if sets.is_empty() {
        return Ok(params.clone());
    }
    let mut obj = serde_json::Map::new();
    for s in sets {
        let (k, v) = s
            .split_once('=')
            .ok_or_else(|| format!("--set expects KEY=VALUE, got `{s}`"))?;
        let v = v.trim();
        let value = serde_json::from_str(v).unwrap_or_else(|_| serde_json::Value::from(v));
        obj.insert(k.trim().to_string(), value);
    }
    params
        .with_json_overrides(&serde_json::Value::Object(obj).to_string())
        .map_err(|e| format!("--set: {e}"))
}

/// The spacing a `--set spacing=…` asks for, taken out of the settings (a built-in scene is
/// laid out for its spacing, so it goes where `--spacing` goes).
fn take_spacing(spacing: Option<f32>, sets: &mut Vec<String>) -> Result<Option<f32>, String> {
    let mut out = spacing;
    let mut rest = Vec::new();
    for s in sets.drain(..) {
        match s.split_once('=') {
            Some((k, v)) if k.trim() == "spacing" => {
                out = Some(
                    v.trim()
                        .parse()
                        .map_err(|_| format!("--set spacing: not a number: `{v}`"))?,
                )
            }
            _ => rest.push(s),
        }
    }
    *sets = rest;
    Ok(out)
}

fn is_file(scene: &str) -> bool {
    let path = Path::new(scene);
    path.extension().is_some_and(|e| e == "ron" || e == "json") || path.exists()
}

/// The scene description: a built-in's (at `spacing`) or a file's, with the settings applied.
fn load_spec(
    scene: &str,
    spacing: Option<f32>,
    sets: &[String],
    games: bool,
) -> Result<SceneFile, String> {
    let preset = |p: &FluidParams| {
        if games {
            p.clone().for_games()
        } else {
            p.clone()
        }
    };
    let mut sets = sets.to_vec();
    if is_file(scene) {
        let path = Path::new(scene);
        if spacing.is_some() {
            return Err(
                "--spacing applies to built-in scenes; set `params.spacing` in the file or use --set spacing=…".into(),
            );
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let mut spec =
            SceneFile::parse(&text, &path.display().to_string()).map_err(|e| e.to_string())?;
        spec.params = apply_sets(&preset(&spec.params), &sets)?;
        Ok(spec)
    } else {
        let spacing = take_spacing(spacing, &mut sets)?;
        if let Some(dx) = spacing {
            if !(dx.is_finite() && dx > 0.0) {
                return Err(format!(
                    "--spacing must be a positive number of metres, got {dx}"
                ));
            }
        }
        let mut spec = scenes::spec_by_name(scene, spacing, FluidParams::default())
            .map_err(|e| e.to_string())?;
        spec.params = apply_sets(&preset(&spec.params), &sets)?;
        Ok(spec)
    }
}

fn load_scene(
    scene: &str,
    spacing: Option<f32>,
    sets: &[String],
    settle: Option<f32>,
    games: bool,
) -> Result<Scene, String> {
    if is_file(scene) && spacing.is_none() && sets.is_empty() && settle.is_none() && !games {
        // errors located in the file's text
        let path = Path::new(scene);
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        return SceneFile::check(&text, &path.display().to_string()).map_err(|e| e.to_string());
    }
    let mut spec = load_spec(scene, spacing, sets, games)?;
    if let Some(t) = settle {
        spec.settle = (t != 0.0).then_some(t);
    }
    spec.build().map_err(|e| e.to_string())
}

fn run(mut sc: Scene, o: RunOpts) -> Result<(), String> {
    if let Some(s) = o.seconds {
        if !(s.is_finite() && s > 0.0) {
            return Err(format!("--seconds must be a positive number, got {s}"));
        }
    }
    if o.surface && !cfg!(feature = "surface") {
        return Err("--surface needs the `surface` feature: cargo run --release --features surface -- run …".into());
    }
    // paths are checked before the run, not after it
    let create = |path: &Path| {
        std::fs::File::create(path)
            .map(|_| ())
            .map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    if let Some(p) = &o.report {
        create(p)?;
    }
    if let Some(p) = &o.snapshot {
        create(p)?;
    }
    let secs = o.seconds.unwrap_or(sc.seconds as f64);
    println!(
        "scene {}: {} fluid / {} solid carriers, Δx {} m, dt {} s, {} s simulated (from t = {:.4} s)",
        sc.name,
        sc.world.fluid().len(),
        sc.world.solid_carriers().len(),
        sc.world.params().spacing,
        sc.dt,
        secs,
        sc.world.time()
    );
    let changed = sc.world.params().changed_fields();
    if !changed.is_empty() {
        println!(
            "parameters changed from the defaults: {}",
            changed.join(", ")
        );
    }
    settle(&mut sc)?;
    let out = sc.spec.output.clone();
    let mut formats = match &o.formats {
        Some(list) => FrameFormats::parse(list).map_err(|e| e.to_string())?,
        None => FrameFormats {
            vtk: out.vtk,
            ply: out.ply,
            png: out.png,
            surface: out.surface,
        },
    };
    formats.surface |= o.surface;
    if formats.surface && !cfg!(feature = "surface") {
        if o.output.is_some() {
            println!("note: surface meshes skipped (built without the `surface` feature)");
        }
        formats.surface = false;
    }
    let mut frames = match &o.output {
        Some(dir) => {
            let opts = PreviewOptions {
                view: match o.view {
                    ViewArg::Side => View::Side,
                    ViewArg::Front => View::Front,
                    ViewArg::Top => View::Top,
                },
                color: match o.color {
                    ColorArg::Speed => ColorBy::Speed,
                    ColorArg::Pressure => ColorBy::Pressure,
                    ColorArg::Density => ColorBy::Density,
                },
                // speeds from 0 to the free-fall speed over the scene's height, the same in
                // every frame; pressures and densities from each frame's own range
                range: match o.color {
                    ColorArg::Speed => {
                        let height = sc
                            .world
                            .domain()
                            .map_or(1.0, |(lo, hi)| hi.y - lo.y)
                            .max(0.01);
                        Some((0.0, (2.0 * scenes::G * height).sqrt()))
                    }
                    _ => None,
                },
                title: sc.name.clone(),
                ..Default::default()
            };
            Some(
                FrameWriter::new(dir, formats)
                    .map_err(|e| e.to_string())?
                    .with_preview(opts),
            )
        }
        None => None,
    };
    let frame_every = ((1.0 / (out.frame_rate as f64 * sc.dt as f64)).round() as u64).max(1);
    let line_every = ((0.02 / sc.dt as f64).round() as u64).max(1);
    let total = (secs / sc.dt as f64).round().max(1.0) as u64;
    // a bar only on a terminal: logs and pipes get the per-frame lines alone
    let bar = if std::io::stderr().is_terminal() {
        ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr())
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} steps  {msg}  {per_sec}  ETA {eta}")
            .map_err(|e| e.to_string())?,
    );
    if let Some(f) = frames.as_mut() {
        f.write(&sc).map_err(|e| e.to_string())?;
    }
    let r = sc
        .run_with(secs, |s, rep| {
            bar.inc(1);
            bar.set_message(format!("t {:.3} s", rep.time));
            let k = rep.step;
            print_step(&bar, s, rep, !o.quiet && k % line_every == 0);
            if let Some(f) = frames.as_mut() {
                if k % frame_every == 0 {
                    f.write(s)?;
                }
            }
            Ok(())
        })
        .map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    summary(&r);
    let json = serde_json::to_string_pretty(&r).map_err(|e| e.to_string())?;
    let write = |path: &Path, bytes: &[u8]| {
        std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))
    };
    if let Some(path) = &o.report {
        write(path, json.as_bytes())?;
        println!("report written to {}", path.display());
    }
    if let (Some(dir), Some(f)) = (&o.output, &frames) {
        write(&dir.join("report.json"), json.as_bytes())?;
        plots(&r, dir).map_err(|e| e.to_string())?;
        println!(
            "{} frames, report.json and plots written to {}",
            f.frames(),
            dir.display()
        );
    }
    if let Some(path) = &o.snapshot {
        Snapshot::save(&sc, path).map_err(|e| e.to_string())?;
        println!(
            "snapshot written to {} (continue with `resume`)",
            path.display()
        );
    }
    Ok(())
}

/// PNG plots of the run: the scene's metric, E, PCG iterations, and tracked body heights.
fn plots(r: &RunReport, dir: &Path) -> staggered_fluid::Result<()> {
    let metric: Vec<(f64, f64)> = r.metric.iter().map(|s| (s.t, s.value)).collect();
    preview::write_plot(
        &dir.join("metric.png"),
        &format!("{}: {}", r.scene, r.metric_axis),
        &r.metric_axis,
        &[("metric", metric)],
    )?;
    let e: Vec<(f64, f64)> = r.steps_log.iter().map(|s| (s.t, 100.0 * s.error)).collect();
    let c: Vec<(f64, f64)> = r
        .steps_log
        .iter()
        .map(|s| (s.t, 100.0 * s.compression))
        .collect();
    preview::write_plot(
        &dir.join("error.png"),
        "incompressibility: velocity divergence E (Eq. 29) and mean compression",
        "%",
        &[("E", e), ("compression", c)],
    )?;
    let it: Vec<(f64, f64)> = r
        .steps_log
        .iter()
        .map(|s| (s.t, s.pcg_iterations as f64))
        .collect();
    preview::write_plot(
        &dir.join("pcg.png"),
        "PCG iterations per step",
        "iterations",
        &[("PCG", it)],
    )?;
    if !r.bodies.is_empty() {
        let series: Vec<(&str, Vec<(f64, f64)>)> = r
            .bodies
            .iter()
            .map(|b| {
                (
                    b.name.as_str(),
                    b.samples
                        .iter()
                        .map(|s| (s.t, s.position[1] as f64))
                        .collect(),
                )
            })
            .collect();
        preview::write_plot(
            &dir.join("bodies.png"),
            "tracked bodies: height of the centre of mass",
            "y, m",
            &series,
        )?;
    }
    Ok(())
}

fn check(files: &[PathBuf]) -> Result<(), String> {
    let mut failed = 0;
    for path in files {
        let result = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read: {e}", path.display()))
            .and_then(|text| {
                SceneFile::check(&text, &path.display().to_string()).map_err(|e| e.to_string())
            });
        match result {
            Ok(sc) => println!(
                "{}: ok ({}: {} fluid / {} solid carriers, {} bodies, {} emitters, {} s)",
                path.display(),
                sc.name,
                sc.world.fluid().len(),
                sc.world.solid_carriers().len(),
                sc.spec.bodies.len(),
                sc.emitters.len(),
                sc.seconds
            ),
            Err(e) => {
                eprintln!("{e}");
                failed += 1;
            }
        }
    }
    if failed > 0 {
        Err(format!("{failed} of {} file(s) failed", files.len()))
    } else {
        Ok(())
    }
}

/// The built-in scenes: name, what they show, their size and length.
fn list() -> Result<(), String> {
    let mut rows = Vec::new();
    for name in scenes::NAMES {
        let spec =
            scenes::spec_by_name(name, None, FluidParams::default()).map_err(|e| e.to_string())?;
        let sc = spec.build().map_err(|e| e.to_string())?;
        let fluid = if sc.emitters.is_empty() {
            sc.world.fluid().len().to_string()
        } else {
            format!("{} + emitters", sc.world.fluid().len())
        };
        rows.push(vec![
            name.to_string(),
            spec.description.clone(),
            format!("{}", spec.params.spacing),
            fluid,
            sc.world.solid_carriers().len().to_string(),
            format!("{}", spec.seconds),
        ]);
    }
    let mut t = table(
        &[
            "scene",
            "what it shows",
            "Δx, m",
            "fluid",
            "solid",
            "seconds",
        ]
        .map(String::from),
        &rows,
    );
    if let Some(c) = t.column_mut(1) {
        c.set_cell_alignment(CellAlignment::Left);
    }
    println!("{t}");
    println!("run one with `staggered-fluid run NAME`; write it as a file with `staggered-fluid export NAME`");
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => {
            load_scene("dam_break", None, &[], None, false).and_then(|s| run(s, RunOpts::default()))
        }
        Some(Command::Run {
            scene,
            spacing,
            set,
            settle,
            games,
            opts,
        }) => load_scene(&scene, spacing, &set, settle, games).and_then(|s| run(s, opts)),
        Some(Command::Resume { snapshot, opts }) => Snapshot::load(&snapshot)
            .and_then(|s| s.resume())
            .map_err(|e| e.to_string())
            .and_then(|s| run(s, opts)),
        Some(Command::Check { files }) => check(&files),
        Some(Command::List) => list(),
        Some(Command::Export {
            scene,
            spacing,
            set,
            games,
        }) => load_spec(&scene, spacing, &set, games).and_then(|spec| {
            // what `export` prints must run: it is built (and so checked) first
            spec.build().map_err(|e| e.to_string())?;
            print!("{}", spec.to_ron());
            Ok(())
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
