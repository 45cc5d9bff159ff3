//! What the pictures share: fonts, margins, a white picture with its title wrapped to its width,
//! and axis labels.
//!
//! The pictures are drawn with plotters' SVG backend (text as SVG `<text>`, no fonts loaded),
//! which cannot measure text, so its width is estimated per character ([`text_width_px`]), and
//! titles and road labels are laid out with that estimate so that they stay inside the picture
//! and clear of each other.

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// Caption font: the lines of a picture's title.
const CAPTION: (&str, u32) = ("sans-serif", 20);
/// Font of the line under a title that says what the picture leaves out.
const NOTE: (&str, u32) = ("sans-serif", 15);
/// Font of a road's label on the map.
pub(super) const ROAD_LABEL: (&str, u32) = ("sans-serif", 13);
/// plotters writes a font of size `s` as the SVG `font-size` `s / 1.24`.
pub(super) const SVG_FONT_SCALE: f64 = 1.0 / 1.24;
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
pub(super) const X_LABEL_AREA: u32 = 40;
/// The font size plotters draws axis labels in.
const AXIS_LABEL_SIZE: u32 = 12;

/// Turns a plotting error (which borrows nothing worth keeping) into an `anyhow` error.
pub fn plot_error<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> anyhow::Error + '_ {
    move |e| anyhow!("cannot draw {}: {e}", path.display())
}

/// An axis label without decimals.
pub fn whole(value: &f64) -> String {
    format!("{value:.0}")
}

/// A count with thousands separated by commas (`10,000`).
pub(super) fn thousands(count: usize) -> String {
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
pub(super) fn picture<'a>(
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
pub(super) fn room_for_last_label(last_label: &str) -> u32 {
    let half = text_width_px(last_label, AXIS_LABEL_SIZE) / 2.0;
    let beyond = (half + 1.0 - f64::from(MARGIN)).ceil();
    if beyond > 0.0 {
        beyond as u32
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
