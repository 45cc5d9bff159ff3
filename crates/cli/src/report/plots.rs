//! SVG pictures of runs, drawn with plotters' SVG backend (text as SVG `<text>`, no fonts
//! loaded): the failing roads on the map, fitness over a run, and a histogram of max BOLP.

use crate::records::{known, TestRecord};
use anyhow::{anyhow, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use road_sim::{Point, Road};
use std::path::Path;
use wogan_core::Phase;

/// Width of a max-BOLP histogram bin.
pub const BOLP_BIN_WIDTH: f64 = 0.05;
/// Caption font.
const CAPTION: (&str, u32) = ("sans-serif", 20);

/// Turns a plotting error (which borrows nothing worth keeping) into an `anyhow` error.
pub(crate) fn plot_error<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> anyhow::Error + '_ {
    move |e| anyhow!("cannot draw {}: {e}", path.display())
}

/// An axis label without decimals.
pub fn whole(value: &f64) -> String {
    format!("{value:.0}")
}

/// The road surface as one polygon: the left edge, then the right edge backwards.
pub fn road_outline(road: &Road) -> Vec<(f64, f64)> {
    let mut outline: Vec<(f64, f64)> = road.left_edge().iter().map(|p| (p[0], p[1])).collect();
    outline.extend(road.right_edge().iter().rev().map(|p| (p[0], p[1])));
    outline
}

/// Draws a map's mesh: whole-metre labels, no light lines.
pub fn draw_map_mesh<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    chart
        .configure_mesh()
        .max_light_lines(0)
        .x_label_formatter(&whole)
        .y_label_formatter(&whole)
        .x_desc("x (m)")
        .y_desc("y (m)")
        .draw()
}

/// A failing road to draw: its label and defining points.
pub struct MapRoad<'a> {
    /// Written at the road's end: the test's id (and run, when several).
    pub label: String,
    /// The road's defining points.
    pub road_points: &'a [Point],
}

/// Beyond this many roads the map leaves out their labels, which would only pile up.
pub const MAX_LABELLED_ROADS: usize = 30;

/// Draws every road on a `map_size_m` square map: the road surface between its edges (one
/// `<polygon>` per road), the centre line, a start marker and, for up to
/// [`MAX_LABELLED_ROADS`] roads, the road's label at the end.
/// Roads whose geometry cannot be built are skipped; returns how many were drawn.
pub fn roads_svg(path: &Path, title: &str, roads: &[MapRoad], map_size_m: f64) -> Result<usize> {
    let err = plot_error(path);
    let root = SVGBackend::new(path, (800, 800)).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, CAPTION)
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..map_size_m, 0.0..map_size_m)
        .map_err(&err)?;
    draw_map_mesh(&mut chart).map_err(&err)?;
    let labelled = roads.len() <= MAX_LABELLED_ROADS;
    let mut drawn = 0;
    for (i, road) in roads.iter().enumerate() {
        let Ok(geometry) = Road::new(road.road_points) else {
            continue;
        };
        let colour = Palette99::pick(i).to_rgba();
        let centre: Vec<(f64, f64)> = geometry.interpolated.iter().map(|p| (p[0], p[1])).collect();
        chart
            .draw_series(std::iter::once(Polygon::new(
                road_outline(&geometry),
                colour.mix(0.3).filled(),
            )))
            .map_err(&err)?;
        chart
            .draw_series(LineSeries::new(
                centre.iter().copied(),
                colour.stroke_width(1),
            ))
            .map_err(&err)?;
        if let (Some(&start), Some(&end)) = (centre.first(), centre.last()) {
            chart
                .draw_series(std::iter::once(Circle::new(start, 5, BLACK.filled())))
                .map_err(&err)?;
            if labelled {
                let label = Text::new(road.label.clone(), end, ("sans-serif", 13));
                chart.draw_series(std::iter::once(label)).map_err(&err)?;
            }
        }
        drawn += 1;
    }
    root.present().map_err(&err)?;
    Ok(drawn)
}

/// Draws fitness over a run's tests in order: the random phase shaded, a line through the
/// fitness values, failures as red dots and passes as small blue ones.
pub fn fitness_svg(path: &Path, title: &str, tests: &[TestRecord]) -> Result<()> {
    let err = plot_error(path);
    let root = SVGBackend::new(path, (900, 450)).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let last_x = tests.len().max(1) as f64 + 0.5;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, CAPTION)
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.5..last_x, 0.0..1.05)
        .map_err(&err)?;
    chart
        .configure_mesh()
        .max_light_lines(0)
        .x_label_formatter(&whole)
        .x_desc("test (execution order)")
        .y_desc("fitness")
        .draw()
        .map_err(&err)?;
    let random: Vec<f64> = (1..=tests.len())
        .zip(tests)
        .filter(|(_, t)| t.phase == Phase::Random)
        .map(|(x, _)| x as f64)
        .collect();
    if let (Some(first), Some(last)) = (random.first(), random.last()) {
        let shade = Rectangle::new(
            [(first - 0.5, 0.0), (last + 0.5, 1.05)],
            BLUE.mix(0.12).filled(),
        );
        chart
            .draw_series(std::iter::once(shade))
            .map_err(&err)?
            .label("random phase")
            .legend(|(x, y)| {
                Rectangle::new([(x, y - 5), (x + 15, y + 5)], BLUE.mix(0.12).filled())
            });
    }
    let points: Vec<(f64, f64, &TestRecord)> = (1..=tests.len())
        .zip(tests)
        .filter_map(|(x, t)| known(t.fitness).map(|f| (x as f64, f, t)))
        .collect();
    chart
        .draw_series(LineSeries::new(
            points.iter().map(|&(x, f, _)| (x, f)),
            BLUE.mix(0.5).stroke_width(1),
        ))
        .map_err(&err)?;
    chart
        .draw_series(
            points
                .iter()
                .filter(|p| !p.2.failed())
                .map(|&(x, f, _)| Circle::new((x, f), 3, BLUE.filled())),
        )
        .map_err(&err)?
        .label("pass / error")
        .legend(|(x, y)| Circle::new((x + 7, y), 3, BLUE.filled()));
    chart
        .draw_series(
            points
                .iter()
                .filter(|p| p.2.failed())
                .map(|&(x, f, _)| Circle::new((x, f), 6, RED.filled())),
        )
        .map_err(&err)?
        .label("failure")
        .legend(|(x, y)| Circle::new((x + 7, y), 6, RED.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(&err)?;
    root.present().map_err(&err)?;
    Ok(())
}

/// Counts of `values` in bins of [`BOLP_BIN_WIDTH`] over [0, 1] (values outside are clamped).
pub fn bolp_bins(values: &[f64]) -> Vec<u32> {
    let bin_count = (1.0 / BOLP_BIN_WIDTH).round() as usize;
    let mut counts = vec![0u32; bin_count];
    for v in values.iter().filter(|v| v.is_finite()) {
        let bin = ((v / BOLP_BIN_WIDTH).floor().max(0.0) as usize).min(bin_count - 1);
        counts[bin] += 1;
    }
    counts
}

/// Draws a histogram of max BOLP (one `<rect>` per non-empty bin) and the failure threshold.
pub fn bolp_histogram_svg(
    path: &Path,
    title: &str,
    max_bolps: &[f64],
    oob_tolerance: Option<f64>,
) -> Result<()> {
    let err = plot_error(path);
    let root = SVGBackend::new(path, (800, 450)).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let counts = bolp_bins(max_bolps);
    let top = f64::from(counts.iter().copied().max().unwrap_or(0).max(1)) * 1.1;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, CAPTION)
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..1.0, 0.0..top)
        .map_err(&err)?;
    chart
        .configure_mesh()
        .max_light_lines(0)
        .y_label_formatter(&whole)
        .x_desc("max BOLP")
        .y_desc("tests")
        .draw()
        .map_err(&err)?;
    let bars = counts
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(i, &c)| {
            let low = i as f64 * BOLP_BIN_WIDTH;
            Rectangle::new(
                [(low, 0.0), (low + BOLP_BIN_WIDTH, f64::from(c))],
                BLUE.mix(0.6).filled(),
            )
        });
    chart.draw_series(bars).map_err(&err)?;
    if let Some(tolerance) = oob_tolerance {
        chart
            .draw_series(LineSeries::new(
                [(tolerance, 0.0), (tolerance, top)],
                RED.stroke_width(2),
            ))
            .map_err(&err)?
            .label(format!("failure threshold {tolerance}"))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 15, y)], RED.stroke_width(2)));
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(&err)?;
    }
    root.present().map_err(&err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bolp_bins_clamp_and_count() {
        let counts = bolp_bins(&[0.0, 0.04, 0.05, 0.99, 1.0, 1.7, -0.1, f64::NAN]);
        assert_eq!(counts.len(), 20);
        assert_eq!(counts[0], 3);
        assert_eq!(counts[1], 1);
        assert_eq!(counts[19], 3);
    }

    #[test]
    fn road_labels_are_left_out_of_crowded_maps() {
        let points: Vec<Point> = (0..6).map(|i| [50.0, 20.0 + 15.0 * f64::from(i)]).collect();
        let dir = std::env::temp_dir().join(format!("wogan-plots-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for count in [MAX_LABELLED_ROADS, MAX_LABELLED_ROADS + 1] {
            let roads: Vec<MapRoad> = (0..count)
                .map(|i| MapRoad {
                    label: format!("road-{i}"),
                    road_points: &points,
                })
                .collect();
            let path = dir.join(format!("roads-{count}.svg"));
            assert_eq!(roads_svg(&path, "map", &roads, 200.0).unwrap(), count);
            let svg = std::fs::read_to_string(&path).unwrap();
            assert_eq!(
                svg.contains("road-0"),
                count <= MAX_LABELLED_ROADS,
                "{count} roads"
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
