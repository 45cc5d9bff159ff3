//! `wogan report --html --traces N`: the N failing roads of highest BOLP driven again with the
//! driver their run recorded, traced, so that the page can show the car's path and its BOLP along
//! the drive. Only a built-in driver is driven again (wogan never starts a command or loads a
//! model a file names), with the simulation and driver settings of the run's header; a drive
//! whose outcome now differs from the recorded one is shown as it went now, and said so.

use super::failing_roads::{FailingRoad, RoadTrace, TRACE_SAMPLES};
use crate::files::run_file::RunFile;
use crate::options::config_file::lay_over;
use crate::options::driver_options::driver_config;
use anyhow::{Context, Result};
use rayon::prelude::*;
use road_sim::{simulate, DriverConfig, Road, Sample, SimConfig};
use std::sync::atomic::AtomicBool;

/// Drives again the `count` roads of `roads` of highest max BOLP (ties: the earlier first) whose
/// runs (`groups[road.group][road.run]`) recorded a built-in driver, and keeps their traces.
/// Returns, for each road that could not be driven again, why (the page says it).
pub fn redrive_worst(
    roads: &mut [FailingRoad],
    groups: &[&[RunFile]],
    count: usize,
    stop: &AtomicBool,
) -> Vec<String> {
    let mut order: Vec<usize> = (0..roads.len()).collect();
    order.sort_by(|&a, &b| {
        roads[b]
            .max_bolp
            .total_cmp(&roads[a].max_bolp)
            .then(a.cmp(&b))
    });
    order.truncate(count);
    let traced: Vec<(usize, Result<RoadTrace>)> = order
        .par_iter()
        .map(|&index| {
            let road = &roads[index];
            let run = &groups[road.group][road.run];
            let trace = redrive(road, run, stop)
                .with_context(|| format!("{} test {}: not driven again", road.run_file, road.test));
            (index, trace)
        })
        .collect();
    let mut problems = Vec::new();
    for (index, trace) in traced {
        match trace {
            Ok(trace) => roads[index].trace = Some(trace),
            Err(error) => problems.push(format!("{error:#}")),
        }
    }
    problems
}

/// Drives `road` again as `run` recorded it.
fn redrive(road: &FailingRoad, run: &RunFile, stop: &AtomicBool) -> Result<RoadTrace> {
    let header = run.header.as_ref().context("the run has no header")?;
    let kind = header.driver;
    if DriverConfig::built_in(kind).is_none() {
        anyhow::bail!("its driver ({kind}) is not built into wogan");
    }
    let sim = lay_over::<SimConfig>(header.config.get("sim"), SimConfig::default(), "config.sim")
        .context("the run's header")?;
    let driver = driver_config(
        kind,
        None,
        None,
        header.config.get("driver"),
        None,
        "config.driver",
    )
    .context("the run's header")?;
    let geometry = Road::new(&road.road_points).map_err(|error| anyhow::anyhow!("{error}"))?;
    let mut result = simulate(&geometry, driver.build().as_mut(), &sim, true, Some(stop));
    let samples = result.trace.take().unwrap_or_default();
    Ok(RoadTrace {
        driver: kind.to_string(),
        outcome: result.outcome.name().to_owned(),
        max_bolp: result.max_bolp,
        samples: kept_samples(&samples, TRACE_SAMPLES),
    })
}

/// At most `most` of `samples`, evenly taken, the last always kept: time, x, y, BOLP.
fn kept_samples(samples: &[Sample], most: usize) -> Vec<[f64; 4]> {
    let stride = samples.len().div_ceil(most.max(1)).max(1);
    let mut kept: Vec<[f64; 4]> = samples
        .iter()
        .step_by(stride)
        .map(|s| [s.t, s.x, s.y, s.bolp])
        .collect();
    if let Some(last) = samples.last() {
        if !(samples.len() - 1).is_multiple_of(stride) {
            kept.push([last.t, last.x, last.y, last.bolp]);
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(count: usize) -> Vec<Sample> {
        (0..count)
            .map(|i| Sample {
                t: i as f64,
                bolp: i as f64 / count as f64,
                ..Sample::default()
            })
            .collect()
    }

    #[test]
    fn a_long_trace_is_thinned_evenly_and_keeps_its_last_sample() {
        let kept = kept_samples(&samples(1001), 400);
        assert!(kept.len() <= 401, "{}", kept.len());
        assert_eq!(kept[0][0], 0.0);
        assert_eq!(kept[1][0], 3.0);
        assert_eq!(kept.last().map(|s| s[0]), Some(1000.0));
        assert_eq!(kept_samples(&samples(10), 400).len(), 10);
        assert!(kept_samples(&[], 400).is_empty());
    }
}
