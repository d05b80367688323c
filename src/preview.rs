//! Pictures without a GPU or a viewer (plotters, bitmap backend, the bundled DejaVu Sans): a
//! PNG preview of a frame (side view, fluid coloured by speed, bodies outlined) and PNG line
//! plots of a run's metrics over time.

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::world::{FluidWorld, SolidKind};
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

/// The axis a preview looks along.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    /// Along −z: x to the right, y up (the default).
    #[default]
    Side,
    /// Along −x: z to the right, y up.
    Front,
    /// Down −y: x to the right, z up.
    Top,
}

/// What the fluid's colour shows in a preview.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ColorBy {
    /// Speed |v|, m/s (the default; from 0).
    #[default]
    Speed,
    /// Pressure p^d + p^v, Pa.
    Pressure,
    /// SPH density (Eq. 22), kg/m³.
    Density,
}

impl ColorBy {
    /// The field's name and unit, for the colour bar.
    pub fn label(self) -> &'static str {
        match self {
            ColorBy::Speed => "speed, m/s",
            ColorBy::Pressure => "pressure, Pa",
            ColorBy::Density => "density, kg/m³",
        }
    }
}

/// How [`write_preview`] draws a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct PreviewOptions {
    /// Image width, pixels.
    pub width: u32,
    /// The axis the picture looks along.
    pub view: View,
    /// What the fluid's colour shows.
    pub color: ColorBy,
    /// Colour range `(low, high)` in the field's unit; `None`: the frame's own range (speed
    /// from 0). Give a range to compare frames.
    pub range: Option<(f32, f32)>,
    /// Shown in the corner before the time and the fluid count.
    pub title: String,
}

impl Default for PreviewOptions {
    fn default() -> Self {
        Self {
            width: 800,
            view: View::Side,
            color: ColorBy::Speed,
            range: None,
            title: String::new(),
        }
    }
}

/// Room on the right of a preview for the colour bar, pixels.
const BAR_ROOM: u32 = 110;

/// Writes a picture of `world` (fluid carriers coloured by `opts.color` on a blue → red ramp,
/// walls light grey, moving solids as dark rings on top) seen along `opts.view`, with a
/// colour bar in the field's unit and the time and fluid count in the corner.
///
/// ```
/// use staggered_fluid::preview::{write_preview, ColorBy, PreviewOptions, View};
/// use staggered_fluid::prelude::*;
/// let mut world = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
/// world.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip)?;
/// world.add_block(Vector::ZERO, Vector::new(0.25, 0.4, 0.5), Vector::ZERO)?;
/// world.step(Vector::new(0.0, -9.81, 0.0), 0.01)?;
/// let path = std::env::temp_dir().join("staggered_fluid_preview_doc.png");
/// let opts = PreviewOptions { view: View::Top, color: ColorBy::Pressure, ..Default::default() };
/// write_preview(&world, &path, &opts)?;
/// assert!(path.exists());
/// # std::fs::remove_file(&path).ok();
/// # Ok::<(), FluidError>(())
/// ```
pub fn write_preview(world: &FluidWorld, path: &Path, opts: &PreviewOptions) -> Result<()> {
    font();
    let w = world.solid_carriers();
    let f = world.fluid();
    // screen axes (u right, v up) and the depth axis toward the viewer
    let (ua, va, da) = match opts.view {
        View::Side => (0usize, 1usize, 2usize),
        View::Front => (2, 1, 0),
        View::Top => (0, 2, 1),
    };
    let (mut lo, mut hi) = ([f32::INFINITY; 2], [f32::NEG_INFINITY; 2]);
    for p in f.x.iter().chain(w.x.iter()) {
        for (k, v) in [p[ua], p[va]].into_iter().enumerate() {
            lo[k] = lo[k].min(v);
            hi[k] = hi[k].max(v);
        }
    }
    if !(lo[0].is_finite() && hi[0] > lo[0] && hi[1] > lo[1]) {
        lo = [0.0, 0.0];
        hi = [1.0, 1.0];
    }
    let width = opts.width.max(BAR_ROOM + 100);
    let plot_w = width - BAR_ROOM;
    let scale = (plot_w as f32 - 20.0) / (hi[0] - lo[0]).max(1e-6);
    let height = (((hi[1] - lo[1]) * scale) as u32 + 40).clamp(200, 4 * width);
    let root = BitMapBackend::new(path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| draw_err(path, e))?;
    let px = |p: Vector| -> (i32, i32) {
        (
            (10.0 + (p[ua] - lo[0]) * scale) as i32,
            (height as f32 - 10.0 - (p[va] - lo[1]) * scale) as i32,
        )
    };
    let dot = (0.5 * world.params().spacing * scale).clamp(1.0, 6.0) as i32;
    // the coloured field and its range
    let value = |i: usize| match opts.color {
        ColorBy::Speed => f.v[i].length(),
        ColorBy::Pressure => f.p_density[i] + f.p_velocity[i],
        ColorBy::Density => f.density[i],
    };
    let (c0, c1) = opts.range.unwrap_or_else(|| {
        let (a, b) = (0..f.len())
            .map(value)
            .filter(|v| v.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let a = if opts.color == ColorBy::Speed { 0.0 } else { a };
        if a.is_finite() && b > a {
            (a, b)
        } else if a.is_finite() {
            (a, a + 1.0)
        } else {
            (0.0, 1.0)
        }
    });
    let solids = world.solids();
    // walls first, then the fluid back to front, then the bodies' carriers as rings on top, so
    // bodies under water stay visible
    let mut bodies = Vec::new();
    for (i, p) in w.x.iter().enumerate() {
        let s = &solids[w.body[i] as usize];
        if s.kind != SolidKind::Static {
            bodies.push(*p);
            continue;
        }
        // walls facing the viewer would hide the water: only their edges are drawn
        if w.n[i][da].abs() >= 0.7 {
            continue;
        }
        root.draw(&Circle::new(px(*p), dot, RGBColor(200, 200, 200).filled()))
            .map_err(|e| draw_err(path, e))?;
    }
    let mut order: Vec<usize> = (0..f.len()).collect();
    order.sort_by(|a, b| f.x[*a][da].total_cmp(&f.x[*b][da]));
    for i in order {
        let c = ramp((value(i) - c0) / (c1 - c0));
        root.draw(&Circle::new(px(f.x[i]), dot, c.filled()))
            .map_err(|e| draw_err(path, e))?;
    }
    for p in bodies {
        root.draw(&Circle::new(
            px(p),
            dot,
            RGBColor(40, 40, 40).stroke_width(1),
        ))
        .map_err(|e| draw_err(path, e))?;
    }
    let view = match opts.view {
        View::Side => "side view (x →, y ↑)",
        View::Front => "front view (z →, y ↑)",
        View::Top => "top view (x →, z ↑)",
    };
    let sep = if opts.title.is_empty() { "" } else { "  " };
    root.draw(&Text::new(
        format!(
            "{}{sep}t = {:.3} s  {} fluid  {view}",
            opts.title,
            world.time(),
            f.len()
        ),
        (8, 6),
        ("sans-serif", 16).into_font().color(&BLACK),
    ))
    .map_err(|e| draw_err(path, e))?;
    colour_bar(
        &root,
        path,
        (plot_w + 20, 40),
        height.saturating_sub(80).max(60),
        (c0, c1),
        opts.color.label(),
    )?;
    root.present().map_err(|e| draw_err(path, e))
}

/// A vertical colour bar at `at` (top left), `len` pixels tall, labelled with the range's ends
/// and middle and the field's name and unit.
fn colour_bar(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    path: &Path,
    at: (u32, u32),
    len: u32,
    (c0, c1): (f32, f32),
    label: &str,
) -> Result<()> {
    let (x, y) = (at.0 as i32, at.1 as i32);
    for k in 0..len as i32 {
        let s = 1.0 - k as f32 / (len as f32 - 1.0).max(1.0);
        root.draw(&Rectangle::new(
            [(x, y + k), (x + 18, y + k + 1)],
            ramp(s).filled(),
        ))
        .map_err(|e| draw_err(path, e))?;
    }
    let text = ("sans-serif", 13).into_font().color(&BLACK);
    for (s, v) in [(0.0f32, c1), (0.5, 0.5 * (c0 + c1)), (1.0, c0)] {
        let ty = y + (s * (len as f32 - 1.0)) as i32 - 6;
        root.draw(&Text::new(tick(v), (x + 22, ty), text.clone()))
            .map_err(|e| draw_err(path, e))?;
    }
    root.draw(&Text::new(label.to_string(), (x - 10, y - 22), text))
        .map_err(|e| draw_err(path, e))?;
    Ok(())
}

/// An axis label with as many decimals as the axis span needs (so ticks 0.1 apart on an axis
/// near 1 read 0.9, 1.0, 1.1, not 1, 1, 1), in scientific form for very large or small values.
fn axis_label(v: f64, span: f64) -> String {
    let a = v.abs().max(span);
    if a != 0.0 && !(1e-3..1e5).contains(&a) {
        return format!("{v:.2e}");
    }
    let decimals = (1.0 - (span / 10.0).log10().floor()).clamp(0.0, 6.0) as usize;
    let s = format!("{v:.decimals$}");
    // no "-0.0"
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// A number with as many digits as its size needs (`0.5`, `12.3`, `1.2e4`).
fn tick(v: f32) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-2..1e4).contains(&a) {
        format!("{v:.1e}")
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
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
    // a flat series still gets a readable axis: ± half its size (or ± 0.5) around it
    if y1 - y0 <= 1e-9 * y1.abs().max(1.0) {
        let half = (0.5 * y1.abs()).max(0.5);
        (y0, y1) = (y0 - half, y1 + half);
    }
    let pad = 0.05 * (y1 - y0);
    let (y0, y1) = (y0 - pad, y1 + pad);
    let span = y1 - y0;
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
        .y_label_formatter(&|v| axis_label(*v, span))
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
