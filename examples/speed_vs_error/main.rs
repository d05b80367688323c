//! Speed against error (issue 4): the staggered solver (He 2012) and the PCISPH solver (Shao
//! 2014) on the same scenes, at several solver tolerances and time steps. For every scene it
//! writes `DIR/<scene>.csv` and `DIR/<scene>.png` (wall seconds per simulated second on the
//! x-axis, error on the y-axis, one series per solver) and prints a markdown table.
//!
//! `cargo run --release --example speed_vs_error -- [DIR] [scene,scene…]` (default
//! `speed_vs_error/`, all scenes; `STEPS=1,3`, `TOLERANCES=0.01` and `SOLVERS=staggered,salva`
//! narrow the sweep; `PARAMS='{"relative_residual": 0.1}'` changes our solvers' base
//! parameters, and `CFL_FIXED=1` keeps the CFL limit at its default instead of scaling it with
//! the step);
//! with `--features salva` salva3d 0.11 (DFSPH) runs the same scenes as a third series;
//! `REPLOT=1` draws the plots again from the CSVs in DIR without running.
//!
//! Scenes and errors:
//! - `dam_break`: a = 0.1 m, 30 carriers across (Δx 3.33 mm, `DAM_ACROSS=20` for 5 mm), slab
//!   a fifth of that thick (6 carriers); error = the largest |Z − Z_MM|/Z_MM over Martin &
//!   Moyce's tabulated T ∈ [1, 3.3].
//! - `still_tank`: 0.4 × 0.4 m, 0.3 m deep, Δx 2 cm, 1 s from rest; error = the largest speed
//!   at the end over √(gH) (the floor force is printed too).
//! - `five_balls` (He 2012 Fig. 15, Δx 2 cm, 2 s): error = the mean over the two floating balls
//!   (550 and 775 kg/m³) of |d − h|/h, d their draft over the last 0.3 s below the waterline
//!   (median height of the top carrier of every Δx column whose centre is farther than 2R
//!   from every ball's, plus Δx/2), h Archimedes' draft of a sphere, π h² (3R − h)/3 = (ρ_b/ρ)(4/3)π R³.
//!   PCISPH runs once (tolerance 1 %, the scene's step).
//! - `wedge`: the Yettou et al. 2006 drop (`scenes::wedge_yettou`, Δx 2 cm, slab 4 carriers
//!   thick, 27 500 fluid carriers, 40 ms); error = the mean |v − v_exp|/v_exp over the
//!   measurements. PCISPH runs once (tolerance 1 %, the scene's step): it took 172 s and
//!   diverged in the one run made (the wedge thrown upward).
//!
//! Time steps: the scene's step, the CFL limit (default 0.4) and the body-force limit
//! (`FluidParams::body_force_limit`, default 0.2) all times 1, 2, 4 and 8; ×1 is
//! the default set-up (the PCISPH solver still substeps itself at CFL ≤ 0.1, see
//! `PCISPH_MAX_CFL`). A run that diverges (carriers thrown out of the domain, a wedge thrown
//! upward) is listed with its error message and left out of the plot.
use plotters::prelude::*;
use staggered_fluid::math::Vector;
use staggered_fluid::metrics::sphere_draft;
use staggered_fluid::{scenes, FluidParams, Solver};

#[cfg(feature = "salva")]
mod salva;

struct Point {
    solver: &'static str,
    tolerance: f32,
    dt: f32,
    wall_per_sim: f64,
    error: f64,
    note: String,
}

/// The dam break's resolution: (a, Δx, slab thickness in carriers) for `DAM_ACROSS` carriers
/// across the column (default 30, as `tests/dam_break.rs`).
fn dam_resolution() -> (f32, f32, usize) {
    let across: usize = std::env::var("DAM_ACROSS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(30);
    (0.1, 0.1 / across as f32, (across / 5).max(1))
}

fn dam_break(p: FluidParams, dt_factor: f32) -> Result<(f64, f64, f32, String), String> {
    let (a, dx, layers) = dam_resolution();
    let mut sc = scenes::dam_break(a, dx, layers, p).map_err(|e| e.to_string())?;
    sc.dt *= dt_factor;
    let scale = (2.0 * 9.81 / a as f64).sqrt();
    let r = sc.run(3.35 / scale, |_, _| {}).map_err(|e| e.to_string())?;
    lost(&sc)?;
    let err = scenes::martin_moyce_front()
        .into_iter()
        .filter(|(t, _)| (1.0..=3.3).contains(t))
        .map(|(t, z)| {
            let k = r
                .metric
                .iter()
                .position(|m| m.t >= t / scale)
                .unwrap_or(r.metric.len() - 1);
            ((r.metric[k].normalized - z) / z).abs()
        })
        .fold(0.0, f64::max);
    let note = format!(
        "{} carriers, {:.2} µs/particle-step, mean E {:.2} %",
        r.n_fluid,
        r.us_per_particle_step,
        100.0 * r.mean_error
    );
    Ok((r.wall_per_simulated_second, err, sc.dt, note))
}

fn still_tank(p: FluidParams, dt_factor: f32) -> Result<(f64, f64, f32, String), String> {
    let (side, height) = (0.4f32, 0.3f32);
    let mut sc = scenes::hydrostatic(side, height, 0.02, p).map_err(|e| e.to_string())?;
    sc.dt *= dt_factor;
    let r = sc.run(1.0, |_, _| {}).map_err(|e| e.to_string())?;
    lost(&sc)?;
    let vmax = sc
        .world
        .fluid()
        .v
        .iter()
        .map(|v| v.length())
        .fold(0.0f32, f32::max) as f64;
    let tail: Vec<f64> = r
        .metric
        .iter()
        .filter(|m| m.t >= 0.8 - 1e-9)
        .map(|m| m.normalized)
        .collect();
    let floor = tail.iter().sum::<f64>() / tail.len().max(1) as f64;
    let note = format!(
        "floor force {:.3} W, {:.2} µs/particle-step",
        floor, r.us_per_particle_step
    );
    Ok((
        r.wall_per_simulated_second,
        vmax / (9.81 * height as f64).sqrt(),
        sc.dt,
        note,
    ))
}

/// A run that threw carriers out of the domain has diverged: its error is not a measurement.
fn lost(sc: &scenes::Scene) -> Result<(), String> {
    match sc.world.removed_total() {
        0 => Ok(()),
        n => Err(format!(
            "diverged: {n} of {} carriers left the domain",
            n as usize + sc.world.fluid().len()
        )),
    }
}

fn wedge(p: FluidParams, dt_factor: f32) -> Result<(f64, f64, f32, String), String> {
    let mut sc = scenes::wedge_yettou(0.02, 4, p).map_err(|e| e.to_string())?;
    sc.dt *= dt_factor;
    if let Some(ph) = sc.physics.as_mut() {
        ph.integration_parameters.dt = sc.dt;
    }
    let r = sc.run(0.04, |_, _| {}).map_err(|e| e.to_string())?;
    lost(&sc)?;
    let sim: Vec<(f64, f64)> = r.bodies[0]
        .samples
        .iter()
        .map(|s| (s.t, -s.velocity[1] as f64))
        .collect();
    let v0 = scenes::YETTOU_2006.speed as f64;
    if sim.iter().any(|&(_, v)| !(0.0..=2.0 * v0).contains(&v)) {
        return Err("diverged: the wedge was thrown upward or sped up".into());
    }
    let at = |t: f64| {
        sim.iter()
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()))
            .map(|s| s.1)
            .unwrap_or(f64::NAN)
    };
    let exp = scenes::yettou_velocity();
    let dev = exp
        .iter()
        .map(|&(t, v)| ((at(t) - v) / v).abs())
        .sum::<f64>()
        / exp.len() as f64;
    let note = format!(
        "{} carriers, {:.2} µs/particle-step, v(40 ms) {:.3} m/s (measured 1.777)",
        r.n_fluid,
        r.us_per_particle_step,
        at(0.04)
    );
    Ok((r.wall_per_simulated_second, dev, sc.dt, note))
}

/// (scene, error name, run, PCISPH tolerances, PCISPH step factors)
type SceneCase<'a> = (&'a str, &'a str, SceneFn, &'a [f32], &'a [f32]);

/// Drafts of the first two balls (centres `centres`, radius `radius`) below the waterline
/// [`staggered_fluid::metrics::waterline`] of the Δx columns whose centre is farther than 2R
/// (horizontally) from every ball's.
///
/// Until 2026-11-26 (late) the test was per particle and at 3R. With five balls 0.2 m apart in
/// a 0.3 m wide tank almost no column lies 3R from every ball, so the "waterline" came from
/// 2–9 cells cut by that circle, where only the carriers that had drifted outside it counted:
/// at ×2 it read 0.05 m (the water was at 0.26 m) and reported the balls 13–16 cm above the
/// water. Whole columns at 2R give 240–330 columns.
fn ball_drafts(
    points: impl Iterator<Item = [f32; 3]>,
    centres: &[[f32; 3]],
    radius: f32,
    dx: f32,
) -> [f64; 2] {
    let avoid: Vec<Vector> = centres.iter().map(|c| Vector::from_array(*c)).collect();
    let level = staggered_fluid::metrics::waterline(
        points.map(Vector::from_array),
        &avoid,
        2.0 * radius,
        dx,
    )
    .unwrap_or(f32::NAN) as f64;
    [0, 1].map(|k| level - (centres[k][1] - radius) as f64)
}

fn five_balls(p: FluidParams, dt_factor: f32) -> Result<(f64, f64, f32, String), String> {
    let (dx, radius) = (0.02f32, 0.06f32);
    let mut sc = scenes::five_balls(dx, p).map_err(|e| e.to_string())?;
    sc.dt *= dt_factor;
    if let Some(ph) = sc.physics.as_mut() {
        ph.integration_parameters.dt = sc.dt;
    }
    let handles: Vec<_> = sc.tracked.iter().map(|t| t.1).collect();
    let mut drafts = [Vec::new(), Vec::new()];
    let r = sc
        .run(2.0, |s, _| {
            if s.world.time() < 1.7 {
                return;
            }
            let ph = s.physics.as_ref().expect("rapier world");
            let centres: Vec<_> = handles
                .iter()
                .map(|h| ph.bodies[*h].translation())
                .collect();
            let centres: Vec<[f32; 3]> = centres.iter().map(|c| c.to_array()).collect();
            let d = ball_drafts(
                s.world.fluid().x.iter().map(|x| x.to_array()),
                &centres,
                radius,
                dx,
            );
            for k in 0..2 {
                drafts[k].push(d[k]);
            }
        })
        .map_err(|e| e.to_string())?;
    lost(&sc)?;
    let mut errs = Vec::new();
    let mut notes = Vec::new();
    for (k, rho) in [550.0f64, 775.0].into_iter().enumerate() {
        let d = drafts[k].iter().sum::<f64>() / drafts[k].len().max(1) as f64;
        let h = sphere_draft(radius as f64, rho / 1000.0);
        errs.push(((d - h) / h).abs());
        // Archimedes in force form: the fluid force over the last 0.3 s against the weight
        let s = &r.bodies[k].samples;
        let t_end = s.last().map_or(0.0, |x| x.t);
        let tail: Vec<f32> = s
            .iter()
            .filter(|x| x.t >= t_end - 0.3 - 1e-9)
            .map(|x| x.fluid_force[1])
            .collect();
        let weight = rho * 4.0 / 3.0 * std::f64::consts::PI * (radius as f64).powi(3) * 9.81;
        let force = tail.iter().map(|&f| f as f64).sum::<f64>() / tail.len().max(1) as f64;
        notes.push(format!(
            "ρ {rho}: draft {:.1} mm vs {:.1} mm, fluid force {:.3} W",
            1e3 * d,
            1e3 * h,
            force / weight
        ));
    }
    let worst = r.metric.iter().map(|m| m.value).fold(0.0, f64::max);
    notes.push(format!("max carriers inside a ball {worst}"));
    Ok((
        r.wall_per_simulated_second,
        (errs[0] + errs[1]) / 2.0,
        sc.dt,
        notes.join(", "),
    ))
}

type SceneFn = fn(FluidParams, f32) -> Result<(f64, f64, f32, String), String>;

fn main() {
    let dir = std::path::PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "speed_vs_error".into()),
    );
    std::fs::create_dir_all(&dir).expect("output directory");
    plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        include_bytes!("../../assets/fonts/DejaVuSans.ttf"),
    )
    .map_err(|_| "font")
    .expect("bundled font");
    // PARAMS (a JSON object of FluidParams fields) changes the base parameters of both our
    // solvers, e.g. PARAMS='{"relative_residual": 0.1}'
    let base = FluidParams::default()
        .with_env_overrides("PARAMS")
        .expect("PARAMS: a JSON object of FluidParams fields");
    let cfl_fixed = std::env::var("CFL_FIXED").is_ok();
    // STEPS / TOLERANCES (comma lists) and SOLVERS (staggered,pcisph,salva) narrow a sweep
    let list = |var: &str, default: &[f32]| -> Vec<f32> {
        std::env::var(var).map_or(default.to_vec(), |v| {
            v.split(',').filter_map(|x| x.trim().parse().ok()).collect()
        })
    };
    let all = list("TOLERANCES", &[0.01, 0.003, 0.001]);
    let steps = list("STEPS", &[1.0, 2.0, 4.0, 8.0]);
    let solvers = std::env::var("SOLVERS").unwrap_or("staggered,pcisph,salva".into());
    let scenes: [SceneCase; 4] = [
        (
            "dam_break",
            "max |Z − Z_MM| / Z_MM (Martin & Moyce)",
            dam_break,
            &all,
            &steps,
        ),
        (
            "still_tank",
            "max speed after 1 s / √(gH)",
            still_tank,
            &all,
            &steps,
        ),
        (
            "five_balls",
            "mean |d − h| / h over the floating balls (Archimedes)",
            five_balls,
            &[0.01],
            &[1.0],
        ),
        (
            "wedge",
            "mean |v − v_exp| / v_exp (Yettou 2006)",
            wedge,
            &[0.01],
            &[1.0],
        ),
    ];
    let threads = rayon::current_num_threads();
    let only: Option<Vec<String>> = std::env::args()
        .nth(2)
        .map(|s| s.split(',').map(str::to_string).collect());
    for (name, error_name, run, pcisph_tols, pcisph_steps) in scenes {
        if only.as_ref().is_some_and(|o| !o.iter().any(|n| n == name)) {
            continue;
        }
        // REPLOT=1: draw the plot again from the CSV an earlier run wrote, without running
        if std::env::var("REPLOT").is_ok() {
            let points = read_csv(&dir.join(format!("{name}.csv")));
            plot(&dir.join(format!("{name}.png")), name, error_name, &points);
            continue;
        }
        let mut points = Vec::new();
        for (solver, label) in [(Solver::Staggered, "staggered"), (Solver::Pcisph, "PCISPH")] {
            if !solvers.contains(&label.to_lowercase()) {
                continue;
            }
            let (tols, factors) = match solver {
                Solver::Staggered => (&all[..], &steps[..]),
                Solver::Pcisph => (pcisph_tols, pcisph_steps),
            };
            for &tol in tols {
                for &dt_factor in factors {
                    let p = FluidParams {
                        solver,
                        density_error_tolerance: tol,
                        max_cfl: if cfl_fixed {
                            base.max_cfl
                        } else {
                            base.max_cfl * dt_factor
                        },
                        body_force_limit: base.body_force_limit * dt_factor,
                        ..base.clone()
                    };
                    match run(p, dt_factor) {
                        Ok((wall, err, dt, note)) => {
                            eprintln!(
                                "{name} {label} E {tol} dt {dt:.2e}: {wall:.1} s/s, error {:.2} %",
                                100.0 * err
                            );
                            points.push(Point {
                                solver: label,
                                tolerance: tol,
                                dt,
                                wall_per_sim: wall,
                                error: err,
                                note,
                            })
                        }
                        Err(e) => {
                            eprintln!("{name} {label} E {tol} ×{dt_factor}: {e}");
                            points.push(Point {
                                solver: label,
                                tolerance: tol,
                                dt: f32::NAN,
                                wall_per_sim: f64::NAN,
                                error: f64::NAN,
                                note: format!("step ×{dt_factor}: {e}"),
                            })
                        }
                    }
                }
            }
        }
        #[cfg(feature = "salva")]
        if solvers.contains("salva") {
            salva_points(name, &mut points);
        }
        write_csv(&dir.join(format!("{name}.csv")), &points);
        plot(&dir.join(format!("{name}.png")), name, error_name, &points);
        println!("\n### {name} ({threads} threads): error = {error_name}\n");
        println!("| solver | tolerance E | Δt s | wall s per simulated s | error % | notes |");
        println!("|---|---|---|---|---|---|");
        for p in &points {
            let tol = if p.tolerance.is_nan() {
                "its default".to_string()
            } else {
                format!("{:.1} %", 100.0 * p.tolerance)
            };
            println!(
                "| {} | {} | {:.2e} | {:.1} | {:.2} | {} |",
                p.solver,
                tol,
                p.dt,
                p.wall_per_sim,
                100.0 * p.error,
                p.note
            );
        }
    }
}

/// salva3d on the same scene at the scene's step times 1, 2 and 4 (its DFSPH tolerance is its
/// own default; the column says NaN).
/// A salva run at step dt: (wall s per simulated s, error, particles, particles out, note).
#[cfg(feature = "salva")]
type SalvaRun = fn(f32) -> (f64, f64, usize, usize, String);

#[cfg(feature = "salva")]
fn salva_points(name: &str, points: &mut Vec<Point>) {
    let (base, run): (f32, SalvaRun) = match name {
        "dam_break" => {
            let (a, dx, layers) = dam_resolution();
            (
                scenes::dam_break(a, dx, layers, Default::default())
                    .expect("scene")
                    .dt,
                salva::dam_break,
            )
        }
        "still_tank" => (
            scenes::hydrostatic(0.4, 0.3, 0.02, Default::default())
                .expect("scene")
                .dt,
            salva::still_tank,
        ),
        "five_balls" => (1.0 / 240.0, salva::five_balls),
        _ => (1e-3, salva::wedge),
    };
    for f in [1.0f32, 2.0, 4.0] {
        let dt = base * f;
        let (wall, err, n, out, extra) = run(dt);
        // as for our solvers, a run that lost particles (or threw the wedge) has diverged
        let (err, note) = if out > 0 || err.is_nan() {
            (
                f64::NAN,
                format!(
                    "diverged: {out} of {n} particles outside the tank (its error {:.0} %) {extra}",
                    100.0 * err
                ),
            )
        } else {
            (err, format!("{n} particles {extra}"))
        };
        eprintln!(
            "{name} salva dt {dt:.2e}: {wall:.1} s/s, error {:.2} % {note}",
            100.0 * err
        );
        points.push(Point {
            solver: "salva3d",
            tolerance: f32::NAN,
            dt,
            wall_per_sim: wall,
            error: err,
            note,
        });
    }
}

/// The points of a CSV [`write_csv`] wrote (notes dropped).
fn read_csv(path: &std::path::Path) -> Vec<Point> {
    let text = std::fs::read_to_string(path).expect("csv to replot");
    text.lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.splitn(6, ',').collect();
            let name = f.first()?.trim();
            let solver = ["staggered", "PCISPH", "salva3d"]
                .into_iter()
                .find(|s| *s == name)?;
            Some(Point {
                solver,
                tolerance: f.get(1)?.parse().ok()?,
                dt: f.get(2)?.parse().ok()?,
                wall_per_sim: f.get(3)?.parse().ok()?,
                error: f.get(4)?.parse().ok()?,
                note: String::new(),
            })
        })
        .collect()
}

fn write_csv(path: &std::path::Path, points: &[Point]) {
    let mut s = String::from("solver,tolerance,dt,wall_per_simulated_second,error,notes\n");
    for p in points {
        s += &format!(
            "{},{},{},{},{},\"{}\"\n",
            p.solver, p.tolerance, p.dt, p.wall_per_sim, p.error, p.note
        );
    }
    std::fs::write(path, s).expect("csv");
}

/// Ticks 1, 2, 5 × 10^k inside `[lo, hi]` (a log axis labelled across its whole range); on
/// a narrow axis every 1…9 × 10^k, and on a narrower one its ends at two digits.
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let pick = |mantissas: &[f64]| {
        let mut out = Vec::new();
        let mut decade = 10f64.powf(lo.log10().floor());
        while decade <= hi {
            for m in mantissas {
                let t = m * decade;
                if t >= lo && t <= hi {
                    out.push(t);
                }
            }
            decade *= 10.0;
        }
        out
    };
    let coarse = pick(&[1.0, 2.0, 5.0]);
    if coarse.len() >= 3 {
        return coarse;
    }
    let fine = pick(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
    if fine.len() >= 3 {
        return fine;
    }
    let two = |v: f64| {
        let p = 10f64.powf(v.log10().floor() - 1.0);
        (v / p).round() * p
    };
    let (a, b) = (two(lo * 1.02), two(hi / 1.02));
    let mut out = vec![a, (a * b).sqrt(), b];
    out.extend(fine);
    out.sort_by(|x, y| x.total_cmp(y));
    out.dedup_by(|x, y| (*x / *y - 1.0).abs() < 0.05);
    out
}

fn plot(path: &std::path::Path, name: &str, error_name: &str, points: &[Point]) {
    use plotters::coord::combinators::BindKeyPoints;
    let ok: Vec<&Point> = points.iter().filter(|p| p.error.is_finite()).collect();
    if ok.is_empty() {
        return;
    }
    let (x0, x1) = ok.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.wall_per_sim), b.max(p.wall_per_sim))
    });
    let (x0, x1) = (0.8 * x0, 1.25 * x1);
    let y1 = ok.iter().map(|p| 100.0 * p.error).fold(0.0f64, f64::max);
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE).expect("draw");
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{name}: speed against error"), ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(
            (x0..x1).log_scale().with_key_points(log_ticks(x0, x1)),
            0.0..1.15 * y1,
        )
        .expect("chart");
    chart
        .configure_mesh()
        .x_desc("wall seconds per simulated second (2 cores, log scale)")
        .y_desc(format!("{error_name}, %"))
        .x_label_formatter(&|v| {
            if *v >= 10.0 {
                format!("{v:.0}")
            } else {
                format!("{v:.1}")
            }
        })
        .label_style(("sans-serif", 14))
        .draw()
        .expect("mesh");
    // one line per solver and tolerance, joining its time steps (shortest first), so the
    // speed a longer step buys and the error it costs read along the line
    for (k, (label, color)) in [("staggered", BLUE), ("PCISPH", RED), ("salva3d", GREEN)]
        .into_iter()
        .enumerate()
    {
        let mut tols: Vec<f32> = ok
            .iter()
            .filter(|p| p.solver == label)
            .map(|p| p.tolerance)
            .collect();
        tols.sort_by(|a, b| a.total_cmp(b));
        tols.dedup_by(|a, b| a == b || (a.is_nan() && b.is_nan()));
        for (j, &tol) in tols.iter().enumerate() {
            let mut series: Vec<(f32, f64, f64)> = ok
                .iter()
                .filter(|p| {
                    p.solver == label
                        && (p.tolerance == tol || (p.tolerance.is_nan() && tol.is_nan()))
                })
                .map(|p| (p.dt, p.wall_per_sim, 100.0 * p.error))
                .collect();
            series.sort_by(|a, b| a.0.total_cmp(&b.0));
            let shade = color.mix(1.0 - 0.25 * j as f64);
            let name = if tol.is_nan() {
                label.to_string()
            } else {
                format!("{label}, E ≤ {} %", 100.0 * tol)
            };
            let line: Vec<(f64, f64)> = series.iter().map(|&(_, x, y)| (x, y)).collect();
            chart
                .draw_series(LineSeries::new(line.clone(), shade.stroke_width(2)))
                .expect("line")
                .label(name)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], shade.stroke_width(2))
                });
            chart
                .draw_series(
                    line.iter()
                        .map(|&(x, y)| Circle::new((x, y), 4 + k as i32, shade.filled())),
                )
                .expect("points");
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .expect("legend");
    root.present().expect("png");
}
