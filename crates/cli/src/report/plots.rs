//! SVG pictures of runs, drawn with plotters' SVG backend (text as SVG `<text>`, no fonts
//! loaded): the failing roads on the map, fitness over a run, and a histogram of max BOLP; and
//! what the pictures share: a title wrapped to the picture's width.
//!
//! The SVG backend cannot measure text, so its width is estimated per character
//! ([`text_width_px`]), and titles and road labels are laid out with that estimate so that they
//! stay inside the picture and clear of each other. A map of many failing roads draws a seeded
//! sample of them, so that its file stays small enough to open (under 2 MB), and says so under
//! its title.

use crate::files::records::{known, TestRecord};
use anyhow::{anyhow, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use road_sim::{Point, Road};
use std::ops::Range;
use std::path::Path;
use wogan_core::Phase;

/// Caption font: the lines of a picture's title.
const CAPTION: (&str, u32) = ("sans-serif", 20);
/// Font of the line under a title that says what the picture leaves out.
const NOTE: (&str, u32) = ("sans-serif", 15);
/// Font of a road's label on the map.
const ROAD_LABEL: (&str, u32) = ("sans-serif", 13);
/// plotters writes a font of size `s` as the SVG `font-size` `s / 1.24`.
const SVG_FONT_SCALE: f64 = 1.0 / 1.24;
/// Estimated advance of one character, in ems of the SVG font size. Sans-serif text averages
/// about 0.55 em per character; the estimate errs wide so that text laid out with it fits.
pub const CHAR_WIDTH_EM: f64 = 0.6;
/// Space around a picture's title and chart, pixels.
const MARGIN: i32 = 10;
/// Space kept free on each side of a title line, pixels.
const TITLE_SIDE_PX: u32 = 10;
/// Most lines a title is wrapped into; a longer title's last line ends with an ellipsis.
const MAX_TITLE_LINES: usize = 3;
/// Height of the area under a chart that holds the x axis's labels, pixels.
const X_LABEL_AREA: u32 = 40;
/// The font size plotters draws axis labels in.
const AXIS_LABEL_SIZE: u32 = 12;

/// Turns a plotting error (which borrows nothing worth keeping) into an `anyhow` error.
pub(crate) fn plot_error<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> anyhow::Error + '_ {
    move |e| anyhow!("cannot draw {}: {e}", path.display())
}

/// An axis label without decimals.
pub fn whole(value: &f64) -> String {
    format!("{value:.0}")
}

/// A count with thousands separated by commas (`10,000`).
fn thousands(count: usize) -> String {
    let digits = count.to_string();
    let mut text = String::new();
    for (i, digit) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            text.push(',');
        }
        text.push(digit);
    }
    text
}

/// Estimated width in pixels of `text` drawn in a plotters font of `size`.
pub fn text_width_px(text: &str, size: u32) -> f64 {
    text.chars().count() as f64 * f64::from(size) * SVG_FONT_SCALE * CHAR_WIDTH_EM
}

/// Splits `title` into lines of at most `max_chars` characters: between the ` / `-separated
/// parts of a configuration label where it can (so that `oob 0.85` stays on one line), between
/// words where it must, and within a word longer than a line. At most [`MAX_TITLE_LINES`]
/// lines: a longer title's last line is cut and ends with `…`.
pub fn wrap_title(title: &str, max_chars: usize) -> Vec<String> {
    let max_chars = max_chars.max(2);
    let length = |text: &str| text.chars().count();
    let mut pieces: Vec<String> = Vec::new();
    for part in title.split_inclusive(" / ") {
        if length(part.trim_end()) <= max_chars {
            pieces.push(part.to_owned());
            continue;
        }
        for word in part.split_inclusive(' ') {
            let chars: Vec<char> = word.chars().collect();
            pieces.extend(
                chars
                    .chunks(max_chars)
                    .map(|c| c.iter().collect::<String>()),
            );
        }
    }
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for piece in pieces {
        // The line's trailing space ends up inside it; the piece's own does not count.
        if !line.is_empty() && length(&line) + length(piece.trim_end()) > max_chars {
            lines.push(line.trim_end().to_owned());
            line.clear();
        }
        line.push_str(&piece);
    }
    if !line.trim().is_empty() {
        lines.push(line.trim_end().to_owned());
    }
    if lines.len() > MAX_TITLE_LINES {
        lines.truncate(MAX_TITLE_LINES);
        let last = &mut lines[MAX_TITLE_LINES - 1];
        let kept: String = last.chars().take(max_chars - 1).collect();
        *last = format!("{kept}…");
    }
    lines
}

/// Draws `title` centred at the top of `area` in a font of `size`, wrapped to the area's width,
/// and `note` under it in a smaller font when given; returns the area below them.
pub fn titled<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    size: u32,
    note: Option<&str>,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    let width = f64::from(area.dim_in_pixel().0.saturating_sub(2 * TITLE_SIDE_PX));
    let max_chars = |size: u32| (width / text_width_px("x", size)).floor() as usize;
    let mut rest = area.clone();
    for line in wrap_title(title, max_chars(size)) {
        rest = rest.titled(&line, (CAPTION.0, size))?;
    }
    for line in note.map_or_else(Vec::new, |n| wrap_title(n, max_chars(NOTE.1))) {
        rest = rest.titled(&line, NOTE)?;
    }
    Ok(rest)
}

/// A picture's drawing area with a white background, its margin and its title: returns the
/// whole picture (to draw on in pixels) and the area left for the chart.
fn picture<'a>(
    path: &'a Path,
    size: (u32, u32),
    title: &str,
    note: Option<&str>,
) -> Result<(
    DrawingArea<SVGBackend<'a>, Shift>,
    DrawingArea<SVGBackend<'a>, Shift>,
)> {
    let err = plot_error(path);
    let root = SVGBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(&err)?;
    let framed = root.margin(MARGIN, MARGIN, MARGIN, MARGIN);
    let chart_area = titled(&framed, title, CAPTION.1, note).map_err(&err)?;
    Ok((root, chart_area))
}

/// Space to keep right of a chart, beyond the picture's margin, for the label of the x axis's
/// last value (`last_label`), which is centred on the axis's end: the part of its estimated
/// width that the margin does not hold, pixels.
fn room_for_last_label(last_label: &str) -> u32 {
    let half = text_width_px(last_label, AXIS_LABEL_SIZE) / 2.0;
    let beyond = (half + 1.0 - f64::from(MARGIN)).ceil();
    if beyond > 0.0 {
        beyond as u32
    } else {
        0
    }
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

/// Draws fitness over a run's tests in order: the random phase shaded, a line through the
/// fitness values, failures as red dots and passes as small blue ones.
pub fn fitness_svg(path: &Path, title: &str, tests: &[TestRecord]) -> Result<()> {
    let err = plot_error(path);
    let (root, area) = picture(path, (900, 450), title, None)?;
    let last_x = tests.len().max(1) as f64 + 0.5;
    let mut chart = ChartBuilder::on(&area)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(50)
        .margin_right(room_for_last_label(&tests.len().to_string()))
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

/// Widest bin of a max-BOLP histogram (and the width without a failure threshold).
pub const MAX_BOLP_BIN_WIDTH: f64 = 0.05;
/// Fewest bins of a max-BOLP histogram below the failure threshold.
pub const MIN_BINS_BELOW_TOLERANCE: usize = 10;
/// Space kept free above the tallest bar of a histogram for its legend, pixels (the legend is
/// 5 pixels below the top of the plot and about 30 high).
const LEGEND_CLEARANCE_PX: f64 = 45.0;

/// The bins of a max-BOLP histogram, derived from the failure threshold so that the range
/// around it is resolved whatever it is (0.85 for beamng-ai-proxy, 0.10 for dave2-proxy): the
/// threshold on a bin edge with at least [`MIN_BINS_BELOW_TOLERANCE`] bins below it, none wider
/// than [`MAX_BOLP_BIN_WIDTH`], and the axis up to twice the threshold (at most 1). Without a
/// threshold, bins of [`MAX_BOLP_BIN_WIDTH`] over [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BolpBins {
    /// Width of a bin.
    pub width: f64,
    /// Number of bins, from 0.
    pub count: usize,
}

impl BolpBins {
    /// The bins for a failure threshold, if known and in (0, 1].
    pub fn for_tolerance(tolerance: Option<f64>) -> Self {
        // The slack makes a ratio that is whole but for rounding (0.85 / 0.05) count as whole.
        let whole_up = |ratio: f64| (ratio - 1e-9).ceil().max(1.0) as usize;
        match tolerance {
            Some(t) if t > 0.0 && t <= 1.0 => {
                let below = whole_up(t / MAX_BOLP_BIN_WIDTH).max(MIN_BINS_BELOW_TOLERANCE);
                let width = t / below as f64;
                Self {
                    width,
                    count: whole_up((2.0 * t).min(1.0) / width),
                }
            }
            _ => Self {
                width: MAX_BOLP_BIN_WIDTH,
                count: whole_up(1.0 / MAX_BOLP_BIN_WIDTH),
            },
        }
    }

    /// The end of the axis: the last bin's upper edge.
    pub fn upper(&self) -> f64 {
        self.width * self.count as f64
    }

    /// Counts of `values` per bin, and how many were above the axis. Values below 0 count in
    /// the first bin, values above the axis in the last; values that are not finite are left
    /// out.
    pub fn counts(&self, values: &[f64]) -> (Vec<u32>, usize) {
        let mut counts = vec![0u32; self.count];
        let mut above = 0;
        for &v in values.iter().filter(|v| v.is_finite()) {
            // The slack keeps a value on the axis's end (BOLP 1 on [0, 1]) from counting as above.
            above += usize::from(v > self.upper() + 1e-9);
            let bin = ((v / self.width).floor().max(0.0) as usize).min(self.count - 1);
            counts[bin] += 1;
        }
        (counts, above)
    }
}

/// A number with at most 3 decimals and no trailing zeros (`0.2`, `1.008`).
fn short(value: f64) -> String {
    let text = format!("{value:.3}");
    text.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// Draws a histogram of max BOLP (one `<rect>` per non-empty bin, see [`BolpBins`]) and the
/// failure threshold, with room above the bars for the threshold's legend.
pub fn bolp_histogram_svg(
    path: &Path,
    title: &str,
    max_bolps: &[f64],
    oob_tolerance: Option<f64>,
) -> Result<()> {
    let err = plot_error(path);
    let (root, area) = picture(path, (800, 450), title, None)?;
    let bins = BolpBins::for_tolerance(oob_tolerance);
    let (counts, above) = bins.counts(max_bolps);
    let tallest = f64::from(counts.iter().copied().max().unwrap_or(0).max(1));
    let plot_height = f64::from(area.dim_in_pixel().1.saturating_sub(X_LABEL_AREA));
    let top = if oob_tolerance.is_some() && plot_height > 2.0 * LEGEND_CLEARANCE_PX {
        // The tallest bar ends LEGEND_CLEARANCE_PX below the top, under the legend.
        (tallest * 1.1).max(tallest * plot_height / (plot_height - LEGEND_CLEARANCE_PX))
    } else {
        tallest * 1.1
    };
    let mut chart = ChartBuilder::on(&area)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(50)
        .margin_right(room_for_last_label(&short(bins.upper())))
        .build_cartesian_2d(0.0..bins.upper(), 0.0..top)
        .map_err(&err)?;
    let x_desc = if above > 0 {
        format!(
            "max BOLP (the last bin also counts {above} test(s) above {})",
            short(bins.upper())
        )
    } else {
        "max BOLP".to_owned()
    };
    chart
        .configure_mesh()
        .max_light_lines(0)
        .y_label_formatter(&whole)
        .x_desc(x_desc)
        .y_desc("tests")
        .draw()
        .map_err(&err)?;
    let bars = counts
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(i, &c)| {
            let low = i as f64 * bins.width;
            Rectangle::new(
                [(low, 0.0), (low + bins.width, f64::from(c))],
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
        let bins = BolpBins::for_tolerance(None);
        let (counts, above) = bins.counts(&[0.0, 0.04, 0.05, 0.99, 1.0, 1.7, -0.1, f64::NAN]);
        assert_eq!(counts.len(), 20);
        assert_eq!(counts[0], 3);
        assert_eq!(counts[1], 1);
        assert_eq!(counts[19], 3);
        assert_eq!(above, 1);
    }

    #[test]
    fn bolp_bins_resolve_the_range_around_the_tolerance() {
        // beamng-ai-proxy's 0.85: the 0.05 bins over [0, 1] of old, the threshold on an edge.
        let bins = BolpBins::for_tolerance(Some(0.85));
        assert_eq!(bins.count, 20);
        assert!((bins.width - 0.05).abs() < 1e-12 && (bins.upper() - 1.0).abs() < 1e-12);
        // dave2-proxy's 0.10: bins of 0.01 over [0, 0.2].
        let bins = BolpBins::for_tolerance(Some(0.1));
        assert_eq!(bins.count, 20);
        assert!((bins.width - 0.01).abs() < 1e-12 && (bins.upper() - 0.2).abs() < 1e-12);
        let (counts, above) = bins.counts(&[0.095, 0.105, 0.5]);
        assert_eq!((counts[9], counts[10], counts[19], above), (1, 1, 1, 1));
        // A threshold that is no fraction falls back to [0, 1].
        assert_eq!(
            BolpBins::for_tolerance(Some(3.0)),
            BolpBins::for_tolerance(None)
        );
    }

    #[test]
    fn titles_wrap_between_the_parts_of_a_label() {
        let title = "failing roads (A: wogan / beamng-ai-proxy / fitness bolp / decay 0.95 / oob 0.85 / 70.0 km/h)";
        let lines = wrap_title(title, 60);
        assert_eq!(
            lines,
            [
                "failing roads (A: wogan / beamng-ai-proxy / fitness bolp /",
                "decay 0.95 / oob 0.85 / 70.0 km/h)"
            ]
        );
        assert_eq!(wrap_title("short", 60), ["short"]);
        // A word longer than a line is cut; more than three lines end with an ellipsis.
        let long = "x".repeat(50);
        assert_eq!(
            wrap_title(&long, 20),
            ["x".repeat(20), "x".repeat(20), "x".repeat(10)]
        );
        let longer = "y".repeat(100);
        let lines = wrap_title(&longer, 20);
        assert_eq!(lines.len(), MAX_TITLE_LINES);
        assert_eq!(lines[2], format!("{}…", "y".repeat(19)));
        assert_eq!(thousands(10_000), "10,000");
        assert_eq!(thousands(500), "500");
        assert_eq!(thousands(1_234_567), "1,234,567");
    }

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
