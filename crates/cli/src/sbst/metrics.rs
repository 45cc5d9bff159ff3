//! The SBST competition's measures of one run, computed as its pipeline computes them from a result
//! folder: the totals of `generation_stats.csv`, failures, effectiveness (valid / generated),
//! efficiency (generation time per generated test) and its `OOBAnalyzer`'s sides and sparseness of
//! the out-of-bound failures ([`road_sim::oob`]). Sparseness looks only at the 60 m of road around
//! each exit, so unlike the paper's diversity it does not grow with road length.
//!
//! The pipeline's analysis fails a whole run when one OOB cannot be placed on its resampling of
//! the road (no resampled point within 0.5 m of the nearest point, which happens where its
//! samples lie more than 1 m apart). The report then says so, and gives beside it the same
//! sparseness over the OOBs that could be placed, which equals the pipeline's whenever the
//! pipeline's succeeds.

use crate::files::records::{known, TestRecord};
use crate::files::run_file::RunFile;
use road_sim::oob::{self, OobEntry, OobError, OobSummary, SbstTest};
use road_sim::{LaneSide, Outcome, StopReason};

/// Totals of `generation_stats.csv`, counted as the pipeline counts them.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerationStats {
    /// Tests handed to the executor.
    pub generated: u64,
    /// Of those, valid (all of wogan's: it validates before it proposes).
    pub valid: u64,
    /// Of those, invalid.
    pub invalid: u64,
    /// Kept tests that passed.
    pub passed: u64,
    /// Kept tests that failed.
    pub failed: u64,
    /// Kept tests in error.
    pub in_error: u64,
    /// Generation time as the pipeline charges it, seconds.
    pub generation_s: f64,
    /// Execution wall time of every executed test, seconds.
    pub execution_s: f64,
    /// Simulated time of the kept tests, seconds.
    pub simulated_s: f64,
}

impl GenerationStats {
    /// The totals of `run`. A test executed beyond an SBST budget counts as generated and valid
    /// and its execution's wall time counts, but it is not kept: its outcome and simulated time
    /// do not count, as in the pipeline. Runs written before the competition's generation time
    /// was recorded charge the time of choosing and of training.
    pub fn of(run: &RunFile) -> Self {
        let count = |outcome: Outcome| {
            run.tests
                .iter()
                .filter(|t| t.execution.result.outcome == outcome)
                .count() as u64
        };
        let handed = || run.tests.iter().chain(&run.beyond_budget);
        let sum = |tests: &mut dyn Iterator<Item = &TestRecord>, f: fn(&TestRecord) -> f64| {
            tests.filter_map(|t| known(f(t))).sum::<f64>()
        };
        let generated = handed().count() as u64;
        let generation_s = if handed().all(|t| t.sbst_generation_ms.is_some()) {
            sum(&mut handed(), |t| t.sbst_generation_ms.unwrap_or(f64::NAN)) / 1000.0
        } else {
            match &run.summary {
                Some(s) => s.generation_s + s.training_s,
                None => (sum(&mut handed(), |t| t.generation_ms) + run.train_ms) / 1000.0,
            }
        };
        // Tests the pipeline found invalid were generated too (a result folder's).
        let invalid = run.pipeline_invalid as u64;
        Self {
            generated: generated + invalid,
            valid: generated,
            invalid,
            passed: count(Outcome::Pass),
            failed: count(Outcome::Fail),
            in_error: count(Outcome::Error),
            generation_s,
            execution_s: sum(&mut handed(), |t| t.execution.result.execution_ms) / 1000.0,
            simulated_s: sum(&mut run.tests.iter(), |t| t.execution.result.sim_time_s),
        }
    }

    /// The CSV text: the competition's header and one row of totals.
    pub fn csv(&self) -> String {
        format!(
            "test_generated,test_valid,test_invalid,test_passed,test_failed,test_in_error,\
             real_time_generation,real_time_execution,simulated_time_execution\n\
             {},{},{},{},{},{},{},{},{}\n",
            self.generated,
            self.valid,
            self.invalid,
            self.passed,
            self.failed,
            self.in_error,
            self.generation_s,
            self.execution_s,
            self.simulated_s
        )
    }
}

/// The competition's measures of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct SbstMeasures {
    /// Tests handed to execution (kept, and the one beyond a budget; and those the pipeline found
    /// invalid, in a result folder).
    pub generated: usize,
    /// Valid tests over generated ones: 1 for wogan, which validates before it proposes.
    pub effectiveness: Option<f64>,
    /// Candidates wogan rejected as invalid before proposing (the competition never sees them).
    pub invalid_candidates: usize,
    /// Generation time the competition charges per generated test, seconds.
    pub efficiency_s: Option<f64>,
    /// Out-of-lane failures whose car crossed the lane's left edge (the centre line).
    pub exits_left: usize,
    /// Out-of-lane failures whose car crossed the lane's right edge (the road's edge).
    pub exits_right: usize,
    /// The pipeline's `OOBAnalyzer` summary, or why it cannot be made.
    pub oob: Result<OobSummary, String>,
    /// The same summary over the OOBs the analysis could place (failed ones left out), or why
    /// it cannot be made.
    pub oob_placed: Result<OobSummary, String>,
    /// OOBs the analysis could not place.
    pub oob_unplaced: usize,
}

impl SbstMeasures {
    /// Measures `run`. The sparseness is the pipeline's up to
    /// [`oob::sparseness::EXACT_UP_TO`] OOBs, above that of a sample drawn with the run's seed
    /// ([`oob::summarise_bounded`]); Ctrl-C stops it (the report then ends without its figures).
    pub fn of(run: &RunFile) -> Self {
        let stats = GenerationStats::of(run);
        let seed = run.header.as_ref().and_then(|h| h.seed).unwrap_or(0);
        let stop = Some(crate::interrupt::stop_signal());
        let summarise =
            |e: &[OobEntry]| oob::summarise_bounded(e, seed, stop).map_err(|e| e.to_string());
        let (oob, oob_placed, oob_unplaced) = match oob_tests(run) {
            Err(e) => (Err(e.to_string()), Err(e.to_string()), 0),
            Ok(tests) => {
                let entries = oob::entries(&tests);
                let unplaced = entries.iter().filter(|e| e.failure.is_some()).count();
                let oob = summarise(&entries);
                // With every OOB placed the two summaries are one: measured once.
                let placed = if unplaced == 0 {
                    oob.clone()
                } else {
                    let placed: Vec<OobEntry> = entries
                        .iter()
                        .filter(|entry| entry.failure.is_none())
                        .cloned()
                        .collect();
                    summarise(&placed)
                };
                (oob, placed, unplaced)
            }
        };
        let generated = stats.generated as usize;
        let exits = |side: LaneSide| {
            run.tests
                .iter()
                .filter_map(|t| t.execution.result.oob)
                .filter(|exit| exit.side == side)
                .count()
        };
        Self {
            generated,
            effectiveness: (generated > 0).then(|| stats.valid as f64 / generated as f64),
            invalid_candidates: run
                .tests
                .iter()
                .chain(&run.beyond_budget)
                .map(|t| t.invalid_candidates)
                .sum(),
            efficiency_s: (generated > 0 && stats.generation_s.is_finite())
                .then(|| stats.generation_s / generated as f64),
            exits_left: exits(LaneSide::Left),
            exits_right: exits(LaneSide::Right),
            oob,
            oob_placed,
            oob_unplaced,
        }
    }

    /// A figure of the pipeline's OOB summary, when it could be made and is a number.
    pub fn oob_figure(&self, f: fn(&OobSummary) -> f64) -> Option<f64> {
        figure(&self.oob, f)
    }

    /// A figure of the summary over the placed OOBs, when it could be made and is a number.
    pub fn oob_placed_figure(&self, f: fn(&OobSummary) -> f64) -> Option<f64> {
        figure(&self.oob_placed, f)
    }
}

/// `f` of `summary`, when there is one and `f` is a number.
fn figure(summary: &Result<OobSummary, String>, f: fn(&OobSummary) -> f64) -> Option<f64> {
    summary.as_ref().ok().map(f).filter(|v| v.is_finite())
}

/// Why a run's OOBs cannot be analysed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OobSummaryError {
    /// The run was written before test records said where the car left its lane.
    #[error("test {0} left its lane but its record does not say where (a run written before wogan recorded it)")]
    NoExitRecorded(usize),
    /// The pipeline's analysis itself fails on these tests.
    #[error("the competition's OOB analysis fails: {0}")]
    Analysis(#[from] OobError),
}

/// The kept tests of `run` as the pipeline's analysis reads their files, in the order of their
/// file names (which export pads to one width, so id order).
pub fn oob_tests(run: &RunFile) -> Result<Vec<SbstTest>, OobSummaryError> {
    let mut tests = Vec::with_capacity(run.tests.len());
    for t in &run.tests {
        let result = &t.execution.result;
        if result.reason == Some(StopReason::OutOfLane) && result.oob.is_none() {
            return Err(OobSummaryError::NoExitRecorded(t.id));
        }
        tests.push(SbstTest {
            id: t.id as u64,
            is_valid: true,
            test_outcome: Some(outcome_name(result.outcome).to_owned()),
            road_points: t.execution.road_points.clone(),
            oob_point: result.oob.and_then(|exit| exit.place()),
        });
    }
    tests.sort_by_key(|t| t.id);
    Ok(tests)
}

/// The pipeline's `OOBAnalyzer` summary of `run`'s kept tests.
pub fn oob_summary(run: &RunFile) -> Result<OobSummary, OobSummaryError> {
    Ok(oob::summarise_tests(&oob_tests(run)?)?)
}

/// The outcome as a test file spells it.
fn outcome_name(outcome: Outcome) -> &'static str {
    match outcome {
        Outcome::Pass => "PASS",
        Outcome::Fail => "FAIL",
        Outcome::Error => "ERROR",
    }
}
