//! What the `staggered-fluid` binary prints: tables, run summaries, per-step lines.

use comfy_table::{presets::UTF8_FULL_CONDENSED, CellAlignment, ContentArrangement, Table};
use indicatif::ProgressBar;
use staggered_fluid::scenes::{Comparison, RunReport, Scene};
use staggered_fluid::{StageTimes, StepReport};

/// Lets the scene's water settle as it asks (`settle`), and says what that did.
pub(crate) fn settle(sc: &mut Scene) -> Result<(), String> {
    let settle = sc.spec.settle.unwrap_or_default();
    if let Some(r) = sc.settle().map_err(|e| e.to_string())? {
        println!(
            "settled {} s first ({} steps, {} substeps, {:.1} wall s): largest speed {:.3} m/s \
             and {:.3e} J cleared, compression {:.3} %",
            settle,
            r.steps,
            r.substeps,
            r.wall_seconds,
            r.final_speed,
            r.kinetic_energy_cleared,
            100.0 * r.compression_mean
        );
    }
    Ok(())
}

/// A table with the crate's look: condensed UTF-8 borders, numbers right-aligned.
pub(crate) fn table(header: &[String], rows: &[Vec<String>]) -> Table {
    let mut t = Table::new();
    t.load_preset(UTF8_FULL_CONDENSED)
        .set_content_arrangement(ContentArrangement::Dynamic)
        .set_width(110)
        .set_header(header);
    for r in rows {
        t.add_row(r);
    }
    for (k, col) in t.column_iter_mut().enumerate() {
        if k > 0 {
            col.set_cell_alignment(CellAlignment::Right);
        }
    }
    t
}

/// He 2012 Table 3's stage columns: seconds, share and µs per fluid particle-step.
pub(crate) fn stage_table(s: &StageTimes, particle_steps: f64) -> Table {
    let total = s.total().max(1e-12);
    let rows: Vec<Vec<String>> = [
        ("neighbours (t_neighbor)", s.neighbors),
        ("density constraint (t_p^d)", s.density),
        ("staggered particles (t_creating)", s.staggered),
        ("free surface (t_surface)", s.surface),
        ("assembly (t_assemble)", s.assembly),
        ("solve (t_solving)", s.solve),
        ("remap, smoothing, contact (other)", s.other),
        ("deformable bodies, heat, melting", s.deformable),
        ("step", s.total()),
    ]
    .iter()
    .map(|(name, t)| {
        vec![
            name.to_string(),
            format!("{t:.3}"),
            format!("{:.1}", 100.0 * t / total),
            format!("{:.3}", 1e6 * t / particle_steps.max(1.0)),
        ]
    })
    .collect();
    table(
        &["stage", "seconds", "share, %", "µs per particle-step"].map(String::from),
        &rows,
    )
}

pub(crate) fn print_comparison(c: &Comparison) {
    println!("against {}:", c.reference);
    if !c.rows.is_empty() {
        println!("{}", table(&c.columns, &c.rows));
    }
    println!("result: {}", c.verdict);
}

/// What the run cost and what it reached, against the scene's reference.
pub(crate) fn summary(r: &RunReport) {
    let particle_steps = 1e6 * r.stage_seconds.total() / r.us_per_particle_step.max(1e-12);
    println!(
        "done: {} steps, {:.3} s simulated in {:.2} s wall ({:.1} s per simulated s), {:.2} µs per particle-step",
        r.steps, r.simulated_seconds, r.wall_seconds, r.wall_per_simulated_second, r.us_per_particle_step
    );
    println!(
        "velocity divergence E (Eq. 29): mean {:.1e}, largest {:.1e}; density: mean compression {:.3} %, largest {:.2} %, {} steps beyond the tolerance; {:.1} PCG iterations a step",
        r.mean_error, r.max_error, 100.0 * r.mean_compression, 100.0 * r.max_compression, r.steps_off_density, r.mean_pcg_iterations
    );
    println!(
        "fluid: {} carriers at the end; emitted {}, sunk {}, removed outside the domain {}",
        r.n_fluid, r.emitted, r.sunk, r.removed_outside
    );
    println!("{}", stage_table(&r.stage_seconds, particle_steps));
    print_comparison(&r.comparison);
}

/// A step's warnings (on stderr) and, when `line`, its per-frame line.
pub(crate) fn print_step(bar: &ProgressBar, s: &Scene, rep: &StepReport, line: bool) {
    for w in &rep.warnings {
        bar.suspend(|| eprintln!("warning: step {} (t = {:.4} s): {w}", rep.step, rep.time));
    }
    if line {
        let m = s.metric_line(&s.sample());
        bar.suspend(|| {
            println!(
                "t {:7.4} s  E {:.1e}  compression {:.3} % (max {:.2} %)  PCG {:3}  substeps {:2}  vmax {:.3} m/s  fluid {}  {m}",
                rep.time, rep.error, 100.0 * rep.compression_mean, 100.0 * rep.compression_max, rep.pcg_iterations, rep.substeps, rep.max_speed, rep.n_fluid
            )
        });
    }
}
