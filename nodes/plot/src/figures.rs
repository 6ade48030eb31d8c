//! The figures of a run, each drawn once per backend (PNG and SVG) by the same function:
//! axis signals with command events, CA gaps, mover trails, the TCP path, cycle-time
//! histograms. Every figure has a caption, axis labels with units and a legend.

use crate::run::{Rect, Run};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

type Area<'a, DB> = DrawingArea<DB, Shift>;
type Res = Result<(), String>;

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
];

fn colour(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Colour of a command state mark.
fn state_colour(state: &str) -> RGBColor {
    match state {
        "Active" => RGBColor(44, 160, 44),
        "Done" => RGBColor(31, 119, 180),
        "Aborted" => RGBColor(255, 127, 14),
        _ => RGBColor(214, 39, 40),
    }
}

fn e<E: std::fmt::Display>(x: E) -> String {
    x.to_string()
}

/// (min, max) of values, widened when flat or empty.
fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-9 {
        return (lo - 1.0, hi + 1.0); // a flat signal in the middle
    }
    let pad = (hi - lo) * 0.05;
    (lo - pad, hi + pad)
}

/// One figure of a run.
#[derive(Clone, Copy, Debug)]
enum Figure {
    Axes,
    Gaps,
    Trails,
    Tcp,
    CycleTimes,
}

impl Figure {
    fn draw<DB: DrawingBackend>(self, run: &Run, root: &Area<'_, DB>) -> Res {
        match self {
            Figure::Axes => axes(run, root),
            Figure::Gaps => ca_gaps(run, root),
            Figure::Trails => planar_trails(run, root),
            Figure::Tcp => pickplace_tcp(run, root),
            Figure::CycleTimes => cycle_times(run, root),
        }
    }
}

/// Writes every figure the run has data for into `dir` as PNG and SVG; returns the files.
pub fn render(run: &Run, dir: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(e)?;
    let mut figures: Vec<(&str, (u32, u32), Figure)> = Vec::new();
    if !run.axes.is_empty() {
        let h = 60 + 260 * run.axes.len() as u32;
        figures.push(("axes", (1500, h), Figure::Axes));
    }
    if !run.gaps.is_empty() {
        let h = 60 + 360 * run.gaps.len() as u32;
        figures.push(("ca_gaps", (1200, h), Figure::Gaps));
    }
    if !run.movers.is_empty() {
        figures.push(("planar_trails", (1100, 800), Figure::Trails));
    }
    if !run.tcp.is_empty() {
        figures.push(("pickplace_tcp", (1500, 560), Figure::Tcp));
    }
    if !run.cycle_stats.is_empty() {
        let h = 60 + 300 * run.cycle_stats.len() as u32;
        figures.push(("cycle_times", (1300, h), Figure::CycleTimes));
    }
    let mut out = Vec::new();
    for (stem, size, figure) in figures {
        let file = dir.join(format!("{stem}.png"));
        {
            let root = BitMapBackend::new(&file, size).into_drawing_area();
            root.fill(&WHITE).map_err(e)?;
            figure.draw(run, &root)?;
            root.present().map_err(e)?;
        }
        out.push(file);
        let file = dir.join(format!("{stem}.svg"));
        {
            let root = SVGBackend::new(&file, size).into_drawing_area();
            root.fill(&WHITE).map_err(e)?;
            figure.draw(run, &root)?;
            root.present().map_err(e)?;
        }
        out.push(file);
    }
    Ok(out)
}

/// Reads one signal of an axis sample.
type Signal = fn(&crate::run::AxisSample) -> f64;

/// Per axis SetPos, SetVelo, SetAcc over time; the axis' command events as vertical lines
/// (green Active, blue Done, orange Aborted, red Error).
fn axes<DB: DrawingBackend>(run: &Run, root: &Area<'_, DB>) -> Res {
    let root = root
        .titled(
            "Axis set values over time (command events: green Active, blue Done, orange Aborted, red Error)",
            ("sans-serif", 20),
        )
        .map_err(e)?;
    let rows = root.split_evenly((run.axes.len(), 3));
    let t_end = run
        .axes
        .values()
        .flat_map(|s| s.last())
        .map(|s| s.t)
        .fold(0.0, f64::max)
        .max(1e-3);
    for (i, (name, samples)) in run.axes.iter().enumerate() {
        let signals: [(&str, &str, Signal); 3] = [
            ("SetPos", "u", |s| s.pos),
            ("SetVelo", "u/s", |s| s.velo),
            ("SetAcc", "u/s²", |s| s.acc),
        ];
        for (j, (label, unit, get)) in signals.iter().enumerate() {
            let area = &rows[3 * i + j];
            let (lo, hi) = range(samples.iter().map(get));
            let mut chart = plane_chart(
                area,
                &format!("{name}: {label}"),
                16,
                0.0..t_end,
                lo..hi,
                "time [s]",
                &format!("{label} [{unit}]"),
            )?;
            for c in run.commands.iter().filter(|c| &c.object == name) {
                chart
                    .draw_series(LineSeries::new(
                        [(c.t, lo), (c.t, hi)],
                        state_colour(c.state).mix(0.6),
                    ))
                    .map_err(e)?;
            }
            chart
                .draw_series(LineSeries::new(
                    samples.iter().map(|s| (s.t, get(s))),
                    colour(i).stroke_width(2),
                ))
                .map_err(e)?
                .label(format!("{name} {label}"))
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 16, y)], colour(i).stroke_width(2))
                });
            legend(&mut chart)?;
        }
    }
    Ok(())
}

/// Per CA group: each axis' gap to its predecessor (solid) and its target gap (dashed).
fn ca_gaps<DB: DrawingBackend>(run: &Run, root: &Area<'_, DB>) -> Res {
    let root = root
        .titled(
            "Collision avoidance: gap to the predecessor (solid) and target gap (dashed)",
            ("sans-serif", 20),
        )
        .map_err(e)?;
    let rows = root.split_evenly((run.gaps.len(), 1));
    for (area, (group, axes)) in rows.iter().zip(&run.gaps) {
        let all = axes.values().flatten();
        let t_end = all.clone().map(|g| g.t).fold(1e-3, f64::max);
        let (lo, hi) = range(all.flat_map(|g| [g.actual, g.target]));
        let mut chart = plane_chart(
            area,
            &format!("group {group}"),
            16,
            0.0..t_end,
            lo..hi,
            "time [s]",
            "gap [mm]",
        )?;
        for (i, (axis, s)) in axes.iter().enumerate() {
            let c = colour(i);
            chart
                .draw_series(LineSeries::new(
                    s.iter()
                        .filter(|g| g.actual.is_finite())
                        .map(|g| (g.t, g.actual)),
                    c.stroke_width(2),
                ))
                .map_err(e)?
                .label(format!("{axis} gap"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
            chart
                .draw_series(DashedLineSeries::new(
                    s.iter().map(|g| (g.t, g.target)),
                    6,
                    4,
                    c.into(),
                ))
                .map_err(e)?
                .label(format!("{axis} target"))
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c));
        }
        legend(&mut chart)?;
    }
    Ok(())
}

/// Bounds of rectangles and points, square (equal scales), with a margin.
fn square_bounds(
    rects: &[Rect],
    points: impl Iterator<Item = (f64, f64)>,
) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut y0, mut x1, mut y1) = (
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, y) in rects.iter().flat_map(|r| r.corners()).chain(points) {
        x0 = x0.min(x);
        y0 = y0.min(y);
        x1 = x1.max(x);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    // At least 100 mm across: a TCP that stood still is a point in a readable frame.
    let pad = (0.05 * (x1 - x0).max(y1 - y0)).max(50.0);
    ((x0 - pad, x1 + pad), (y0 - pad, y1 + pad))
}

/// A chart of two real axes on `area`: caption, margins and a mesh labelled with the axes'
/// names and units, so every panel of every figure looks alike.
fn plane_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    caption_size: u32,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
    x_desc: &str,
    y_desc: &str,
) -> Result<
    ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    String,
> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", caption_size))
        .margin(8)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x, y)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(e)?;
    Ok(chart)
}

/// The legend box of a chart: white, framed, in the upper right.
fn legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Res {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(e)
}

fn draw_rects<DB: DrawingBackend, CT: plotters::coord::CoordTranslate<From = (f64, f64)>>(
    chart: &mut ChartContext<'_, DB, CT>,
    rects: &[Rect],
    fill: RGBAColor,
) -> Res {
    chart
        .draw_series(
            rects
                .iter()
                .map(|r| Polygon::new(r.corners().to_vec(), fill.filled())),
        )
        .map_err(e)?;
    chart
        .draw_series(rects.iter().map(|r| {
            let mut c = r.corners().to_vec();
            c.push(c[0]);
            PathElement::new(c, WHITE)
        }))
        .map_err(e)?;
    Ok(())
}

/// Mover trails on the stator grid: start (circle), end (square, named).
fn planar_trails<DB: DrawingBackend>(run: &Run, root: &Area<'_, DB>) -> Res {
    let ((x0, x1), (y0, y1)) = square_bounds(
        &run.stators,
        run.movers.values().flatten().map(|&(_, x, y)| (x, y)),
    );
    // Equal scales: widen the shorter side to the area's aspect.
    let (w, h) = root.dim_in_pixel();
    let aspect = (w as f64 - 90.0) / (h as f64 - 100.0);
    let (cx, cy, mut sx, mut sy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0, x1 - x0, y1 - y0);
    if sx / sy < aspect {
        sx = sy * aspect;
    } else {
        sy = sx / aspect;
    }
    let mut chart = plane_chart(
        root,
        "XPlanar mover trails on the stator grid (circle: start, square: end)",
        20,
        cx - sx / 2.0..cx + sx / 2.0,
        cy - sy / 2.0..cy + sy / 2.0,
        "x [mm]",
        "y [mm]",
    )?;
    draw_rects(&mut chart, &run.stators, RGBColor(70, 75, 85).mix(0.85))?;
    for (k, track) in run.tracks.iter().enumerate() {
        let s = chart
            .draw_series(LineSeries::new(
                track.iter().copied(),
                RGBColor(200, 200, 200).stroke_width(2),
            ))
            .map_err(e)?;
        if k == 0 {
            s.label("tracks").legend(|(x, y)| {
                PathElement::new(
                    [(x, y), (x + 16, y)],
                    RGBColor(200, 200, 200).stroke_width(2),
                )
            });
        }
    }
    for (i, (name, trail)) in run.movers.iter().enumerate() {
        let c = colour(i);
        chart
            .draw_series(LineSeries::new(
                trail.iter().map(|&(_, x, y)| (x, y)),
                c.stroke_width(3),
            ))
            .map_err(e)?
            .label(name.clone())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(3)));
        if let (Some(&(_, xs, ys)), Some(&(_, xe, ye))) = (trail.first(), trail.last()) {
            chart
                .draw_series([Circle::new((xs, ys), 6, c.filled())])
                .map_err(e)?;
            chart
                .draw_series([EmptyElement::at((xe, ye))
                    + Rectangle::new([(-6, -6), (6, 6)], c.filled())
                    + Text::new(
                        name.clone(),
                        (8, -18),
                        ("sans-serif", 16).into_font().color(&WHITE),
                    )])
                .map_err(e)?;
        }
    }
    legend(&mut chart)?;
    Ok(())
}

/// The TCP path in three projections, with the belts and the workpieces seen on them.
fn pickplace_tcp<DB: DrawingBackend>(run: &Run, root: &Area<'_, DB>) -> Res {
    let root = root
        .titled(
            "Pick-and-place TCP path (MCS) with belts (blue) and workpieces (green)",
            ("sans-serif", 20),
        )
        .map_err(e)?;
    let panels = root.split_evenly((1, 3));
    let views: [(&str, &str, usize, usize); 3] =
        [("XY", "x", 1, 2), ("XZ", "x", 1, 3), ("YZ", "y", 2, 3)];
    for (area, (name, _, a, b)) in panels.iter().zip(views) {
        let pick = |p: &(f64, f64, f64, f64), k: usize| [p.0, p.1, p.2, p.3][k];
        let wp = |w: &(f64, f64, f64), k: usize| [0.0, w.0, w.1, w.2][k];
        let belts: Vec<Rect> = if name == "XY" {
            run.belts.clone()
        } else {
            Vec::new()
        };
        let ((x0, x1), (y0, y1)) = square_bounds(
            &belts,
            run.tcp
                .iter()
                .map(|p| (pick(p, a), pick(p, b)))
                .chain(run.workpieces.iter().map(|w| (wp(w, a), wp(w, b)))),
        );
        let axis_name = |k: usize| ["t", "x", "y", "z"][k];
        let mut chart = plane_chart(
            area,
            &format!("{name} projection"),
            16,
            x0..x1,
            y0..y1,
            &format!("{} [mm]", axis_name(a)),
            &format!("{} [mm]", axis_name(b)),
        )?;
        draw_rects(&mut chart, &belts, RGBColor(51, 89, 153).mix(0.5))?;
        chart
            .draw_series(
                run.workpieces
                    .iter()
                    .map(|w| Circle::new((wp(w, a), wp(w, b)), 3, RGBColor(44, 160, 44).filled())),
            )
            .map_err(e)?;
        chart
            .draw_series(LineSeries::new(
                run.tcp.iter().map(|p| (pick(p, a), pick(p, b))),
                RGBColor(214, 39, 40).stroke_width(2),
            ))
            .map_err(e)?
            .label("TCP")
            .legend(|(x, y)| {
                PathElement::new([(x, y), (x + 16, y)], RGBColor(214, 39, 40).stroke_width(2))
            });
        if let Some(p) = run.tcp.first() {
            chart
                .draw_series([Circle::new(
                    (pick(p, a), pick(p, b)),
                    5,
                    RGBColor(214, 39, 40).filled(),
                )])
                .map_err(e)?
                .label("TCP at start")
                .legend(|(x, y)| Circle::new((x + 8, y), 4, RGBColor(214, 39, 40).filled()));
        }
        legend(&mut chart)?;
    }
    Ok(())
}

/// Per node: histograms of cycle execution time and wake-up jitter (1 µs buckets), up to the
/// bucket that holds 99.9 % of the cycles (the caption gives the maximum).
fn cycle_times<DB: DrawingBackend>(run: &Run, root: &Area<'_, DB>) -> Res {
    let root = root
        .titled(
            "Cycle execution time and wake-up jitter (1 µs buckets)",
            ("sans-serif", 20),
        )
        .map_err(e)?;
    let cells = root.split_evenly((run.cycle_stats.len(), 2));
    for (i, (node, s)) in run.cycle_stats.iter().enumerate() {
        for (j, (what, hist, max)) in [
            ("execution time", &s.exec_histogram, s.exec_max),
            ("jitter", &s.jitter_histogram, s.jitter_max),
        ]
        .into_iter()
        .enumerate()
        {
            let area = &cells[2 * i + j];
            let total: u64 = hist.iter().map(|&c| u64::from(c)).sum();
            let mut seen = 0u64;
            let end = hist
                .iter()
                .position(|&c| {
                    seen += u64::from(c);
                    total > 0 && seen as f64 >= 0.999 * total as f64
                })
                .map_or(1, |k| k + 1)
                .max(1);
            let top = hist[..end.min(hist.len())]
                .iter()
                .copied()
                .max()
                .unwrap_or(0)
                .max(1);
            let caption = if s.lockstep && j == 1 {
                format!("{node}: {what} (lockstep: none)")
            } else {
                format!("{node}: {what}, {total} cycles, max {:.1} µs", max * 1e6)
            };
            let mut chart = ChartBuilder::on(area)
                .caption(caption, ("sans-serif", 16))
                .margin(8)
                .x_label_area_size(36)
                .y_label_area_size(70)
                .build_cartesian_2d(0u32..end as u32 + 1, 0u32..top + top / 10 + 1)
                .map_err(e)?;
            chart
                .configure_mesh()
                .x_desc(format!("{what} [µs]"))
                .y_desc("cycles")
                .draw()
                .map_err(e)?;
            let c = colour(j);
            if s.lockstep && j == 1 {
                continue; // simulated time: no wake-up lateness to show
            }
            chart
                .draw_series(
                    Histogram::vertical(&chart).style(c.filled()).data(
                        hist.iter()
                            .enumerate()
                            .take(end)
                            .map(|(k, &n)| (k as u32, n)),
                    ),
                )
                .map_err(e)?
                .label(format!("cycles per µs of {what}"))
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], c.filled()));
            legend(&mut chart)?;
        }
    }
    Ok(())
}
