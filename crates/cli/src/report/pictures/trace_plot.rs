//! A picture of one simulation from a `wogan simulate --trace` file: the car's path over the road
//! (coloured by BOLP), and BOLP and speed over time, in one SVG.

use super::layout::{plot_error, titled};
use super::road_map::{draw_map_mesh, road_outline};
use crate::files::json_lines::{numbered_lines, open_input};
use crate::files::records::TraceRecord;
use anyhow::{anyhow, Result};
use plotters::prelude::*;
use road_sim::{Point, Road, Sample};
use serde_json::Value;
use std::path::Path;

/// A trace read from its file.
#[derive(Debug)]
pub struct Trace {
    /// The road's defining points.
    pub road_points: Vec<Point>,
    /// The samples, in file order.
    pub samples: Vec<Sample>,
    /// `file:line: problem` for each line that could not be read.
    pub problems: Vec<String>,
}

/// Reads a trace; `Err` when the file cannot be opened or holds no road record.
pub fn read_trace(path: &Path) -> Result<Trace> {
    let mut road_points = None;
    let mut samples = Vec::new();
    let mut problems = Vec::new();
    for line in numbered_lines(open_input(Some(path))?) {
        let line = line.map_err(|e| anyhow!("cannot read {}: {e}", path.display()))?;
        let at = format!("{}:{}", path.display(), line.number);
        let parsed = line.text.and_then(|text| {
            let value: Value = serde_json::from_str(&text).map_err(|e| format!("not JSON: {e}"))?;
            let kind = value
                .get("type")
                .and_then(Value::as_str)
                .ok_or("no \"type\" field")?
                .to_owned();
            let record: TraceRecord =
                serde_json::from_value(value).map_err(|e| format!("bad {kind} record: {e}"))?;
            match record {
                TraceRecord::Road { road_points: r, .. } => road_points = Some(r),
                TraceRecord::Sample(sample) => samples.push(sample),
                TraceRecord::Unknown => {}
            }
            Ok(())
        });
        if let Err(problem) = parsed {
            problems.push(format!("{at}: {problem}"));
        }
    }
    let road_points = road_points.ok_or_else(|| anyhow!("{}: no road record", path.display()))?;
    Ok(Trace {
        road_points,
        samples,
        problems,
    })
}

/// Colour of the path at a BOLP: green in the lane, through yellow, to red fully out.
fn bolp_colour(bolp: f64) -> RGBColor {
    let b = bolp.clamp(0.0, 1.0);
    let red = (255.0 * (2.0 * b).min(1.0)) as u8;
    let green = (200.0 * (2.0 - 2.0 * b).min(1.0)) as u8;
    RGBColor(red, green, 0)
}

/// Draws `trace` to `path`: the map panel (road surface, centre line, start marker, car path
/// coloured by BOLP) on the left, BOLP over time and speed over time on the right.
pub fn trace_svg(path: &Path, title: &str, trace: &Trace) -> Result<()> {
    let err = plot_error(path);
    let road = Road::new(&trace.road_points)
        .map_err(|e| anyhow!("the trace's road cannot be built: {e}"))?;
    let root = SVGBackend::new(path, (1300, 650)).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    // Wrapped to the picture's width, so that a long file name is not cut off.
    let root = titled(&root, title, 22, None).map_err(&err)?;
    let (map_area, right) = root.split_horizontally(640);
    let (bolp_area, speed_area) = right.split_vertically(300);

    // Map panel: a square window around the road and the path.
    let outline = road_outline(&road);
    let all_x = outline
        .iter()
        .map(|p| p.0)
        .chain(trace.samples.iter().map(|s| s.x));
    let all_y = outline
        .iter()
        .map(|p| p.1)
        .chain(trace.samples.iter().map(|s| s.y));
    let (x_min, x_max) = all_x.fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let (y_min, y_max) = all_y.fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let side = (x_max - x_min).max(y_max - y_min) + 10.0;
    let (cx, cy) = ((x_min + x_max) / 2.0, (y_min + y_max) / 2.0);
    let mut map = ChartBuilder::on(&map_area)
        .caption(
            "path over the road (colour: BOLP, green 0 → red 1)",
            ("sans-serif", 16),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(
            cx - side / 2.0..cx + side / 2.0,
            cy - side / 2.0..cy + side / 2.0,
        )
        .map_err(&err)?;
    draw_map_mesh(&mut map).map_err(&err)?;
    map.draw_series(std::iter::once(Polygon::new(
        outline,
        RGBColor(190, 190, 190).filled(),
    )))
    .map_err(&err)?;
    let centre = road.interpolated.iter().map(|p| (p[0], p[1]));
    map.draw_series(LineSeries::new(centre, WHITE.stroke_width(2)))
        .map_err(&err)?;
    if let Some(start) = road.interpolated.first() {
        map.draw_series(std::iter::once(Circle::new(
            (start[0], start[1]),
            6,
            BLACK.filled(),
        )))
        .map_err(&err)?;
    }
    let segments = trace.samples.windows(2).map(|w| {
        PathElement::new(
            [(w[0].x, w[0].y), (w[1].x, w[1].y)],
            bolp_colour(w[1].bolp).stroke_width(3),
        )
    });
    map.draw_series(segments).map_err(&err)?;

    let end_s = trace.samples.last().map_or(1.0, |s| s.t).max(1e-3);
    let mut bolp = ChartBuilder::on(&bolp_area)
        .caption("BOLP over time", ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(0.0..end_s, 0.0..1.05)
        .map_err(&err)?;
    bolp.configure_mesh()
        .max_light_lines(0)
        .x_desc("t (s)")
        .y_desc("BOLP")
        .draw()
        .map_err(&err)?;
    bolp.draw_series(LineSeries::new(
        trace.samples.iter().map(|s| (s.t, s.bolp)),
        RED.stroke_width(2),
    ))
    .map_err(&err)?;

    let top_kmh = trace
        .samples
        .iter()
        .map(|s| s.speed_kmh)
        .fold(10.0, f64::max)
        * 1.1;
    let mut speed = ChartBuilder::on(&speed_area)
        .caption("speed over time", ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(0.0..end_s, 0.0..top_kmh)
        .map_err(&err)?;
    speed
        .configure_mesh()
        .max_light_lines(0)
        .x_desc("t (s)")
        .y_desc("speed (km/h)")
        .draw()
        .map_err(&err)?;
    speed
        .draw_series(LineSeries::new(
            trace.samples.iter().map(|s| (s.t, s.speed_kmh)),
            BLUE.stroke_width(2),
        ))
        .map_err(&err)?;
    root.present().map_err(&err)?;
    Ok(())
}

/// Draws one `simulate --trace` file to `out/trace.svg`. Returns how many of its lines were bad
/// (each said on stderr).
pub fn trace_picture(trace_path: &Path, out: &Path) -> Result<usize> {
    let trace = read_trace(trace_path)?;
    for problem in &trace.problems {
        eprintln!("wogan report: {problem}");
    }
    let name = trace_path
        .file_name()
        .map_or_else(|| "trace".to_owned(), |f| f.to_string_lossy().into_owned());
    let path = out.join("trace.svg");
    trace_svg(&path, &format!("simulation {name}"), &trace)?;
    eprintln!("wogan report: wrote {}", path.display());
    Ok(trace.problems.len())
}
