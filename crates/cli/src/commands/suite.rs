//! `wogan suite`: the regression suite a team keeps in its repository. `add` keeps the failing
//! roads of runs (each once; with `--max N` the most different ones, by farthest-point selection
//! on the heading profiles' distance, never dropping a road the suite already holds); `list`
//! shows it.
//! The file's layout is [`crate::files::suite_file`].

use super::Status;
use crate::files::output_file::same_file;
use crate::files::records::{RecordedDrive, RoadOrigin, SuiteRoad};
use crate::files::run_file::read_run;
use crate::files::suite_file::{self, farthest_points, profile_of, Suite};
use anyhow::{bail, Result};
use clap::{Args, Subcommand};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// Options of `wogan suite`.
#[derive(Debug, Args)]
pub struct SuiteArgs {
    #[command(subcommand)]
    pub action: SuiteAction,
}

/// What `wogan suite` does.
#[derive(Debug, Subcommand)]
pub enum SuiteAction {
    /// Keep the failing roads of runs in a suite file (created when missing).
    Add {
        /// JSON lines of `wogan run`.
        #[arg(value_name = "RUN", required = true)]
        runs: Vec<PathBuf>,
        /// The suite file to add to.
        #[arg(long, value_name = "SUITE")]
        to: PathBuf,
        /// Hold at most N roads: the new ones most different from those kept (the roads already
        /// in the suite are never dropped).
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
        max: Option<u64>,
    },
    /// List a suite's roads.
    List {
        /// The suite file.
        #[arg(value_name = "SUITE")]
        suite: PathBuf,
    },
}

/// Runs `wogan suite`.
pub fn run(args: &SuiteArgs) -> Result<Status> {
    match &args.action {
        SuiteAction::Add { runs, to, max } => add(runs, to, max.map(|m| m as usize)),
        SuiteAction::List { suite } => list(suite),
    }
}

/// A failing road of a run, before it is kept.
struct Candidate {
    road: SuiteRoad,
    profile: Vec<f64>,
}

/// `wogan suite add`.
fn add(runs: &[PathBuf], to: &Path, max: Option<usize>) -> Result<Status> {
    if let Some(run) = runs.iter().find(|r| same_file(to, r)) {
        bail!(
            "--to {} is one of the runs read ({}); give the suite its own file",
            to.display(),
            run.display()
        );
    }
    let mut suite = if to.exists() {
        suite_file::read(to)?
    } else {
        Suite::default()
    };
    let mut problems = 0;
    let mut seen: HashSet<String> = suite
        .roads
        .iter()
        .map(|r| points_key(&r.road_points))
        .collect();
    let mut names: HashSet<String> = suite.roads.iter().map(|r| r.name.clone()).collect();
    let mut candidates: Vec<Candidate> = Vec::new();
    let (mut failing, mut duplicates) = (0, 0);
    for path in runs {
        let run = read_run(path)?;
        for problem in &run.problems {
            eprintln!("wogan suite: {problem}");
        }
        problems += run.problems.len();
        let Some(header) = &run.header else {
            eprintln!(
                "wogan suite: {}: no header: not a wogan run",
                path.display()
            );
            problems += 1;
            continue;
        };
        let stem = path
            .file_stem()
            .map_or_else(|| "run".to_owned(), |s| s.to_string_lossy().into_owned());
        for test in run.tests.iter().filter(|t| t.failed()) {
            failing += 1;
            if !seen.insert(points_key(&test.execution.road_points)) {
                duplicates += 1;
                continue;
            }
            let Some(profile) = profile_of(&test.execution.road_points) else {
                eprintln!(
                    "wogan suite: {}: test {}: its road points make no road",
                    path.display(),
                    test.id
                );
                problems += 1;
                continue;
            };
            let mut name = format!("{stem}#{}", test.id);
            let mut n = 2;
            while names.contains(&name) {
                name = format!("{stem}#{}-{n}", test.id);
                n += 1;
            }
            names.insert(name.clone());
            candidates.push(Candidate {
                road: SuiteRoad {
                    name,
                    road_points: test.execution.road_points.clone(),
                    recorded: RecordedDrive {
                        outcome: test.execution.result.outcome,
                        max_bolp: test.execution.result.max_bolp,
                    },
                    origin: RoadOrigin {
                        run: path.display().to_string(),
                        test: test.id,
                        seed: header.seed,
                        driver: header.simulator.clone(),
                        oob_tolerance: header.oob_tolerance,
                        wogan: header.version.clone(),
                    },
                },
                profile,
            });
        }
    }
    let before = suite.roads.len();
    let picked: Vec<usize> = match max {
        Some(total) => {
            let kept: Vec<Vec<f64>> = suite
                .roads
                .iter()
                .filter_map(|r| profile_of(&r.road_points))
                .collect();
            let profiles: Vec<Vec<f64>> = candidates.iter().map(|c| c.profile.clone()).collect();
            let priority: Vec<f64> = candidates
                .iter()
                .map(|c| c.road.recorded.max_bolp)
                .collect();
            farthest_points(&kept, &profiles, &priority, total)
        }
        None => (0..candidates.len()).collect(),
    };
    let over_cap = candidates.len() - picked.len();
    let mut slots: Vec<Option<Candidate>> = candidates.into_iter().map(Some).collect();
    suite.roads.extend(
        picked
            .iter()
            .filter_map(|&i| slots[i].take())
            .map(|c| c.road),
    );
    suite_file::write(to, &suite)?;
    eprintln!(
        "wogan suite: {failing} failing road(s) read, {duplicates} already kept, {over_cap} over \
         the cap; added {}, {} now holds {} road(s)",
        suite.roads.len() - before,
        to.display(),
        suite.roads.len()
    );
    Ok(if problems == 0 {
        Status::AllRead
    } else {
        Status::BadInput
    })
}

/// A road's identity for deduplication: its points exactly as written.
fn points_key(points: &[road_sim::Point]) -> String {
    serde_json::to_string(points).unwrap_or_default()
}

/// `wogan suite list`: one line per road.
fn list(path: &Path) -> Result<Status> {
    let suite = suite_file::read(path)?;
    println!("{} road(s) in {}", suite.roads.len(), path.display());
    for road in &suite.roads {
        let origin = &road.origin;
        let seed = origin
            .seed
            .map_or_else(|| "?".to_owned(), |s| s.to_string());
        println!(
            "{}\t{} max BOLP {:.3}\t{} seed {seed}\t{} points\tfrom {} test {}",
            road.name,
            road.recorded.outcome.name(),
            road.recorded.max_bolp,
            origin.driver,
            road.road_points.len(),
            origin.run,
            origin.test,
        );
    }
    Ok(Status::AllRead)
}
