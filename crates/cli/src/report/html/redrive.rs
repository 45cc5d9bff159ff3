//! `wogan report --html --traces N`: the N failing roads of highest BOLP driven again with the
//! driver their run recorded, traced, so that the page can show the car's path and its BOLP along
//! the drive. Only a built-in driver is driven again (wogan never starts a command or loads a
//! model a file names, and an executor's run was driven by the executor), with the simulation and
//! driver settings of the run's header, checked as a `--config` file's are
//! ([`RunHeader::drive_settings`](crate::files::run_file::RunHeader::drive_settings)); a drive
//! whose outcome now differs from the recorded one is shown as it went now, and said so. A drive
//! that Ctrl-C stopped is no outcome: it is not shown, and the page says how many were stopped.

use super::failing_roads::{FailingRoad, RoadTrace, TRACE_SAMPLES};
use crate::files::run_file::RunFile;
use anyhow::{Context, Result};
use rayon::prelude::*;
use road_sim::{simulate, DriverConfig, DriverKind, Road, Sample, SimConfig, StopReason};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};

/// What could not be driven again, as stderr and the page say it.
#[derive(Debug, Default)]
pub struct NotDrivenAgain {
    /// Why, once for each run whose roads were not driven (its file first) and once for each
    /// road that failed on its own.
    pub reasons: Vec<String>,
    /// Runs whose header holds settings no run is made with: bad inputs, as the exit status says.
    pub bad_headers: usize,
}

/// Drives again the `count` roads of `roads` of highest max BOLP (ties: the earlier first) whose
/// runs (`groups[road.group][road.run]`) recorded a built-in driver, and keeps their traces. Each
/// run's settings are read from its header once; a run whose settings cannot be used has none of
/// its roads driven, and is named once.
pub fn redrive_worst(
    roads: &mut [FailingRoad],
    groups: &[&[RunFile]],
    count: usize,
    stop: &AtomicBool,
) -> NotDrivenAgain {
    let mut order: Vec<usize> = (0..roads.len()).collect();
    order.sort_by(|&a, &b| {
        roads[b]
            .max_bolp
            .total_cmp(&roads[a].max_bolp)
            .then(a.cmp(&b))
    });
    order.truncate(count);
    let mut not_driven = NotDrivenAgain::default();
    // Each run's settings, read once, for the runs of the roads asked for.
    let mut settings: BTreeMap<(usize, usize), Option<Settings>> = BTreeMap::new();
    for &index in &order {
        let road = &roads[index];
        settings.entry((road.group, road.run)).or_insert_with(|| {
            let run = &groups[road.group][road.run];
            match run_settings(run) {
                Ok(settings) => Some(settings),
                Err(refusal) => {
                    let reason = match &refusal {
                        Refusal::BadHeader(error) => {
                            not_driven.bad_headers += 1;
                            error
                        }
                        Refusal::NotDrivable(error) => error,
                    };
                    not_driven
                        .reasons
                        .push(format!("{}: not driven again: {reason:#}", road.run_file));
                    None
                }
            }
        });
    }
    // `None`: not driven, or the drive did not end (Ctrl-C); it is no result to show.
    let traced: Vec<(usize, Option<Result<RoadTrace>>)> = order
        .par_iter()
        .filter_map(|&index| {
            let road = &roads[index];
            let settings = settings.get(&(road.group, road.run))?.as_ref()?;
            let trace = redrive(road, settings, stop).transpose().map(|trace| {
                trace.with_context(|| {
                    format!("{} test {}: not driven again", road.run_file, road.test)
                })
            });
            Some((index, trace))
        })
        .collect();
    let mut cut_short = 0;
    for (index, trace) in traced {
        match trace {
            Some(Ok(trace)) => roads[index].trace = Some(trace),
            Some(Err(error)) => not_driven.reasons.push(format!("{error:#}")),
            None => cut_short += 1,
        }
    }
    if cut_short > 0 {
        not_driven.reasons.push(format!(
            "{cut_short} of the {} roads asked for were not driven again: Ctrl-C or SIGTERM \
             stopped the drives",
            order.len()
        ));
    }
    not_driven
}

/// What a run's roads are driven again with: its driver's name and settings.
struct Settings {
    /// The driver, as the trace names it.
    driver: DriverKind,
    /// The simulation's settings.
    sim: SimConfig,
    /// The driver's settings.
    config: DriverConfig,
}

/// Why a run's roads are not driven again.
enum Refusal {
    /// The header holds what no run is made with (no header, settings out of range).
    BadHeader(anyhow::Error),
    /// The run is sound but wogan cannot drive it: a controller, a camera network, an executor.
    NotDrivable(anyhow::Error),
}

/// The settings `run` recorded, checked as a `--config` file's are.
fn run_settings(run: &RunFile) -> Result<Settings, Refusal> {
    let header = run
        .header
        .as_ref()
        .ok_or_else(|| Refusal::BadHeader(anyhow::anyhow!("the run has no header")))?;
    if let Some(why) = header.executor_run() {
        return Err(Refusal::NotDrivable(anyhow::anyhow!(why)));
    }
    let Some(kind) = header.driver else {
        return Err(Refusal::NotDrivable(anyhow::anyhow!(
            "its driver ({}) is not one of wogan's",
            header.simulator
        )));
    };
    if DriverConfig::built_in(kind).is_none() {
        return Err(Refusal::NotDrivable(anyhow::anyhow!(
            "its driver ({kind}) is not built into wogan"
        )));
    }
    let (sim, config) = header.drive_settings(None).map_err(Refusal::BadHeader)?;
    Ok(Settings {
        driver: kind,
        sim,
        config,
    })
}

/// Drives `road` again with its run's `settings`; `None` when Ctrl-C or SIGTERM came before the
/// drive ended (or before it began).
fn redrive(
    road: &FailingRoad,
    settings: &Settings,
    stop: &AtomicBool,
) -> Result<Option<RoadTrace>> {
    if stop.load(Ordering::SeqCst) {
        return Ok(None);
    }
    let geometry = Road::new(&road.road_points).map_err(|error| anyhow::anyhow!("{error}"))?;
    let mut result = simulate(
        &geometry,
        settings.config.build().as_mut(),
        &settings.sim,
        true,
        Some(stop),
    );
    if result.reason == Some(StopReason::Interrupted) || stop.load(Ordering::SeqCst) {
        // Stopped, not ended: the driver's ERROR would be no outcome of the road.
        return Ok(None);
    }
    let samples = result.trace.take().unwrap_or_default();
    Ok(Some(RoadTrace {
        driver: settings.driver.to_string(),
        outcome: result.outcome.name().to_owned(),
        max_bolp: result.max_bolp,
        samples: kept_samples(&samples, TRACE_SAMPLES),
    }))
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
