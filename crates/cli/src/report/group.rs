//! The figures of a group of repeated runs: per-run measures and their mean and SD over runs,
//! and the competition's feature coverage of the failing tests.

use super::stats::{mean, median, sample_sd};
use crate::files::records::{known, TestRecord};
use crate::files::run_file::RunFile;
use crate::sbst::metrics::SbstMeasures;
use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use rayon::prelude::*;
use road_sim::distinct::{distinct, ExitProfile, DELTA_RAD};
use road_sim::road::diversity_profile::{angle_distance, diversity_profile};
use road_sim::Road;
use road_sim::SimResult;
use std::collections::BTreeSet;
use wogan_core::diversity::{median_pairwise_distance, median_pairwise_distance_by, SAMPLED_PAIRS};
use wogan_core::Phase;

/// Width of a MAX_CURV coverage bin, 1/m.
pub const MAX_CURV_BIN_PER_M: f64 = 0.01;
/// Width of a STD_SA coverage bin, degrees.
pub const STD_SA_BIN_DEG: f64 = 1.0;
/// Width of a MEAN_LP coverage bin, metres.
pub const MEAN_LP_BIN_M: f64 = 0.25;

/// The measures of one run.
#[derive(Debug, Clone)]
pub struct RunMeasures {
    /// Tests executed.
    pub executed: usize,
    /// Failing tests.
    pub failures: usize,
    /// Mean generation time per test, milliseconds.
    pub generation_ms_per_test: Option<f64>,
    /// Total simulated time, seconds.
    pub simulated_s: f64,
    /// Time spent training models (WOGAN's `train` records), seconds.
    pub training_s: f64,
    /// The paper's diversity: median pairwise distance of the failing roads' diversity profiles
    /// ([`diversity_profile`]); `None` below two failures.
    pub diversity: Option<f64>,
    /// Whether the diversities were measured on sampled pairs (more than
    /// [`wogan_core::diversity::EXACT_UP_TO`] failing roads), not on all.
    pub diversity_sampled: bool,
    /// The paper's diversity with each direction difference taken as the angle between the
    /// directions ([`angle_distance`]), so that roads heading back alike are near; `None` below
    /// two failures.
    pub angle_diversity: Option<f64>,
    /// Distinct failures: the greedy count of failing roads whose exit profiles lie at least
    /// [`DELTA_RAD`] apart ([`road_sim::distinct`]); `None` when a failing test's record does not
    /// say where the car left its lane (runs written before wogan recorded it).
    pub distinct_failures: Option<usize>,
    /// The failing tests the distinct failures were counted over when a sample was
    /// ([`DISTINCT_EXACT_UP_TO`]); `None` when every one was.
    pub distinct_sample: Option<usize>,
    /// Failing tests per hour of simulated driving; `None` without simulated time.
    pub failures_per_simulated_hour: Option<f64>,
    /// Median length of the failing roads' centre lines, metres; `None` without a failure.
    pub failing_road_length_m: Option<f64>,
    /// Position (1-based) of the first failing test; `None` when no test failed.
    pub first_failure: Option<usize>,
    /// Share of the tests after the first failing one that failed too (how well a search exploits
    /// a failure once it has one); `None` when no test follows a failure.
    pub failure_rate_after_first: Option<f64>,
    /// Mean of the candidates the analyzer ranked per test it chose (the acceptance rule's
    /// selection pressure); `None` when it chose none.
    pub ranked_per_choice: Option<f64>,
    /// Largest `fitness_distance` of the run's tests: how near the lane's edge the search drove
    /// the car, the one sign of progress against a driver it never breaks; `None` without tests.
    pub closest_approach: Option<f64>,
    /// Invalid candidates rejected over the run.
    pub invalid_candidates: usize,
    /// Generation time of the tests the search chose (after the random phase), milliseconds,
    /// and the candidates it drew for them (valid ones ranked and invalid ones): what a candidate
    /// costs.
    pub chosen_generation_ms: f64,
    /// See [`RunMeasures::chosen_generation_ms`].
    pub chosen_candidates: usize,
    /// The SBST competition's measures.
    pub sbst: SbstMeasures,
}

impl RunMeasures {
    /// Measures `run`. The work is bounded whatever the run's size: the pairwise measures
    /// (diversity, the OOB sparseness, distinct failures) measure a seeded sample of a run's
    /// failures above their stated sizes, and say so ([`RunMeasures::sampled`]).
    pub fn of(run: &RunFile) -> Self {
        let generation: Vec<f64> = run
            .tests
            .iter()
            .filter_map(|t| known(t.generation_ms))
            .collect();
        let ranked: Vec<f64> = run
            .tests
            .iter()
            .filter_map(|t| t.ranked_candidates)
            .filter(|&n| n > 0)
            .map(|n| n as f64)
            .collect();
        // Each failing road built once (the spline is the costly part), on every core.
        let failing: Vec<(&TestRecord, Option<Road>)> = run
            .tests
            .par_iter()
            .filter(|t| t.failed())
            .map(|t| (t, Road::new(&t.execution.road_points).ok()))
            .collect();
        let failing_roads: Vec<&Road> = failing.iter().filter_map(|(_, r)| r.as_ref()).collect();
        let profiles: Vec<Vec<f64>> = failing_roads
            .par_iter()
            .map(|road| diversity_profile(&road.interpolated))
            .collect();
        let lengths_m: Vec<f64> = failing_roads.iter().map(|r| r.length_m()).collect();
        let seed = run.header.as_ref().and_then(|h| h.seed).unwrap_or(0);
        let failures = run.failures();
        let first_index = run.tests.iter().position(|t| t.failed());
        let chosen: Vec<&TestRecord> = run
            .tests
            .iter()
            .filter(|t| t.phase != Phase::Random)
            .collect();
        let tests_after_first = first_index.map_or(0, |i| run.tests.len() - i - 1);
        let simulated_s: f64 = run
            .tests
            .iter()
            .filter_map(|t| known(t.execution.result.sim_time_s))
            .sum();
        let distinct = exit_profiles(&failing).map(|profiles| bounded_distinct(&profiles, seed));
        let diversity = median_pairwise_distance(&profiles, seed);
        Self {
            executed: run.tests.len(),
            failures,
            generation_ms_per_test: mean(&generation),
            simulated_s,
            training_s: run.train_ms / 1000.0,
            diversity: diversity.median_distance,
            diversity_sampled: diversity.pairs == "sampled",
            angle_diversity: median_pairwise_distance_by(&profiles, seed, angle_distance)
                .median_distance,
            distinct_failures: distinct.map(|(count, _)| count),
            distinct_sample: distinct.and_then(|(_, sample)| sample),
            failures_per_simulated_hour: (simulated_s > 0.0)
                .then(|| failures as f64 * 3600.0 / simulated_s),
            failing_road_length_m: median(&lengths_m),
            first_failure: first_index.map(|i| i + 1),
            // Every failure but the first comes after it.
            failure_rate_after_first: (tests_after_first > 0)
                .then(|| (failures - 1) as f64 / tests_after_first as f64),
            ranked_per_choice: mean(&ranked),
            closest_approach: run
                .tests
                .iter()
                .filter_map(|t| known(t.execution.result.fitness_distance))
                .reduce(f64::max),
            invalid_candidates: run.tests.iter().map(|t| t.invalid_candidates).sum(),
            chosen_generation_ms: chosen.iter().filter_map(|t| known(t.generation_ms)).sum(),
            chosen_candidates: chosen
                .iter()
                .map(|t| t.invalid_candidates + t.ranked_candidates.unwrap_or(0))
                .sum(),
            sbst: SbstMeasures::of(run),
        }
    }

    /// The first failing test's position, or one past the last test when none failed, so that
    /// runs without a failure rank behind every run with one.
    pub fn first_failure_or_past_end(&self) -> f64 {
        self.first_failure.unwrap_or(self.executed + 1) as f64
    }

    /// Which of this run's measures were taken on a sample of its failures, as the report says
    /// so: each a phrase ("the OOB sparseness on 1000 of its 100000 OOBs").
    pub fn sampled(&self) -> Vec<String> {
        let mut sampled = Vec::new();
        if let Some(n) = self.distinct_sample {
            sampled.push(format!(
                "distinct failures counted over {n} of its {} failing tests",
                self.failures
            ));
        }
        let oob = [&self.sbst.oob, &self.sbst.oob_placed];
        if let Some(summary) = oob.iter().find_map(|s| s.as_ref().ok()) {
            if let Some(n) = summary.sparseness_sample {
                sampled.push(format!(
                    "the OOB sparseness measured on {n} of its {} OOBs",
                    summary.total
                ));
            }
        }
        if self.diversity_sampled {
            sampled.push(format!(
                "the diversity measured on {SAMPLED_PAIRS} pairs of its {} failing roads",
                self.failures
            ));
        }
        sampled
    }
}

/// Up to this many failing tests [`bounded_distinct`] counts every one; above, a seeded sample of
/// this many, in test order. The greedy count compares each failure with those kept before it, so
/// its work grows with failures times distinct failures: at most 2 × 10^8 profile distances.
pub const DISTINCT_EXACT_UP_TO: usize = 20_000;

/// The greedy count of distinct failures among `tests`, in test order, every one counted; `None`
/// when a failing test does not say where the car left its lane.
#[cfg(test)]
fn distinct_failures(tests: &[TestRecord]) -> Option<usize> {
    let failing: Vec<(&TestRecord, Option<Road>)> = tests
        .iter()
        .filter(|t| t.failed())
        .map(|t| (t, Road::new(&t.execution.road_points).ok()))
        .collect();
    Some(distinct(&exit_profiles(&failing)?, DELTA_RAD).len())
}

/// The exit profile of each failing test (with its road, when its points make one); `None`
/// when one cannot be made.
fn exit_profiles(failing: &[(&TestRecord, Option<Road>)]) -> Option<Vec<ExitProfile>> {
    failing
        .par_iter()
        .map(|(t, road)| {
            // An executor reports the side of an exit, not its place: no count then.
            let place = t.execution.result.oob?.place()?;
            // A road that cannot be built cannot have been driven: there is nothing to count.
            ExitProfile::of(&road.as_ref()?.interpolated, place)
        })
        .collect()
}

/// The greedy count of distinct failures among `profiles` (in test order), and the size of the
/// sample it was taken over when there were more than [`DISTINCT_EXACT_UP_TO`]: that many drawn
/// with `seed`, kept in test order. A sample's count is at most the whole run's.
fn bounded_distinct(profiles: &[ExitProfile], seed: u64) -> (usize, Option<usize>) {
    if profiles.len() <= DISTINCT_EXACT_UP_TO {
        return (distinct(profiles, DELTA_RAD).len(), None);
    }
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut drawn =
        rand::seq::index::sample(&mut rng, profiles.len(), DISTINCT_EXACT_UP_TO).into_vec();
    drawn.sort_unstable();
    let sample: Vec<ExitProfile> = drawn.iter().map(|&i| profiles[i].clone()).collect();
    (
        distinct(&sample, DELTA_RAD).len(),
        Some(DISTINCT_EXACT_UP_TO),
    )
}

/// Mean and sample SD of one measure over runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// Runs the measure was defined for.
    pub count: usize,
    /// Mean over those runs.
    pub mean: Option<f64>,
    /// Sample standard deviation over those runs.
    pub sd: Option<f64>,
}

impl Spread {
    /// Spread of `values`.
    pub fn of(values: &[f64]) -> Self {
        Self {
            count: values.len(),
            mean: mean(values),
            sd: sample_sd(values),
        }
    }
}

/// Range and bins covered by one feature over the failing tests.
#[derive(Debug, Clone, PartialEq)]
pub struct FeatureCoverage {
    /// Smallest value.
    pub min: Option<f64>,
    /// Median value.
    pub median: Option<f64>,
    /// Largest value.
    pub max: Option<f64>,
    /// Distinct bins hit.
    pub bins: usize,
}

impl FeatureCoverage {
    /// Coverage of `values` with bins of `bin_width` (bins counted from 0).
    pub fn of(values: &[f64], bin_width: f64) -> Self {
        let bins: BTreeSet<i64> = values
            .iter()
            .map(|v| (v / bin_width).floor() as i64)
            .collect();
        Self {
            min: values.iter().copied().reduce(f64::min),
            median: median(values),
            max: values.iter().copied().reduce(f64::max),
            bins: bins.len(),
        }
    }
}

/// Everything the report says about one group of runs.
#[derive(Debug, Clone)]
pub struct GroupFigures {
    /// Per-run measures, in input order.
    pub runs: Vec<RunMeasures>,
    /// Tests executed per run.
    pub executed: Spread,
    /// Failures per run.
    pub failures: Spread,
    /// Failures over all tests of the group.
    pub failure_rate: Option<f64>,
    /// Mean generation time per test, milliseconds, over runs.
    pub generation_ms: Spread,
    /// Simulated time per run, seconds.
    pub simulated_s: Spread,
    /// Training time per run, seconds.
    pub training_s: Spread,
    /// Diversity over the runs with at least two failures.
    pub diversity: Spread,
    /// Angle diversity over the runs with at least two failures.
    pub angle_diversity: Spread,
    /// Distinct failures per run (runs that say where their cars left the lane).
    pub distinct_failures: Spread,
    /// DIR_COV buckets (k of k/26) hit by the failing tests.
    pub dir_cov_buckets: BTreeSet<u32>,
    /// DIR_COV of the failing tests (bins: the buckets above).
    pub dir_cov: FeatureCoverage,
    /// MAX_CURV of the failing tests, 1/m.
    pub max_curv: FeatureCoverage,
    /// STD_SA of the failing tests, degrees.
    pub std_sa: FeatureCoverage,
    /// MEAN_LP of the failing tests, metres.
    pub mean_lp: FeatureCoverage,
}

impl GroupFigures {
    /// Figures of `runs`.
    pub fn of(runs: &[&RunFile]) -> Self {
        // Runs are measured apart (the OOB analysis is quadratic in a run's failures).
        let measures: Vec<RunMeasures> = runs.par_iter().map(|r| RunMeasures::of(r)).collect();
        Self::of_measured(runs, measures)
    }

    /// Figures of `runs` already measured (`measures[i]` of `runs[i]`, taken as each was read):
    /// beyond the measures, the figures read only the failing tests of the runs.
    pub fn of_measured(runs: &[&RunFile], measures: Vec<RunMeasures>) -> Self {
        let column = |measure| values_of(&measures, measure);
        let executed_total: usize = measures.iter().map(|m| m.executed).sum();
        let failed_total: usize = measures.iter().map(|m| m.failures).sum();
        let failing: Vec<_> = runs
            .iter()
            .flat_map(|r| r.tests.iter().filter(|t| t.failed()))
            .collect();
        let feature = |f: &dyn Fn(&SimResult) -> f64| -> Vec<f64> {
            failing
                .iter()
                .filter_map(|t| known(f(&t.execution.result)))
                .collect()
        };
        let dir_cov_values = feature(&|r| r.dir_cov);
        let dir_cov_buckets: BTreeSet<u32> = dir_cov_values
            .iter()
            .map(|v| (v * 26.0).round() as u32)
            .collect();
        let mut dir_cov = FeatureCoverage::of(&dir_cov_values, 1.0 / 26.0);
        dir_cov.bins = dir_cov_buckets.len();
        Self {
            executed: Spread::of(&column(|m| Some(m.executed as f64))),
            failures: Spread::of(&column(|m| Some(m.failures as f64))),
            failure_rate: (executed_total > 0).then(|| failed_total as f64 / executed_total as f64),
            generation_ms: Spread::of(&column(|m| m.generation_ms_per_test)),
            simulated_s: Spread::of(&column(|m| Some(m.simulated_s))),
            training_s: Spread::of(&column(|m| Some(m.training_s))),
            diversity: Spread::of(&column(|m| m.diversity)),
            angle_diversity: Spread::of(&column(|m| m.angle_diversity)),
            distinct_failures: Spread::of(&column(|m| m.distinct_failures.map(|n| n as f64))),
            dir_cov_buckets,
            dir_cov,
            max_curv: FeatureCoverage::of(&feature(&|r| r.max_curv), MAX_CURV_BIN_PER_M),
            std_sa: FeatureCoverage::of(&feature(&|r| r.std_sa), STD_SA_BIN_DEG),
            mean_lp: FeatureCoverage::of(&feature(&|r| r.mean_lp), MEAN_LP_BIN_M),
            runs: measures,
        }
    }

    /// One measure of each run where it is defined (the samples of a test between groups).
    pub fn values(&self, measure: Measure) -> Vec<f64> {
        values_of(&self.runs, measure)
    }
}

/// One figure of a run, `None` where the run does not define it.
pub type Measure = fn(&RunMeasures) -> Option<f64>;

/// `measure` of each run where it is defined.
fn values_of(runs: &[RunMeasures], measure: Measure) -> Vec<f64> {
    runs.iter().filter_map(measure).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::files::records::TestRecord;
    use road_sim::Outcome;

    fn run_of(outcomes: &[Outcome]) -> RunFile {
        run_with(outcomes, &vec![0; outcomes.len()])
    }

    /// A run of these outcomes whose tests the analyzer chose from `ranked` candidates each.
    fn run_with(outcomes: &[Outcome], ranked: &[usize]) -> RunFile {
        let tests: Vec<TestRecord> = outcomes
            .iter()
            .zip(ranked)
            .enumerate()
            .map(|(i, (&outcome, &ranked))| TestRecord::example(i + 1, outcome, ranked))
            .collect();
        RunFile {
            path: "run.jsonl".into(),
            header: None,
            tests,
            beyond_budget: Vec::new(),
            train_ms: 0.0,
            pipeline_invalid: 0,
            summary: None,
            problems: Vec::new(),
        }
    }

    #[test]
    fn first_failure_and_the_rate_after_it() {
        let run = RunMeasures::of(&run_of(&[
            Outcome::Pass,
            Outcome::Fail,
            Outcome::Pass,
            Outcome::Fail,
            Outcome::Fail,
        ]));
        assert_eq!(run.first_failure, Some(2));
        assert_eq!(run.first_failure_or_past_end(), 2.0);
        assert_eq!(run.failure_rate_after_first, Some(2.0 / 3.0));

        let never = RunMeasures::of(&run_of(&[Outcome::Pass, Outcome::Error]));
        assert_eq!(never.first_failure, None);
        assert_eq!(never.first_failure_or_past_end(), 3.0);
        assert_eq!(never.failure_rate_after_first, None);

        let at_the_end = RunMeasures::of(&run_of(&[Outcome::Pass, Outcome::Fail]));
        assert_eq!(at_the_end.first_failure, Some(2));
        assert_eq!(at_the_end.failure_rate_after_first, None);
    }

    #[test]
    fn candidates_ranked_count_only_the_analyzers_choices() {
        let run = run_with(
            &[Outcome::Pass, Outcome::Pass, Outcome::Fail, Outcome::Pass],
            &[0, 0, 20, 40],
        );
        assert_eq!(RunMeasures::of(&run).ranked_per_choice, Some(30.0));
        assert_eq!(
            RunMeasures::of(&run_of(&[Outcome::Pass])).ranked_per_choice,
            None
        );
    }

    /// A failing test on a road bending left (or right when `mirrored`) that the car left at
    /// (x, y), or whose record does not say where when `exit` is `None`.
    fn failure(id: usize, mirrored: bool, exit: Option<(f64, f64)>) -> TestRecord {
        let mut test = TestRecord::example(id, Outcome::Fail, 0);
        let side = if mirrored { -1.0 } else { 1.0 };
        test.execution.road_points = vec![
            [100.0, 10.0],
            [100.0, 25.0],
            [100.0 - side * 5.0, 39.0],
            [100.0 - side * 16.0, 49.0],
            [100.0 - side * 30.0, 54.0],
        ];
        test.execution.result.oob = exit.map(|(x, y)| road_sim::LaneExit {
            t_s: 5.0,
            x: side * (x - 100.0) + 100.0,
            y,
            side: road_sim::LaneSide::Right,
            sbst_side: None,
        });
        test
    }

    #[test]
    fn distinct_failures_count_failing_roads_apart_around_their_exits() {
        let at = Some((97.0, 36.0));
        let pass = TestRecord::example(1, Outcome::Pass, 0);
        assert_eq!(distinct_failures(std::slice::from_ref(&pass)), Some(0));
        // The same road left at the same place twice: one failure; its mirror is another.
        let twice = [failure(2, false, at), pass.clone(), failure(4, false, at)];
        assert_eq!(distinct_failures(&twice), Some(1));
        let mirrored = [failure(2, false, at), failure(3, true, at)];
        assert_eq!(distinct_failures(&mirrored), Some(2));
        // A failure without its exit leaves the count undefined; a pass without one does not.
        assert_eq!(
            distinct_failures(&[failure(2, false, at), failure(3, false, None)]),
            None
        );
        let mut run = run_of(&[Outcome::Pass]);
        run.tests.extend(mirrored);
        assert_eq!(RunMeasures::of(&run).distinct_failures, Some(2));
    }

    #[test]
    fn failures_are_counted_per_simulated_hour_and_failing_roads_measured() {
        let mut run = run_of(&[Outcome::Pass]);
        run.tests.push(failure(2, false, Some((97.0, 36.0))));
        for (test, sim_time_s) in run.tests.iter_mut().zip([1000.0, 800.0]) {
            test.execution.result.sim_time_s = sim_time_s;
        }
        let measures = RunMeasures::of(&run);
        assert_eq!(measures.failures_per_simulated_hour, Some(2.0));
        // The failing road's five points lie 15 + 15.2 + 14.9 + 14.9 m apart; its spline is
        // a little shorter than the polygon through them.
        let length_m = measures.failing_road_length_m.unwrap();
        assert!((55.0..61.0).contains(&length_m), "{length_m}");
        let passing = RunMeasures::of(&run_of(&[Outcome::Pass]));
        assert_eq!(passing.failing_road_length_m, None);
    }

    #[test]
    fn closest_approach_is_the_largest_fitness_distance_of_a_run() {
        let mut run = run_of(&[Outcome::Pass, Outcome::Pass, Outcome::Pass]);
        for (test, distance) in run.tests.iter_mut().zip([0.2, 0.45, 0.1]) {
            test.execution.result.fitness_distance = distance;
        }
        assert_eq!(RunMeasures::of(&run).closest_approach, Some(0.45));
        assert_eq!(RunMeasures::of(&run_of(&[])).closest_approach, None);
    }
}
