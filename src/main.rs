//! `staggered-fluid`: runs a built-in scene or a scene file end to end, with a progress bar,
//! per-frame lines, frames (VTK, PLY, PNG, surface meshes), a JSON report and plots; checks
//! scene files; resumes from snapshots.

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use staggered_fluid::frames::FrameWriter;
use staggered_fluid::scenes::SceneFile;
use staggered_fluid::scenes::{self, RunReport, Scene};
use staggered_fluid::snapshot::Snapshot;
use staggered_fluid::{preview, FluidParams};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "staggered-fluid",
    version,
    about = "He 2012 staggered meshless SPH fluid for rapier3d worlds"
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
    /// List the built-in scenes.
    List,
    /// Print a built-in scene as a scene file (RON) to start your own from.
    Export {
        /// Built-in scene name.
        scene: String,
        /// Particle spacing in metres (default: the scene's own).
        #[arg(long)]
        spacing: Option<f32>,
    },
}

#[derive(Args)]
struct RunOpts {
    /// Simulated seconds (default: the scene's own duration).
    #[arg(long)]
    seconds: Option<f64>,
    /// Write frames (as the scene's `output` section says), the report and plots here.
    #[arg(long)]
    output: Option<PathBuf>,
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

fn load_scene(scene: &str, spacing: Option<f32>) -> Result<Scene, String> {
    let path = Path::new(scene);
    let is_file = path.extension().is_some_and(|e| e == "ron" || e == "json") || path.exists();
    if is_file {
        if spacing.is_some() {
            return Err(
                "--spacing applies to built-in scenes; set `params.spacing` in the file".into(),
            );
        }
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        SceneFile::check(&text, &path.display().to_string()).map_err(|e| e.to_string())
    } else {
        scenes::by_name(scene, spacing).map_err(|e| e.to_string())
    }
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
    let secs = o.seconds.unwrap_or(sc.seconds as f64);
    println!(
        "scene {}: {} fluid / {} solid carriers, dt {} s, {} s simulated (from t = {:.4} s)",
        sc.name,
        sc.world.fluid().len(),
        sc.world.solid_carriers().len(),
        sc.dt,
        secs,
        sc.world.time()
    );
    let out = sc.spec.output.clone();
    // the scene file may ask for surface meshes too; without the feature that is a note, not
    // an error (the flag on the command line is an error, above)
    let surface = (o.surface || out.surface) && cfg!(feature = "surface");
    if out.surface && !cfg!(feature = "surface") && o.output.is_some() {
        println!("note: surface meshes skipped (built without the `surface` feature)");
    }
    let mut frames = match &o.output {
        Some(dir) => Some(FrameWriter::new(dir, out.vtk, out.ply).map_err(|e| e.to_string())?),
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
    // speeds in the previews run from 0 to the free-fall speed over the scene's height
    let height = sc
        .world
        .domain()
        .map_or(1.0, |(lo, hi)| hi.y - lo.y)
        .max(0.01);
    let speed_scale = (2.0 * scenes::G * height).sqrt();
    let write_frame = |s: &Scene, frames: &mut FrameWriter| -> staggered_fluid::Result<()> {
        let k = frames.write(s)?;
        if out.png {
            preview::write_preview(s, &frames.path("preview", k, "png"), 800, speed_scale)?;
        }
        if surface {
            surface_frame(s, &frames.path("surface", k, "obj"))?;
        }
        Ok(())
    };
    if let Some(f) = frames.as_mut() {
        write_frame(&sc, f).map_err(|e| e.to_string())?;
    }
    let r = sc
        .run_with(secs, |s, rep| {
            bar.inc(1);
            bar.set_message(format!("t {:.3} s", rep.time));
            let k = rep.step;
            if !o.quiet && k % line_every == 0 {
                let m = s.sample();
                bar.suspend(|| {
                    println!(
                        "t {:7.4} s  E {:.2e}  compression {:.3} % (max {:.2} %)  pcg {:3}  surface {:6}  fluid {:7}  vmax {:6.3} m/s  metric {:.4} ({:.4})",
                        rep.time, rep.error, 100.0 * rep.compression_mean, 100.0 * rep.compression_max, rep.pcg_iterations, rep.n_surface, rep.n_fluid, rep.max_speed, m.value, m.normalized
                    )
                });
            }
            if let Some(f) = frames.as_mut() {
                if k % frame_every == 0 {
                    write_frame(s, f)?;
                }
            }
            Ok(())
        })
        .map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    println!(
        "done: {} steps, {:.2} s wall ({:.1} s per simulated s), {:.2} us per particle-step, mean E {:.2e}, mean compression {:.3} % (max {:.2} %, {} steps beyond the density tolerance), mean PCG {:.1}, emitted {}, sunk {}, removed outside {}",
        r.steps, r.wall_seconds, r.wall_per_simulated_second, r.us_per_particle_step, r.mean_error, 100.0 * r.mean_compression, 100.0 * r.max_compression, r.steps_off_density, r.mean_pcg_iterations, r.emitted, r.sunk, r.removed_outside
    );
    println!("stages (s): {:?}", r.stage_seconds);
    println!("comparison: {}", r.comparison);
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
    let metric: Vec<(f64, f64)> = r.metric.iter().map(|s| (s.t, s.normalized)).collect();
    preview::write_plot(
        &dir.join("metric.png"),
        &format!("{}: {}", r.scene, r.metric_name),
        "normalized",
        &[("metric", metric)],
    )?;
    let e: Vec<(f64, f64)> = r.steps_log.iter().map(|s| (s.t, 100.0 * s.error)).collect();
    preview::write_plot(
        &dir.join("error.png"),
        "incompressibility error E (Eq. 29)",
        "E, %",
        &[("E", e)],
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

#[cfg(feature = "surface")]
fn surface_frame(s: &Scene, path: &Path) -> staggered_fluid::Result<()> {
    staggered_fluid::surface::write_obj(&s.world, path)
}

#[cfg(not(feature = "surface"))]
fn surface_frame(_: &Scene, _: &Path) -> staggered_fluid::Result<()> {
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let defaults = RunOpts {
        seconds: None,
        output: None,
        report: None,
        surface: false,
        snapshot: None,
        quiet: false,
    };
    let result = match cli.command {
        None => load_scene("dam_break", None).and_then(|s| run(s, defaults)),
        Some(Command::Run {
            scene,
            spacing,
            opts,
        }) => load_scene(&scene, spacing).and_then(|s| run(s, opts)),
        Some(Command::Resume { snapshot, opts }) => Snapshot::load(&snapshot)
            .and_then(|s| s.resume())
            .map_err(|e| e.to_string())
            .and_then(|s| run(s, opts)),
        Some(Command::Check { files }) => check(&files),
        Some(Command::List) => {
            for n in scenes::NAMES {
                println!("{n}");
            }
            Ok(())
        }
        Some(Command::Export { scene, spacing }) => {
            scenes::spec_by_name(&scene, spacing, FluidParams::default())
                .map(|s| print!("{}", s.to_ron()))
                .map_err(|e| e.to_string())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
