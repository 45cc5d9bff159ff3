//! A histogram of max BOLP: how far the drives of a group got out of their lane, with bins fine
//! enough around the failure threshold to see the near misses.

use super::layout::{picture, plot_error, room_for_last_label, whole, X_LABEL_AREA};
use anyhow::Result;
use plotters::prelude::*;
use std::path::Path;

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
}
