//! The drawing primitives of every figure: panels of curves (linear or logarithmic axes, a
//! legend, a reference curve dashed grey) stacked in a PNG, with the bundled DejaVu font.

use plotters::coord::Shift;
use plotters::prelude::*;
use pvfc_sim::error::{Result, SimError};
use std::path::Path;
use std::sync::Once;

static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");
static REGISTER: Once = Once::new();

fn register_font() {
    REGISTER.call_once(|| {
        // The bytes are a valid TTF shipped with the crate; if registering ever failed, text
        // would be missing from the figures, which the figure tests would show.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(23, 190, 207),
    RGBColor(188, 189, 34),
];

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A curve through the points in order, in the next colour.
    Line,
    /// Dashed grey, a reference (the desired contour).
    Reference,
    /// A marker at each point and no line: one marker per run, for points whose order means
    /// nothing (a run's speed against its accuracy).
    Markers,
}

/// One curve of a panel.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// The points.
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub style: Style,
}

fn bounds(series: &[Series], log_y: bool) -> ((f64, f64), (f64, f64)) {
    let pts = series.iter().flat_map(|s| s.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        if !(x.is_finite() && y.is_finite()) || (log_y && y <= 0.0) {
            continue;
        }
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        return ((0.0, 1.0), (if log_y { 1e-9 } else { 0.0 }, 1.0));
    }
    let pad = |a: f64, b: f64| {
        let d = (b - a).abs().max(1e-9) * 0.05;
        (a - d, b + d)
    };
    let y = if log_y {
        (y0 * 0.7, y1 * 1.4)
    } else {
        pad(y0, y1)
    };
    (pad(x0, x1), y)
}

/// A panel to draw on.
pub(crate) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

fn err(path: &Path, e: impl std::fmt::Display) -> SimError {
    SimError::Plot {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Draws one panel.
pub fn panel(
    area: &Area<'_>,
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_y: bool,
) -> Result<()> {
    let ((x0, x1), (y0, y1)) = bounds(series, log_y);
    let mut builder = ChartBuilder::on(area);
    builder
        .caption(title, ("sans-serif", 18))
        .margin(8)
        .x_label_area_size(38)
        .y_label_area_size(70);
    let mut k = 0;
    macro_rules! draw {
        ($chart:expr) => {{
            let mut chart = $chart;
            let log_fmt = |y: &f64| format!("{y:.0e}");
            // A range under 0.01 (an audit residual of 1e-14 J) in scientific notation: three
            // decimals would print every tick as "0".
            let tiny = (y1 - y0).abs() < 1e-2;
            let lin_fmt = |y: &f64| {
                if tiny && *y != 0.0 {
                    format!("{y:.1e}")
                } else {
                    format!("{y:.3}")
                        .trim_end_matches('0')
                        .trim_end_matches('.')
                        .to_string()
                }
            };
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .y_label_formatter(if log_y { &log_fmt } else { &lin_fmt })
                .label_style(("sans-serif", 13))
                .draw()
                .map_err(|e| err(path, e))?;
            for s in series {
                let pts = s
                    .points
                    .iter()
                    .cloned()
                    .filter(|(x, y)| x.is_finite() && y.is_finite() && (!log_y || *y > 0.0));
                match s.style {
                    Style::Reference => {
                        let style = ShapeStyle::from(&RGBColor(120, 120, 120)).stroke_width(1);
                        let drawn = chart
                            .draw_series(DashedLineSeries::new(pts, 6, 4, style))
                            .map_err(|e| err(path, e))?;
                        if !s.label.is_empty() {
                            drawn.label(s.label.clone()).legend(|(x, y)| {
                                PathElement::new(vec![(x, y), (x + 18, y)], RGBColor(120, 120, 120))
                            });
                        }
                    }
                    Style::Line => {
                        let c = COLORS[k % COLORS.len()];
                        k += 1;
                        chart
                            .draw_series(LineSeries::new(pts, c.stroke_width(2)))
                            .map_err(|e| err(path, e))?
                            .label(s.label.clone())
                            .legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                            });
                    }
                    Style::Markers => {
                        let c = COLORS[k % COLORS.len()];
                        k += 1;
                        chart
                            .draw_series(pts.map(|p| Circle::new(p, 4, c.filled())))
                            .map_err(|e| err(path, e))?
                            .label(s.label.clone())
                            .legend(move |(x, y)| Circle::new((x + 9, y), 4, c.filled()));
                    }
                }
            }
            if series.len() > 1 {
                chart
                    .configure_series_labels()
                    .label_font(("sans-serif", 13))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .position(SeriesLabelPosition::UpperRight)
                    .draw()
                    .map_err(|e| err(path, e))?;
            }
        }};
    }
    if log_y {
        draw!(builder
            .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
            .map_err(|e| err(path, e))?);
    } else {
        draw!(builder
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(path, e))?);
    }
    Ok(())
}

/// A figure of `rows` panels stacked vertically, drawn by `draw(panel_index, area)`.
pub fn figure(
    path: &Path,
    rows: usize,
    draw: impl Fn(usize, &Area<'_>) -> Result<()>,
) -> Result<()> {
    register_font();
    let root = BitMapBackend::new(path, (900, 330 * rows as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(path, e))?;
    for (i, a) in root.split_evenly((rows, 1)).iter().enumerate() {
        draw(i, a)?;
    }
    root.present().map_err(|e| err(path, e))?;
    Ok(())
}

/// `v` to `digits` significant digits, without trailing zeros.
fn significant(v: f64, digits: i32) -> String {
    let magnitude = if v == 0.0 {
        0
    } else {
        v.abs().log10().floor() as i32
    };
    let decimals = (digits - 1 - magnitude).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// A heat map: `values[i][j]` (absent cells blank) coloured on the viridis scale over the
/// cells of the grid `x_ticks` × `y_ticks` (the axes' values, as labels), each cell labelled
/// with its value when the grid is small enough to read.
#[allow(clippy::too_many_arguments)]
pub fn heat_map(
    area: &Area<'_>,
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    x_ticks: &[f64],
    y_ticks: &[f64],
    values: &[Vec<Option<f64>>],
) -> Result<()> {
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    let finite = values.iter().flatten().flatten().copied();
    let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    });
    let (nx, ny) = (x_ticks.len(), y_ticks.len());
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("{title}   (dark {lo:.3e} … bright {hi:.3e})"),
            ("sans-serif", 16),
        )
        .margin(8)
        .x_label_area_size(38)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..nx as f64, 0.0..ny as f64)
        .map_err(|e| err(path, e))?;
    let label = |ticks: &[f64], v: f64| {
        let i = v.floor() as usize;
        if v - v.floor() == 0.5 && i < ticks.len() {
            significant(ticks[i], 4)
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_labels(2 * nx + 1)
        .y_labels(2 * ny + 1)
        .x_label_formatter(&|v| label(x_ticks, *v))
        .y_label_formatter(&|v| label(y_ticks, *v))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(|e| err(path, e))?;
    let span = if hi > lo { hi - lo } else { 1.0 };
    let cells = values.iter().enumerate().flat_map(|(i, col)| {
        col.iter().enumerate().filter_map(move |(j, v)| {
            let v = (*v)?;
            let c: RGBColor = ViridisRGB.get_color_normalized((v - lo) / span, 0.0, 1.0);
            Some(Rectangle::new(
                [(i as f64, j as f64), (i as f64 + 1.0, j as f64 + 1.0)],
                c.filled(),
            ))
        })
    });
    chart.draw_series(cells).map_err(|e| err(path, e))?;
    if nx * ny <= 144 {
        let text = values.iter().enumerate().flat_map(|(i, col)| {
            col.iter().enumerate().filter_map(move |(j, v)| {
                let v = (*v)?;
                let bright = (v - lo) / span > 0.6;
                let colour = if bright { BLACK } else { WHITE };
                Some(Text::new(
                    format!("{v:.3e}"),
                    (i as f64 + 0.15, j as f64 + 0.55),
                    ("sans-serif", 11).into_font().color(&colour),
                ))
            })
        });
        chart.draw_series(text).map_err(|e| err(path, e))?;
    }
    Ok(())
}

/// A histogram of `samples` in `bins` equal bins, with the mean marked.
pub fn histogram(
    area: &Area<'_>,
    path: &Path,
    title: &str,
    x_label: &str,
    samples: &[f64],
    bins: usize,
) -> Result<()> {
    let (lo, hi) = samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else if lo.is_finite() {
        (
            lo - 0.5 * lo.abs().max(1e-12),
            lo + 0.5 * lo.abs().max(1e-12),
        )
    } else {
        (0.0, 1.0)
    };
    let bins = bins.max(1);
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for v in samples {
        counts[(((v - lo) / width) as usize).min(bins - 1)] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(0).max(1) as f64 * 1.1;
    let mean = samples.iter().sum::<f64>() / samples.len().max(1) as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!(
                "{title}   ({} runs, mean {})",
                samples.len(),
                significant(mean, 4)
            ),
            ("sans-serif", 16),
        )
        .margin(8)
        .x_label_area_size(38)
        .y_label_area_size(70)
        .build_cartesian_2d(lo..hi, 0.0..top)
        .map_err(|e| err(path, e))?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc("runs")
        .x_label_formatter(&|x| significant(*x, 3))
        .y_label_formatter(&|y| format!("{y:.0}"))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(|e| err(path, e))?;
    chart
        .draw_series(counts.iter().enumerate().map(|(k, &c)| {
            let x0 = lo + k as f64 * width;
            Rectangle::new([(x0, 0.0), (x0 + width, c as f64)], COLORS[0].filled())
        }))
        .map_err(|e| err(path, e))?;
    chart
        .draw_series(counts.iter().enumerate().map(|(k, &c)| {
            let x0 = lo + k as f64 * width;
            Rectangle::new([(x0, 0.0), (x0 + width, c as f64)], WHITE.stroke_width(1))
        }))
        .map_err(|e| err(path, e))?;
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(mean, 0.0), (mean, top)],
            COLORS[1].stroke_width(2),
        )))
        .map_err(|e| err(path, e))?;
    Ok(())
}
