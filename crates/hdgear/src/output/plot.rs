//! Rendering figures to SVG and PNG with plotters and the embedded DejaVu Sans font (no system
//! libraries, no system fonts). A [`Figure`] is plain data (panels of series, shaded intervals,
//! markers, or a categorical map); this module only turns it into bytes.

use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use serde::Serialize;
use std::path::Path;
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn ensure_font() {
    REGISTER.call_once(|| {
        // The font is compiled in and known to parse; a failure would only lose labels.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Colour-blind-safe palette (Okabe–Ito), used in order.
pub const PALETTE: [(u8, u8, u8); 8] = [
    (0, 114, 178),
    (213, 94, 0),
    (0, 158, 115),
    (204, 121, 167),
    (230, 159, 0),
    (86, 180, 233),
    (0, 0, 0),
    (240, 228, 66),
];

fn color(i: usize) -> RGBColor {
    let (r, g, b) = PALETTE[i % PALETTE.len()];
    RGBColor(r, g, b)
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Style {
    /// A line of width 2.
    Line,
    /// A thin line (width 1), for background curves.
    Thin,
    /// Dots.
    Points,
}

/// One data series of a panel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Series {
    /// Legend label (empty: no legend entry).
    pub label: String,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
    /// Palette index.
    pub color: usize,
    /// Drawing style.
    pub style: Style,
}

/// One chart.
#[derive(Clone, Debug, PartialEq, Serialize, Default)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Logarithmic x axis.
    pub x_log: bool,
    /// Logarithmic y axis.
    pub y_log: bool,
    /// x range (default: the data's).
    pub x_range: Option<(f64, f64)>,
    /// y range (default: the data's, padded 5 %).
    pub y_range: Option<(f64, f64)>,
    /// Data.
    pub series: Vec<Series>,
    /// Shaded x-intervals with their legend label and palette colour.
    pub shaded: Vec<(f64, f64, usize)>,
    /// Legend label of the shaded intervals.
    pub shaded_label: String,
    /// Vertical marker lines (x, label).
    pub vlines: Vec<(f64, String)>,
    /// Marked points (x, y, label).
    pub markers: Vec<(f64, f64, String)>,
    /// Legend in the upper left instead of the upper right.
    pub legend_left: bool,
}

/// A categorical map: cells coloured by category.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Map {
    /// The chart frame, labels and log flags (its series are drawn over the cells).
    pub frame: Panel,
    /// Cells (x0, x1, y0, y1, category index).
    pub cells: Vec<(f64, f64, f64, f64, usize)>,
    /// Category names, in index order (colour = palette index).
    pub categories: Vec<String>,
}

/// A figure: panels stacked vertically, or one map.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Figure {
    /// File stem, e.g. `xdot-gamma`.
    pub name: String,
    /// What the figure shows and what to see in it.
    pub caption: String,
    /// Pixel size (width, height).
    pub size: (u32, u32),
    /// Panels, stacked.
    pub panels: Vec<Panel>,
    /// Or a map (drawn instead of panels when present).
    pub map: Option<Map>,
}

fn data_range(p: &Panel, pick: impl Fn(&(f64, f64)) -> f64, log: bool) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for s in &p.series {
        for q in &s.points {
            let v = pick(q);
            if v.is_finite() && (!log || v > 0.0) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if !lo.is_finite() {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        (lo / 1.3, hi * 1.3)
    } else {
        let pad = if hi > lo {
            0.05 * (hi - lo)
        } else {
            0.5 * lo.abs().max(1.0)
        };
        (lo - pad, hi + pad)
    }
}

/// Tick labels: up to 4 significant digits, no "-0".
fn tick(v: f64) -> String {
    if v == 0.0 || v.abs() < 1e-12 {
        return "0".into();
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-3..5).contains(&mag) {
        return format!("{v:.1e}");
    }
    let decimals = (3 - mag).clamp(0, 6) as usize;
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".into() } else { s }
}

/// What drawing can fail with: plotters' error, kept as the source.
type DrawError = Box<dyn std::error::Error + Send + Sync>;

fn plot_err(figure: &str, source: DrawError) -> Error {
    Error::Plot {
        figure: figure.to_string(),
        source,
    }
}

/// Splits a polyline where it turns back on itself, keeping one point per pixel (`px` maps a
/// point to its pixel): plotters joins thick segments through their normals, and a zero-length
/// segment or a reversal (a spike narrower than a pixel, drawn up and down one pixel column)
/// loses segments.
fn pixel_pieces(
    points: &[(f64, f64)],
    px: impl Fn(&(f64, f64)) -> (i32, i32),
) -> Vec<Vec<(f64, f64)>> {
    let mut pieces: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    let mut px_prev: Option<(i32, i32)> = None;
    let mut dir_prev: Option<(f64, f64)> = None;
    for q in points
        .iter()
        .copied()
        .filter(|q| q.0.is_finite() && q.1.is_finite())
    {
        let at = px(&q);
        if px_prev == Some(at) {
            continue;
        }
        if let Some(pp) = px_prev {
            let d = (f64::from(at.0 - pp.0), f64::from(at.1 - pp.1));
            if let Some(dp) = dir_prev {
                let dot = d.0 * dp.0 + d.1 * dp.1;
                let norm = (d.0.hypot(d.1)) * (dp.0.hypot(dp.1));
                let last = pieces.last().and_then(|v| v.last()).copied();
                if let (true, Some(last)) = (dot < -0.5 * norm, last) {
                    pieces.push(vec![last]);
                }
            }
            dir_prev = Some(d);
        }
        if let Some(piece) = pieces.last_mut() {
            piece.push(q);
        }
        px_prev = Some(at);
    }
    pieces.retain(|v| !v.is_empty());
    pieces
}

/// Draws marked points, one shape and one legend entry per distinct label (red crosses, black
/// circles, alternately); true when it added a legend entry.
fn draw_markers<DB: DrawingBackend, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'_, DB, CT>,
    markers: &[(f64, f64, String)],
) -> std::result::Result<bool, DrawError>
where
    DB::ErrorType: 'static,
{
    // one legend entry and one shape per distinct label: red crosses, then black circles, …
    let mut kinds: Vec<&str> = Vec::new();
    for (x, y, label) in markers {
        let known = kinds.iter().position(|k| *k == label);
        let j = known.unwrap_or(kinds.len());
        if known.is_none() {
            kinds.push(label);
        }
        let first = known.is_none();
        if j % 2 == 0 {
            let c = RGBColor(200, 0, 0);
            let anno =
                chart.draw_series(std::iter::once(Cross::new((*x, *y), 7, c.stroke_width(2))))?;
            if first {
                anno.label(label.as_str())
                    .legend(move |(x, y)| Cross::new((x + 8, y), 6, c.stroke_width(2)));
            }
        } else {
            let c = RGBColor(0, 0, 0);
            let anno =
                chart.draw_series(std::iter::once(Circle::new((*x, *y), 6, c.stroke_width(2))))?;
            if first {
                anno.label(label.as_str())
                    .legend(move |(x, y)| Circle::new((x + 8, y), 5, c.stroke_width(2)));
            }
        }
    }
    Ok(!markers.is_empty())
}

/// Draws one series on `chart`; true when it added a legend entry.
fn draw_series<DB: DrawingBackend, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'_, DB, CT>,
    s: &Series,
) -> std::result::Result<bool, DrawError>
where
    DB::ErrorType: 'static,
{
    let c = color(s.color);
    let pieces = pixel_pieces(&s.points, |q| chart.as_coord_spec().translate(q));
    let mut labelled = false;
    for piece in pieces {
        let anno = match s.style {
            Style::Line | Style::Thin => {
                let w = if s.style == Style::Line { 2 } else { 1 };
                chart.draw_series(LineSeries::new(piece, c.stroke_width(w)))?
            }
            Style::Points => chart.draw_series(
                piece
                    .into_iter()
                    .map(move |q| Circle::new(q, 2, c.filled())),
            )?,
        };
        if !labelled && !s.label.is_empty() {
            anno.label(s.label.as_str()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(3))
            });
            labelled = true;
        }
    }
    Ok(labelled)
}

/// Draws a map's cells on `chart`, one legend entry per category; true when there was one.
fn draw_cells<DB: DrawingBackend, CT: CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'_, DB, CT>,
    m: &Map,
) -> std::result::Result<bool, DrawError>
where
    DB::ErrorType: 'static,
{
    for (i, name) in m.categories.iter().enumerate() {
        let c = color(i);
        let cells = m.cells.iter().filter(move |c| c.4 == i);
        chart
            .draw_series(cells.map(move |&(x0, x1, y0, y1, _)| {
                Rectangle::new([(x0, y0), (x1, y1)], c.mix(0.75).filled())
            }))?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 14, y + 6)], c.filled()));
    }
    Ok(!m.categories.is_empty())
}

#[allow(clippy::too_many_arguments)]
fn draw_chart<DB: DrawingBackend, X, Y>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
    map: Option<&Map>,
    xr: X,
    yr: Y,
    y_min: f64,
    y_max: f64,
) -> std::result::Result<(), DrawError>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
    DB::ErrorType: 'static,
{
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(46)
        .y_label_area_size(72)
        .build_cartesian_2d(xr, yr)?;
    chart
        .configure_mesh()
        .x_desc(p.x_label.as_str())
        .y_desc(p.y_label.as_str())
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .light_line_style(RGBColor(246, 246, 246))
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()?;
    let mut legend = false;
    if let Some(m) = map {
        legend |= draw_cells(&mut chart, m)?;
    }
    for (k, &(x0, x1, ci)) in p.shaded.iter().enumerate() {
        let c = color(ci);
        let anno = chart.draw_series(std::iter::once(Rectangle::new(
            [(x0, y_min), (x1, y_max)],
            c.mix(0.18).filled(),
        )))?;
        if k == 0 && !p.shaded_label.is_empty() {
            anno.label(p.shaded_label.as_str()).legend(move |(x, y)| {
                Rectangle::new([(x, y - 6), (x + 14, y + 6)], c.mix(0.3).filled())
            });
            legend = true;
        }
    }
    for s in &p.series {
        legend |= draw_series(&mut chart, s)?;
    }
    for (x, label) in &p.vlines {
        let c = RGBColor(90, 90, 90);
        chart
            .draw_series(LineSeries::new(
                vec![(*x, y_min), (*x, y_max)],
                c.stroke_width(1),
            ))?
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(1)));
        legend = true;
    }
    legend |= draw_markers(&mut chart, &p.markers)?;
    if legend {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .label_font(("sans-serif", 15))
            .position(if p.legend_left {
                SeriesLabelPosition::UpperLeft
            } else {
                SeriesLabelPosition::UpperRight
            })
            .draw()?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
    map: Option<&Map>,
) -> std::result::Result<(), DrawError>
where
    DB::ErrorType: 'static,
{
    let (x0, x1) = p.x_range.unwrap_or_else(|| data_range(p, |q| q.0, p.x_log));
    let (y0, y1) = p.y_range.unwrap_or_else(|| data_range(p, |q| q.1, p.y_log));
    match (p.x_log, p.y_log) {
        (false, false) => draw_chart(area, p, map, x0..x1, y0..y1, y0, y1),
        (true, false) => draw_chart(area, p, map, (x0..x1).log_scale(), y0..y1, y0, y1),
        (false, true) => draw_chart(area, p, map, x0..x1, (y0..y1).log_scale(), y0, y1),
        (true, true) => draw_chart(
            area,
            p,
            map,
            (x0..x1).log_scale(),
            (y0..y1).log_scale(),
            y0,
            y1,
        ),
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    f: &Figure,
) -> std::result::Result<(), DrawError>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    if let Some(m) = &f.map {
        draw_panel(&root, &m.frame, Some(m))?;
    } else {
        let areas = root.split_evenly((f.panels.len().max(1), 1));
        for (a, p) in areas.iter().zip(&f.panels) {
            draw_panel(a, p, None)?;
        }
    }
    Ok(root.present()?)
}

/// Renders a figure as an SVG document.
pub fn svg(f: &Figure) -> Result<String> {
    ensure_font();
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, f.size).into_drawing_area();
        draw(root, f).map_err(|e| plot_err(&f.name, e))?;
    }
    Ok(s)
}

/// Renders a figure as a PNG file at `path` (written to a temporary sibling, then renamed; the
/// temporary is removed on any failure and listed for removal on a signal).
pub fn png(f: &Figure, path: &Path) -> Result<()> {
    ensure_font();
    super::check_output_path(path)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}.png", std::process::id()));
    super::track_temporary(&tmp);
    // drawn in memory, then encoded: a failed write (a full disk) is the encoder's io::Error,
    // reported as such, not as the drawing library's debug form
    let (w, h) = f.size;
    let mut pixels = vec![0u8; 3 * w as usize * h as usize];
    let res = {
        let root = BitMapBackend::with_buffer(&mut pixels, f.size).into_drawing_area();
        draw(root, f)
    };
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let done = res
        .map_err(|e| io(std::io::Error::other(e)))
        .and_then(|()| {
            image::save_buffer_with_format(
                &tmp,
                &pixels,
                w,
                h,
                image::ColorType::Rgb8,
                image::ImageFormat::Png,
            )
            .map_err(|e| match e {
                image::ImageError::IoError(source) => io(source),
                other => io(std::io::Error::other(other)),
            })
        })
        .and_then(|()| std::fs::rename(&tmp, path).map_err(io));
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    super::untrack_temporary(&tmp);
    done
}

/// Writes a figure to `path`, SVG or PNG by extension.
pub fn write(f: &Figure, path: &Path) -> Result<()> {
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg") => super::write_atomic(path, svg(f)?.as_bytes()),
        Some("png") => png(f, path),
        _ => Err(Error::InvalidInput {
            what: "figure file",
            text: path.display().to_string(),
            reason: "the extension must be .svg or .png".into(),
        }),
    }
}
