//! Failing roads on the map: each road's surface drawn to scale, labelled by its test while the map
//! is not crowded. A map of many failing roads draws a seeded sample of them, so that its file
//! stays small enough to open (under 2 MB), and says so under its title.

use super::layout::{
    picture, plot_error, room_for_last_label, text_width_px, thousands, whole, ROAD_LABEL,
    SVG_FONT_SCALE, X_LABEL_AREA,
};
use anyhow::Result;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use road_sim::{Point, Road};
use std::ops::Range;
use std::path::Path;

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

/// Beyond this many drawn roads the map leaves out their labels, which would only pile up.
pub const MAX_LABELLED_ROADS: usize = 30;
/// Most roads a map draws; of more, it draws a seeded random sample.
pub const MAX_DRAWN_ROADS: usize = 500;
/// Most points (road outlines and centre lines) a map draws. Each is about 8 bytes of SVG, so
/// this keeps the file under 2 MB however long the roads are.
pub const MAX_DRAWN_POINTS: usize = 200_000;
/// Seed of the sample of roads that a crowded map draws: fixed, so that the same runs give the
/// same picture.
const ROAD_SAMPLE_SEED: u64 = 20_260_101;
/// How many lines a road's label may move up or down to clear the labels placed before it.
const LABEL_NUDGES: i32 = 3;

/// The roads a map draws, with their geometry, in input order: every road when they fit
/// [`MAX_DRAWN_ROADS`] and [`MAX_DRAWN_POINTS`]; else those of a seeded random order that fit
/// (then the second value is `true`). Roads whose geometry cannot be built are left out.
fn roads_to_draw(roads: &[MapRoad]) -> (Vec<(usize, Road)>, bool) {
    // Roads are taken in a seeded random order, so that when they do not all fit, those drawn
    // are a random sample; when they all fit, the order does not matter (they are sorted back).
    let mut order: Vec<usize> = (0..roads.len()).collect();
    order.shuffle(&mut ChaCha8Rng::seed_from_u64(ROAD_SAMPLE_SEED));
    let mut drawn = Vec::new();
    let mut points = 0;
    let mut sampled = false;
    for i in order {
        let Ok(geometry) = Road::new(roads[i].road_points) else {
            continue;
        };
        // The outline has two points for each point of the centre line.
        let cost = 3 * geometry.interpolated.len();
        if drawn.len() == MAX_DRAWN_ROADS || points + cost > MAX_DRAWN_POINTS {
            sampled = true;
            break;
        }
        points += cost;
        drawn.push((i, geometry));
    }
    drawn.sort_by_key(|&(i, _)| i);
    (drawn, sampled)
}

/// Places road labels, each given with the pixel at its road's end, where each is written: its
/// top-left corner at the road's end, moved left to stay inside `bounds` (the plotting area in
/// pixels) and up or down by up to [`LABEL_NUDGES`] lines where it would cover a label placed
/// before it. A label with no free place is left out (`None`), so that labels never pile up.
fn place_labels(
    labels: &[(&str, (i32, i32))],
    bounds: &(Range<i32>, Range<i32>),
) -> Vec<Option<(i32, i32)>> {
    let height = (f64::from(ROAD_LABEL.1) * SVG_FONT_SCALE).ceil() as i32;
    let mut taken: Vec<((i32, i32), (i32, i32))> = Vec::new();
    let mut places = Vec::new();
    for &(label, (end_x, end_y)) in labels {
        let width = text_width_px(label, ROAD_LABEL.1).ceil() as i32;
        let x = end_x.min(bounds.0.end - width).max(bounds.0.start);
        let free = |y: i32| {
            taken.iter().all(|&((tx, ty), (tw, th))| {
                x + width <= tx || tx + tw <= x || y + height <= ty || ty + th <= y
            })
        };
        // At the end first, then a line below, a line above, two below, ...
        let place = (0..=2 * LABEL_NUDGES)
            .map(|k| {
                let lines = (k + 1) / 2;
                let direction = if k % 2 == 1 { 1 } else { -1 };
                end_y + direction * lines * (height + 1)
            })
            .map(|y| y.min(bounds.1.end - height).max(bounds.1.start))
            .find(|&y| free(y));
        if let Some(y) = place {
            taken.push(((x, y), (width, height)));
        }
        places.push(place.map(|y| (x, y)));
    }
    places
}

/// Draws the roads on a `map_size_m` square map: the road surface between its edges (one
/// `<polygon>` per road), the centre line, a start marker and, for up to [`MAX_LABELLED_ROADS`]
/// roads, the road's label at its end (see [`place_labels`]). Of many roads it draws a seeded
/// sample (see [`roads_to_draw`]) and says under the title how many of how many. Roads whose
/// geometry cannot be built are skipped; returns how many were drawn.
pub fn roads_svg(path: &Path, title: &str, roads: &[MapRoad], map_size_m: f64) -> Result<usize> {
    let err = plot_error(path);
    let (drawn, sampled) = roads_to_draw(roads);
    let note = (drawn.len() < roads.len()).then(|| {
        let why = if sampled {
            ", a seeded random sample"
        } else {
            "; the others' geometry cannot be built"
        };
        format!(
            "{} of {} roads drawn{why}",
            thousands(drawn.len()),
            thousands(roads.len())
        )
    });
    let (root, area) = picture(path, (800, 800), title, note.as_deref())?;
    let mut chart = ChartBuilder::on(&area)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(50)
        .margin_right(room_for_last_label(&whole(&map_size_m)))
        .build_cartesian_2d(0.0..map_size_m, 0.0..map_size_m)
        .map_err(&err)?;
    draw_map_mesh(&mut chart).map_err(&err)?;
    let mut ends = Vec::new();
    for (i, geometry) in &drawn {
        let colour = Palette99::pick(*i).to_rgba();
        let centre: Vec<(f64, f64)> = geometry.interpolated.iter().map(|p| (p[0], p[1])).collect();
        chart
            .draw_series(std::iter::once(Polygon::new(
                road_outline(geometry),
                colour.mix(0.3).filled(),
            )))
            .map_err(&err)?;
        chart
            .draw_series(LineSeries::new(
                centre.iter().copied(),
                colour.stroke_width(1),
            ))
            .map_err(&err)?;
        if let (Some(&start), Some(end)) = (centre.first(), centre.last()) {
            chart
                .draw_series(std::iter::once(Circle::new(start, 5, BLACK.filled())))
                .map_err(&err)?;
            ends.push((roads[*i].label.as_str(), chart.backend_coord(end)));
        }
    }
    // Labels go on top of every road, so that no later road covers one.
    if drawn.len() <= MAX_LABELLED_ROADS {
        let bounds = chart.plotting_area().get_pixel_range();
        for ((label, _), place) in ends.iter().zip(place_labels(&ends, &bounds)) {
            if let Some(corner) = place {
                root.draw(&Text::new(*label, corner, ROAD_LABEL))
                    .map_err(&err)?;
            }
        }
    }
    root.present().map_err(&err)?;
    Ok(drawn.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_move_clear_of_each_other_and_stay_inside() {
        let bounds = (0..400, 0..300);
        let labels = [("#1", (100, 100)); 9];
        let places = place_labels(&labels, &bounds);
        // The end, three lines below and three above: 7 places, then none.
        assert_eq!(places.iter().flatten().count(), 7);
        assert_eq!(places[0], Some((100, 100)));
        assert_eq!(places[1], Some((100, 112)));
        assert_eq!(places[2], Some((100, 88)));
        assert_eq!(places[8], None);
        // A label at the right edge moves left, inside the bounds.
        let places = place_labels(&[("a long label", (399, 299))], &bounds);
        let (x, y) = places[0].expect("placed");
        assert!(x + text_width_px("a long label", ROAD_LABEL.1).ceil() as i32 <= 400);
        assert!(y + 11 <= 300);
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
