//! Fitness over a run: each executed test's fitness by its position, by phase, with the failure
//! threshold.

use super::layout::{picture, plot_error, room_for_last_label, whole, X_LABEL_AREA};
use crate::files::records::{known, TestRecord};
use anyhow::Result;
use plotters::prelude::*;
use std::path::Path;
use wogan_core::Phase;

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
