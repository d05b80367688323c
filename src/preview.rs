//! Pictures without a GPU or a viewer (plotters, bitmap backend, the bundled DejaVu Sans): a
//! PNG preview of a frame (side view, fluid coloured by speed, bodies outlined) and PNG line
//! plots of a run's metrics over time.

use crate::error::{FluidError, Result};
use crate::scenes::Scene;
use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;

fn draw_err(path: &Path, e: impl std::fmt::Debug) -> FluidError {
    FluidError::Io {
        path: path.display().to_string(),
        message: format!("{e:?}"),
    }
}

/// Registers the bundled font once (plotters' ab_glyph text needs it; no system fontconfig).
fn font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // the font is compiled in: registering it cannot fail on well-formed bytes
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            include_bytes!("../assets/fonts/DejaVuSans.ttf"),
        );
    });
}

/// Blue → cyan → yellow → red as `s` goes 0 → 1.
fn ramp(s: f32) -> RGBColor {
    let s = s.clamp(0.0, 1.0);
    let (r, g, b) = if s < 1.0 / 3.0 {
        let t = 3.0 * s;
        (0.1, 0.3 + 0.6 * t, 0.9)
    } else if s < 2.0 / 3.0 {
        let t = 3.0 * s - 1.0;
        (0.1 + 0.85 * t, 0.9, 0.9 - 0.8 * t)
    } else {
        let t = 3.0 * s - 2.0;
        (0.95, 0.9 - 0.75 * t, 0.1)
    };
    RGBColor((255.0 * r) as u8, (255.0 * g) as u8, (255.0 * b) as u8)
}

/// Writes a side view (x right, y up) of `scene` at `width` pixels wide: fluid carriers
/// coloured by speed from 0 (blue) to `speed_scale` (red), walls light grey, moving solids
/// dark grey; the time and the fluid count in the corner.
pub fn write_preview(scene: &Scene, path: &Path, width: u32, speed_scale: f32) -> Result<()> {
    font();
    let w = scene.world.solid_carriers();
    let f = scene.world.fluid();
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for p in f.x.iter().chain(w.x.iter()) {
        for (k, v) in [p.x, p.y].into_iter().enumerate() {
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    if !(lo[0].is_finite() && hi[0] > lo[0] && hi[1] > lo[1]) {
        lo = [0.0, 0.0];
        hi = [1.0, 1.0];
    }
    let scale = (width as f32 - 20.0) / (hi[0] - lo[0]).max(1e-6);
    let height = (((hi[1] - lo[1]) * scale) as u32 + 40).clamp(60, 4 * width);
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let px = |x: f32, y: f32| -> (i32, i32) {
        (
            (10.0 + (x - lo[0]) * scale) as i32,
            (height as f32 - 10.0 - (y - lo[1]) * scale) as i32,
        )
    };
    let dot = (0.5 * scene.world.params().spacing * scale).clamp(1.0, 6.0) as i32;
    let solids = scene.world.solids();
    // walls first, then the water back to front in z, then the bodies' carriers as rings on
    // top, so bodies under water stay visible
    let mut bodies = Vec::new();
    for (i, p) in w.x.iter().enumerate() {
        let s = &solids[w.body[i] as usize];
        if s.collider.is_some() {
            bodies.push(*p);
            continue;
        }
        // tank walls facing the viewer would hide the water: only their edges are drawn
        if w.n[i].z.abs() >= 0.7 {
            continue;
        }
        root.draw(&Circle::new(
            px(p.x, p.y),
            dot,
            RGBColor(200, 200, 200).filled(),
        ))
        .map_err(|e| draw_err(path, e))?;
    }
    let mut order: Vec<usize> = (0..f.len()).collect();
    order.sort_by(|a, b| f.x[*a].z.total_cmp(&f.x[*b].z));
    for i in order {
        let (p, v) = (f.x[i], f.v[i]);
        let c = ramp(v.length() / speed_scale.max(1e-6));
        root.draw(&Circle::new(px(p.x, p.y), dot, c.filled()))
            .map_err(|e| draw_err(path, e))?;
    }
    for p in bodies {
        root.draw(&Circle::new(
            px(p.x, p.y),
            dot,
            RGBColor(40, 40, 40).stroke_width(1),
        ))
        .map_err(|e| draw_err(path, e))?;
    }
    root.draw(&Text::new(
        format!(
            "{}  t = {:.3} s  {} fluid",
            scene.name,
            scene.world.time(),
            f.len()
        ),
        (8, 6),
        ("sans-serif", 16).into_font().color(&BLACK),
    ))
    .map_err(|e| draw_err(path, e))?;
    root.present().map_err(|e| draw_err(path, e))
}

/// A named series of `(x, y)` points.
pub type Series<'a> = (&'a str, Vec<(f64, f64)>);

/// Writes a PNG line plot of one or more series against time.
pub fn write_plot(path: &Path, title: &str, y_label: &str, series: &[Series]) -> Result<()> {
    font();
    let pts = series
        .iter()
        .flat_map(|s| s.1.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !(x0.is_finite() && y0.is_finite()) {
        return Ok(());
    }
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    let pad = 0.05 * (y1 - y0).max(1e-9 * y1.abs().max(1.0));
    let (y0, y1) = (y0 - pad, y1 + pad);
    let root = BitMapBackend::new(path, (800, 500)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(|e| draw_err(path, e))?;
    chart
        .configure_mesh()
        .x_desc("simulated time, s")
        .y_desc(y_label)
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| draw_err(path, e))?;
    for (k, (name, s)) in series.iter().enumerate() {
        let c = Palette99::pick(k).to_rgba();
        chart
            .draw_series(LineSeries::new(s.iter().copied(), c.stroke_width(2)))
            .map_err(|e| draw_err(path, e))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
    }
    if series.len() > 1 {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()
            .map_err(|e| draw_err(path, e))?;
    }
    root.present().map_err(|e| draw_err(path, e))
}
