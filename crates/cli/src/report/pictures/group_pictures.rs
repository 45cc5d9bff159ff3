//! The pictures of a group of runs: its failing roads on the map, a BOLP histogram and each run's
//! fitness over time.

use super::bolp_histogram::bolp_histogram_svg;
use super::fitness_plot::fitness_svg;
use super::road_map::{roads_svg, MapRoad};
use crate::files::records::known;
use crate::files::run_file::RunFile;
use anyhow::Result;
use std::path::Path;

/// File names of a group's pictures (relative to the report).
pub struct Pictures {
    /// The failing roads on the map.
    pub roads: String,
    /// The max-BOLP histogram.
    pub bolp: String,
    /// Fitness over each run, in input order.
    pub fitness: Vec<String>,
}

/// Draws a group's pictures into `out`, named after `slug`.
pub fn draw_group(out: &Path, slug: &str, label: &str, runs: &[&RunFile]) -> Result<Pictures> {
    let map_size_m = runs
        .iter()
        .filter_map(|r| r.header.as_ref())
        .map(|h| h.map_size_m)
        .fold(0.0, f64::max);
    let map_size_m = if map_size_m > 0.0 { map_size_m } else { 200.0 };
    // Test ids repeat across runs, so with several runs the label names the run too.
    let several = runs.len() > 1;
    let failing: Vec<MapRoad> = runs
        .iter()
        .enumerate()
        .flat_map(|(i, r)| r.tests.iter().filter(|t| t.failed()).map(move |t| (i, t)))
        .map(|(i, t)| MapRoad {
            label: if several {
                format!("r{} #{}", i + 1, t.id)
            } else {
                format!("#{}", t.id)
            },
            road_points: &t.execution.road_points,
        })
        .collect();
    let roads = format!("roads.{slug}.svg");
    roads_svg(
        &out.join(&roads),
        &format!("failing roads ({label})"),
        &failing,
        map_size_m,
    )?;
    let bolps: Vec<f64> = runs
        .iter()
        .flat_map(|r| {
            r.tests
                .iter()
                .filter_map(|t| known(t.execution.result.max_bolp))
        })
        .collect();
    let tolerance = runs
        .iter()
        .filter_map(|r| r.header.as_ref())
        .find_map(|h| h.oob_tolerance);
    let bolp = format!("bolp.{slug}.svg");
    bolp_histogram_svg(
        &out.join(&bolp),
        &format!("max BOLP of every test ({label})"),
        &bolps,
        tolerance,
    )?;
    let mut fitness = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let name = format!("fitness.{slug}.r{}.svg", i + 1);
        let file = run
            .path
            .file_name()
            .map_or_else(String::new, |f| f.to_string_lossy().into_owned());
        fitness_svg(
            &out.join(&name),
            &format!("fitness over the run: {file}"),
            &run.tests,
        )?;
        fitness.push(name);
    }
    Ok(Pictures {
        roads,
        bolp,
        fitness,
    })
}
