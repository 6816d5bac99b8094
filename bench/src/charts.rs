//! The bench's charts, PNG through plotters' bitmap backend. Text is drawn with ab_glyph from the
//! DejaVu Sans that `hair-render` bundles ([`hair_render::preview::FONT`]), so no system font
//! library is needed.

use std::path::Path;
use std::sync::Once;

use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use crate::stability::{Grid, FPS};
use crate::{BenchError, BenchReport};

static FONT: Once = Once::new();

/// Registers the bundled font as "sans-serif" (once per process).
fn font() {
    FONT.call_once(|| {
        // The font is compiled in and known to parse; a failure would only lose the labels.
        let _ = register_font("sans-serif", FontStyle::Normal, hair_render::preview::FONT);
    });
}

const COLORS: [RGBColor; 13] = [
    RGBColor(214, 39, 40),
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(0, 90, 50),
    RGBColor(120, 40, 140),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(0, 0, 0),
];

fn err(path: &Path) -> impl Fn(String) -> BenchError + '_ {
    move |message| BenchError::Write {
        path: path.to_path_buf(),
        message,
    }
}

/// A tick label: plain above 1, scientific below.
fn tick(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.0e}")
    }
}

/// A log range covering `values` (positive ones), padded by a factor 2 each side.
fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() {
        lo / 2.0..hi * 2.0
    } else {
        1e-3..1.0
    }
}

/// Error against cost, log–log, one panel per case, one series per method; `auto` marked; the
/// last panel is the rod's tip-moment case (error against the analytic arc).
pub fn pareto(r: &BenchReport, path: &Path) -> Result<(), BenchError> {
    font();
    let e = err(path);
    let rows = (r.cases.len() + 1).div_ceil(2);
    let root = BitMapBackend::new(path, (1600, 600 * rows as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(format!("{x:?}")))?;
    let panels = root.split_evenly((rows, 2));
    let mut methods: Vec<&str> = Vec::new();
    for run in &r.runs {
        if !methods.contains(&run.method.as_str()) {
            methods.push(&run.method);
        }
    }
    for ((case, _), panel) in r.cases.iter().zip(&panels) {
        // The case and its truth, short enough for half the width.
        let truth = r
            .truths
            .iter()
            .find(|t| &t.case == case)
            .map_or("", |t| t.truth.as_str());
        let truth = match truth.strip_prefix("analytic: ") {
            Some(rest) => rest.split(',').next().unwrap_or(rest),
            None => "the converged rod",
        };
        let title = format!("{case}: against {truth}");
        let runs: Vec<_> = r.runs.iter().filter(|x| &x.case == case).collect();
        let stable = || runs.iter().filter_map(|x| x.stable().map(|s| (x, s)));
        let plans = || r.plan.iter().filter(|p| &p.case == case);
        let xr = log_range(
            stable()
                .map(|(_, (c, _))| c.ms_per_frame)
                .chain(plans().filter_map(|p| p.ms_per_frame)),
        );
        let yr = log_range(
            stable()
                .map(|(_, (_, er))| er.position_rms)
                .chain(plans().filter_map(|p| p.truth_error)),
        );
        let mut chart = ChartBuilder::on(panel)
            .caption(&title, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(75)
            .build_cartesian_2d(xr.log_scale(), yr.log_scale())
            .map_err(|x| e(format!("{x:?}")))?;
        chart
            .configure_mesh()
            .x_desc("cost: ms per frame")
            .y_desc("position RMS error vs the truth (m)")
            .x_labels(6)
            .y_labels(8)
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|x| e(format!("{x:?}")))?;
        for (i, m) in methods.iter().enumerate() {
            if !runs.iter().any(|x| x.method == *m) {
                continue;
            }
            let color = COLORS[i % COLORS.len()];
            let pts: Vec<(f64, f64)> = stable()
                .filter(|(x, _)| x.method == *m && !x.auto)
                .map(|(_, (c, er))| (c.ms_per_frame, er.position_rms))
                .filter(|&(_, y)| y > 0.0)
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(|x| e(format!("{x:?}")))?
                .label(*m)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3))
                });
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(|x| e(format!("{x:?}")))?;
        }
        plan_markers(r, case, &mut chart, &e)?;
        for (x, (c, er)) in stable().filter(|(x, _)| x.auto) {
            let p = (c.ms_per_frame, er.position_rms);
            chart
                .draw_series([EmptyElement::at(p)
                    + Cross::new((0, 0), 9, BLACK.stroke_width(3))
                    + Text::new(
                        format!("auto ({} substeps)", x.substeps),
                        (10, -18),
                        ("sans-serif", 15),
                    )])
                .map_err(|x| e(format!("{x:?}")))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 13))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|x| e(format!("{x:?}")))?;
    }
    if let Some(panel) = panels.get(r.cases.len()) {
        tip_moment_panel(r, panel, &e)?;
    }
    root.present().map_err(|x| e(format!("{x:?}")))
}

/// Marks where `hairsys plan` lands on `case`'s panel: each measured choice as a diamond at
/// its cost and its error against the truth, labelled with the tolerance.
fn plan_markers<'a, DB: DrawingBackend + 'a>(
    r: &BenchReport,
    case: &str,
    chart: &mut ChartContext<'a, DB, LogCartesian>,
    e: &impl Fn(String) -> BenchError,
) -> Result<(), BenchError> {
    let violet = RGBColor(106, 27, 154);
    let points = r.plan.iter().filter(|p| p.case == case);
    for (i, p) in points.enumerate() {
        let (Some(cost), Some(error)) = (p.ms_per_frame, p.truth_error) else {
            continue;
        };
        // Alternate the labels above and below: the choices may land close together.
        let offset = if i % 2 == 0 { (12, -26) } else { (12, 10) };
        chart
            .draw_series([EmptyElement::at((cost, error))
                + Polygon::new(vec![(0, -9), (9, 0), (0, 9), (-9, 0)], violet.filled())
                + Text::new(
                    format!("plan, {:.0} mm", p.tolerance * 1e3),
                    offset,
                    ("sans-serif", 16).into_font().color(&violet),
                )])
            .map_err(|x| e(format!("{x:?}")))?;
    }
    Ok(())
}

/// The chart type of a pareto panel: log cost against log error.
type LogCartesian = Cartesian2d<LogCoord<f64>, LogCoord<f64>>;

/// The rod's tip-moment case: error against the analytic arc (over L) against the cost of
/// relaxing it (ms per simulated second), one series per projection iteration limit.
fn tip_moment_panel(
    r: &BenchReport,
    panel: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    e: &impl Fn(String) -> BenchError,
) -> Result<(), BenchError> {
    let done: Vec<_> = r
        .tip_moment
        .iter()
        .filter_map(|t| {
            let cost = t.us_per_substep / t.dt / 1e3;
            t.error_over_length.map(|err| (t, cost, err))
        })
        .collect();
    let mut chart = ChartBuilder::on(panel)
        .caption(
            "rod: tip moment (t = 0.1 and 1.5 rad) against the elastica",
            ("sans-serif", 20),
        )
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(75)
        .build_cartesian_2d(
            log_range(done.iter().map(|d| d.1)).log_scale(),
            log_range(done.iter().map(|d| d.2)).log_scale(),
        )
        .map_err(|x| e(format!("{x:?}")))?;
    chart
        .configure_mesh()
        .x_desc("cost: ms per simulated second")
        .y_desc("largest node error / L")
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|x| e(format!("{x:?}")))?;
    let mut limits: Vec<u32> = r.tip_moment.iter().map(|t| t.iterations).collect();
    limits.sort_unstable();
    limits.dedup();
    for (i, &it) in limits.iter().enumerate() {
        let color = COLORS[(i + 5) % COLORS.len()];
        let pts: Vec<(f64, f64)> = done
            .iter()
            .filter(|d| d.0.iterations == it)
            .map(|d| (d.1, d.2))
            .collect();
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 5, color.filled())))
            .map_err(|x| e(format!("{x:?}")))?
            .label(format!(
                "rod, {it} projection iteration{}",
                if it == 1 { "" } else { "s" }
            ))
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|x| e(format!("{x:?}")))?;
    Ok(())
}

/// Stretch stiffness × substeps per frame, stable (green dot) or unstable (red cross), one panel
/// per method, with the predicted bound (line) and the observed boundary (triangles).
pub fn stability_map(r: &BenchReport, grid: &Grid, path: &Path) -> Result<(), BenchError> {
    font();
    let e = err(path);
    let rows = r.stability.len().div_ceil(2);
    let root = BitMapBackend::new(path, (1500, 460 * rows as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(format!("{x:?}")))?;
    let panels = root.split_evenly((rows, 2));
    let xr = log_range(grid.substeps.iter().map(|&s| s as f64));
    // Room below the lowest row for the legend.
    let yr = log_range(grid.stiffness.iter().copied());
    let yr = yr.start / 20.0..yr.end;
    for (m, panel) in r.stability.iter().zip(&panels) {
        let mut chart = ChartBuilder::on(panel)
            .caption(&m.method, ("sans-serif", 19))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(xr.clone().log_scale(), yr.clone().log_scale())
            .map_err(|x| e(format!("{x:?}")))?;
        chart
            .configure_mesh()
            .x_desc(format!("substeps per frame at {FPS} fps"))
            .y_desc(&m.axis)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|x| e(format!("{x:?}")))?;
        let cells = grid.stiffness.iter().enumerate().flat_map(|(row, &k)| {
            grid.substeps
                .iter()
                .enumerate()
                .map(move |(c, &s)| (row, c, s as f64, k))
        });
        let green = RGBColor(44, 160, 44);
        let red = RGBColor(214, 39, 40);
        chart
            .draw_series(
                cells
                    .clone()
                    .filter(|&(row, c, ..)| m.stable[row][c])
                    .map(|(_, _, s, k)| Circle::new((s, k), 4, green.filled())),
            )
            .map_err(|x| e(format!("{x:?}")))?
            .label("stable")
            .legend(move |(x, y)| Circle::new((x + 10, y), 4, green.filled()));
        chart
            .draw_series(
                cells
                    .filter(|&(row, c, ..)| !m.stable[row][c])
                    .map(|(_, _, s, k)| Cross::new((s, k), 4, red.stroke_width(2))),
            )
            .map_err(|x| e(format!("{x:?}")))?
            .label("unstable")
            .legend(move |(x, y)| Cross::new((x + 10, y), 4, red.stroke_width(2)));
        let predicted: Vec<(f64, f64)> = grid
            .stiffness
            .iter()
            .zip(&m.predicted_dt)
            .filter(|(_, dt)| dt.is_finite())
            .map(|(&k, dt)| (1.0 / (FPS * dt), k))
            .collect();
        if !predicted.is_empty() {
            chart
                .draw_series(LineSeries::new(predicted, BLACK.stroke_width(2)))
                .map_err(|x| e(format!("{x:?}")))?
                .label("predicted bound dt = 2/ω")
                .legend(|(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2))
                });
        }
        let observed: Vec<(f64, f64)> = grid
            .stiffness
            .iter()
            .zip(&m.observed_dt)
            .filter_map(|(&k, dt)| dt.filter(|d| d.is_finite()).map(|d| (1.0 / (FPS * d), k)))
            .collect();
        chart
            .draw_series(
                observed
                    .iter()
                    .map(|&p| TriangleMarker::new(p, 6, BLUE.filled())),
            )
            .map_err(|x| e(format!("{x:?}")))?
            .label("observed boundary")
            .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLUE.filled()));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .label_font(("sans-serif", 12))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|x| e(format!("{x:?}")))?;
    }
    root.present().map_err(|x| e(format!("{x:?}")))
}

/// Shades of red for the rod's iteration limits on the segments chart (they overlap: one hue
/// for the model), in the order the methods come.
const ROD_COLORS: [RGBColor; 4] = [
    RGBColor(90, 0, 0),
    RGBColor(150, 0, 0),
    RGBColor(210, 40, 40),
    RGBColor(255, 120, 120),
];

/// Colour of each method on the segments chart: reds for the rod, [`COLORS`] but its red for the
/// rest.
fn segment_colors(methods: &[&str]) -> Vec<RGBColor> {
    let (mut rods, mut others) = (0, 0);
    methods
        .iter()
        .map(|m| {
            if m.starts_with("rod") {
                rods += 1;
                ROD_COLORS[(rods - 1) % ROD_COLORS.len()]
            } else {
                others += 1;
                COLORS[1 + (others - 1) % (COLORS.len() - 1)]
            }
        })
        .collect()
}

/// The segments axis ([`crate::segments`]): position error against segments per strand, log–log,
/// one panel per case, one series per method at its automatic substeps (methods with no stable
/// run are left out; the table lists them); the dashed line is the truth's own change when its
/// segments are doubled (errors below it are not resolved by the truth). One legend below the
/// panels.
pub fn segments(r: &BenchReport, path: &Path) -> Result<(), BenchError> {
    font();
    let e = err(path);
    fn stable(x: &crate::segments::SegmentRun) -> bool {
        matches!(&x.outcome, crate::Outcome::Stable { errors, .. } if errors.position_rms > 0.0)
    }
    let mut cases: Vec<&str> = Vec::new();
    let mut methods: Vec<&str> = Vec::new();
    for run in r.segments.iter().filter(|x| stable(x)) {
        if !cases.contains(&run.case.as_str()) {
            cases.push(&run.case);
        }
        if !methods.contains(&run.method.as_str()) {
            methods.push(&run.method);
        }
    }
    let colors = segment_colors(&methods);
    let columns = cases.len().max(1);
    let legend_rows = methods.len().div_ceil(4) + 1;
    let legend_height = 24 * legend_rows as u32 + 16;
    let root =
        BitMapBackend::new(path, (800 * columns as u32, 640 + legend_height)).into_drawing_area();
    root.fill(&WHITE).map_err(|x| e(format!("{x:?}")))?;
    let (top, bottom) = root.split_vertically(640);
    let panels = top.split_evenly((1, columns));
    for (case, panel) in cases.iter().zip(&panels) {
        let runs: Vec<_> = r.segments.iter().filter(|x| x.case == *case).collect();
        let points = |m: &str| -> Vec<(f64, f64)> {
            runs.iter()
                .filter(|x| x.method == m && stable(x))
                .filter_map(|x| match &x.outcome {
                    crate::Outcome::Stable { errors, .. } => {
                        Some((x.segments as f64, errors.position_rms))
                    }
                    crate::Outcome::Unstable { .. } => None,
                })
                .collect()
        };
        let floor = r
            .truths
            .iter()
            .find(|t| t.case == *case)
            .map_or(0.0, |t| t.space_change);
        let mut counts: Vec<usize> = runs.iter().map(|x| x.segments).collect();
        counts.sort_unstable();
        counts.dedup();
        let xr = log_range(counts.iter().map(|&n| n as f64));
        let yr = log_range(
            methods
                .iter()
                .flat_map(|m| points(m))
                .map(|(_, y)| y)
                .chain((floor > 0.0).then_some(floor)),
        );
        let mut chart = ChartBuilder::on(panel)
            .caption(
                format!("{case}: error against segments per strand (auto substeps)"),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(75)
            .build_cartesian_2d(
                xr.clone()
                    .log_scale()
                    .with_key_points(counts.iter().map(|&n| n as f64).collect()),
                yr.log_scale(),
            )
            .map_err(|x| e(format!("{x:?}")))?;
        chart
            .configure_mesh()
            .x_desc("segments per strand")
            .y_desc("position RMS error vs the truth (m)")
            .x_labels(counts.len())
            .y_labels(8)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(|x| e(format!("{x:?}")))?;
        for (m, &color) in methods.iter().zip(&colors) {
            let pts = points(m);
            chart
                .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))
                .map_err(|x| e(format!("{x:?}")))?;
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(|x| e(format!("{x:?}")))?;
        }
        if floor > 0.0 {
            chart
                .draw_series(DashedLineSeries::new(
                    [(xr.start, floor), (xr.end, floor)],
                    6,
                    4,
                    BLACK.stroke_width(1),
                ))
                .map_err(|x| e(format!("{x:?}")))?;
        }
    }
    // The legend: four columns of methods, then the truth's line.
    let column_width = 800 * columns as i32 / 4;
    let entries = methods
        .iter()
        .zip(&colors)
        .map(|(m, c)| (m.to_string(), *c, false))
        .chain([(
            "truth: its change when its segments are doubled".to_string(),
            BLACK,
            true,
        )]);
    for (i, (label, color, dashed)) in entries.enumerate() {
        let (x, y) = (20 + column_width * (i % 4) as i32, 12 + 24 * (i / 4) as i32);
        let pieces: &[(i32, i32)] = if dashed {
            &[(0, 6), (11, 17), (22, 28)]
        } else {
            &[(0, 28)]
        };
        for &(a, b) in pieces {
            let line =
                PathElement::new(vec![(x + a, y + 8), (x + b, y + 8)], color.stroke_width(3));
            bottom.draw(&line).map_err(|x| e(format!("{x:?}")))?;
        }
        bottom
            .draw(&Text::new(label, (x + 36, y), ("sans-serif", 15)))
            .map_err(|x| e(format!("{x:?}")))?;
    }
    root.present().map_err(|x| e(format!("{x:?}")))
}
