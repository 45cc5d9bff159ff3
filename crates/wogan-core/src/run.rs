//! One search run: the pipeline from budget and seed to streamed events and a summary.
//!
//! `random` executes random valid tests for the whole budget. `wogan` executes random valid tests
//! for the first `init_fraction` of the schedule, then retrains every `train_every` tests and
//! executes the test the networks propose. `stop` is checked between tests, so a Ctrl-C handler
//! that sets it ends the run after the current test with everything so far reported.
//!
//! Every run keeps the SBST competition's accounting ([`SbstBudget`]): each test is charged the
//! real time since the previous test's execution ended, and its execution time. Under an
//! [`SbstBudget`] a test that ends with either budget spent is reported with `beyond_budget`
//! set, is not learnt from, and ends the run, as the competition's pipeline discards it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;
use serde::{Deserialize, Serialize};

#[cfg(doc)]
use crate::budget::SbstBudget;
use crate::budget::{Budget, SbstUsage};
use crate::config::{Algorithm, RunConfig};
use crate::error::Error;
use crate::random::{execute_all, sample_tests};
use crate::sampler::Sampler;
use crate::sut::{clamp_fitness, Sut};
use crate::wogan::WoganModel;

/// Which part of the algorithm produced a test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Phase {
    /// The random sampler.
    Random,
    /// The WOGAN generator and analyzer (or the random fallback after too many invalid
    /// candidates, marked by `predicted_fitness: None`).
    Wogan,
    /// A mutant of one of the best tests so far, chosen by the analyzer (see
    /// [`crate::MutationConfig`]).
    Mutant,
}

impl Phase {
    /// The name, as test records spell it (`random`, `wogan`, `mutant`).
    pub fn name(self) -> &'static str {
        match self {
            Phase::Random => "random",
            Phase::Wogan => "wogan",
            Phase::Mutant => "mutant",
        }
    }
}

/// Something that happened during a run, reported as soon as it is known.
///
/// Serialises as one JSON object tagged `"type": "test"` or `"type": "train"`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "lowercase")]
pub enum Event<O> {
    /// A test was executed.
    Test {
        /// 1-based position in the run.
        id: usize,
        /// Who proposed it.
        phase: Phase,
        /// The normalised test vector.
        test: Vec<f32>,
        /// Fitness in `[0, 1]` (clamped).
        fitness: f64,
        /// The analyzer's prediction, when WOGAN chose it.
        predicted_fitness: Option<f64>,
        /// Invalid candidates rejected since the previous executed test.
        invalid_candidates: usize,
        /// Valid candidates the analyzer ranked to choose it (0 in the random phase).
        ranked_candidates: usize,
        /// Time spent choosing this test (validity checks included, training excluded).
        generation_ms: f64,
        /// Generation time the SBST competition charges for this test: real time from the end of
        /// the previous test's execution (or the start of the run) to the start of this one,
        /// training included.
        sbst_generation_ms: f64,
        /// Time the execution charged to an execution budget, seconds.
        execution_time_s: f64,
        /// Whether the test ended with an [`SbstBudget`] spent: the competition does not keep it,
        /// and the run ends.
        beyond_budget: bool,
        /// The SUT's report.
        output: O,
    },
    /// WOGAN finished a training round.
    Train {
        /// Analyzer loss of its last step.
        analyzer_loss: f64,
        /// Critic loss of its last step.
        critic_loss: f64,
        /// Gradient penalty of its last critic step (coefficient included).
        gradient_penalty: f64,
        /// Generator loss of its last step.
        generator_loss: f64,
        /// Critic's Wasserstein estimate.
        wasserstein_estimate: f64,
        /// Duration of the round.
        train_ms: f64,
        /// Tests the round learnt from.
        tests: usize,
    },
}

/// Totals of a finished run.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Summary {
    /// Executed tests.
    pub executed: usize,
    /// Invalid candidates rejected in total.
    pub invalid_candidates: usize,
    /// Time spent choosing tests.
    pub generation_s: f64,
    /// Time spent training networks.
    pub training_s: f64,
    /// Wall time spent executing tests.
    pub simulation_s: f64,
    /// Wall time of the whole run.
    pub wall_s: f64,
    /// Whether `stop` ended the run before the budget did.
    pub stopped_by_signal: bool,
    /// Generation time the SBST competition charged, seconds (every test handed to execution).
    pub sbst_generation_s: f64,
    /// Execution time charged, seconds (simulated for a simulator; every executed test).
    pub execution_time_s: f64,
    /// Tests executed but not kept because they ended with an [`SbstBudget`] spent (0 or 1).
    pub beyond_budget: usize,
}

struct Runner<'a> {
    budget: Budget,
    stop: &'a AtomicBool,
    start: Instant,
    summary: Summary,
    /// The SBST budgets used so far.
    used: SbstUsage,
    /// When the current test's generation began (the end of the previous test's execution).
    generation_clock: Instant,
}

/// What handing a test to execution charged.
struct Charge {
    generation_s: f64,
    execution_time_s: f64,
    beyond_budget: bool,
}

impl Runner<'_> {
    fn elapsed(&self) -> Duration {
        self.start.elapsed()
    }

    /// The generation time of the test being handed over now: since the generation clock began.
    fn generation_gap_s(&self) -> f64 {
        self.generation_clock.elapsed().as_secs_f64()
    }

    /// Whether a test charged `generation_s` may still be executed (the competition's check
    /// before execution: simulated time remains). Charges the generation time.
    fn hand_over(&mut self, generation_s: f64) -> bool {
        self.used.generation += Duration::from_secs_f64(generation_s.max(0.0));
        self.budget
            .sbst
            .is_none_or(|b| b.can_run_a_test(&self.used))
    }

    /// Charges an executed test's execution time; the test is beyond the budget when a budget
    /// is now spent.
    fn charge(&mut self, generation_s: f64, execution_time_s: f64) -> Charge {
        self.used.execution_s += execution_time_s;
        let beyond_budget = self.budget.sbst.is_some_and(|b| b.is_over(&self.used));
        if beyond_budget {
            self.summary.beyond_budget += 1;
        }
        Charge {
            generation_s,
            execution_time_s,
            beyond_budget,
        }
    }

    /// The next test's generation begins now.
    fn restart_generation_clock(&mut self) {
        self.generation_clock = Instant::now();
    }

    /// Whether the run must end now (and why, recorded in the summary).
    fn should_stop(&mut self) -> bool {
        if self.stop.load(Ordering::Relaxed) {
            self.summary.stopped_by_signal = true;
            return true;
        }
        self.budget
            .exhausted(self.summary.executed, self.elapsed(), &self.used)
    }

    fn remaining_tests(&self) -> usize {
        self.budget
            .max_tests
            .map_or(usize::MAX, |m| m.saturating_sub(self.summary.executed))
    }
}

/// How a test was chosen, for its event.
struct Proposal {
    predicted_fitness: Option<f64>,
    invalid_candidates: usize,
    ranked_candidates: usize,
    generation_s: f64,
}

/// The event of an executed test.
fn test_event<O>(
    id: usize,
    phase: Phase,
    test: Vec<f32>,
    fitness: f64,
    proposal: Proposal,
    charge: &Charge,
    output: O,
) -> Event<O> {
    Event::Test {
        id,
        phase,
        test,
        fitness,
        predicted_fitness: proposal.predicted_fitness,
        invalid_candidates: proposal.invalid_candidates,
        ranked_candidates: proposal.ranked_candidates,
        generation_ms: proposal.generation_s * 1e3,
        sbst_generation_ms: charge.generation_s * 1e3,
        execution_time_s: charge.execution_time_s,
        beyond_budget: charge.beyond_budget,
        output,
    }
}

/// Runs one search.
///
/// `budget` limits tests, wall time and/or the SBST budgets (with none, 300 tests). All random
/// choices flow from
/// `seed`. Events are passed to `on_event` in order as they happen; the returned summary holds
/// the totals. Errors: an invalid configuration, a SUT of dimension 0, or a sampler that finds no
/// valid test.
pub fn run<S: Sut + ?Sized>(
    sut: &S,
    config: &RunConfig,
    budget: Budget,
    seed: u64,
    stop: &AtomicBool,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Result<Summary, Error> {
    config.validate()?;
    let dim = sut.dim();
    if dim == 0 {
        return Err(Error::Config("the SUT's dimension is 0".into()));
    }
    let pool = if config.jobs > 1 {
        Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(config.jobs)
                .build()
                .map_err(|e| Error::ThreadPool {
                    jobs: config.jobs,
                    message: e.to_string(),
                })?,
        )
    } else {
        None
    };
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let budget = budget.effective();
    let start = Instant::now();
    // A long search for a valid test looks at the stop flag and the clock now and then. (Not at
    // the generation budget: the competition lets a generator finish the test in hand, then
    // executes and discards it; the sampler's attempt limit bounds the search.)
    let go_on = || !stop.load(Ordering::Relaxed) && budget.wall.is_none_or(|w| start.elapsed() < w);
    let sampler = Sampler::new(dim, config.sampler.clone()).interruptible(&go_on);
    let mut r = Runner {
        budget,
        stop,
        start,
        summary: Summary::default(),
        used: SbstUsage::default(),
        generation_clock: start,
    };
    let w = &config.wogan;

    // Random phase: the whole run for `random`, the first share for `wogan`.
    let mut executed_tests: Vec<(Vec<f32>, f64)> = Vec::new();
    loop {
        if r.should_stop() {
            break;
        }
        let (elapsed, done) = (r.elapsed(), r.summary.executed);
        if config.algorithm == Algorithm::Wogan
            && r.budget
                .initial_phase_over(w.init_fraction, done, elapsed, &r.used)
        {
            break;
        }
        let mut count = config.jobs.min(r.remaining_tests());
        if config.algorithm == Algorithm::Wogan {
            if let Some(m) = r.budget.max_tests {
                let init = ((w.init_fraction * m as f64).round() as usize).max(1);
                count = count.min(init.saturating_sub(done)).max(1);
            }
        }
        let sampled = match sample_tests(sut, &sampler, &mut rng, count) {
            Ok(sampled) => sampled,
            // The loop's next check says why it ends.
            Err(Error::Interrupted) => continue,
            Err(error) => return Err(error),
        };
        // Tests sampled together are charged in test order: each its own sampling time, the
        // first also the rest of the time since the previous execution ended.
        let gap_s = r.generation_gap_s();
        let later_s: f64 = sampled.iter().skip(1).map(|s| s.generation_s).sum();
        let t0 = Instant::now();
        let results = execute_all(sut, &sampled, pool.as_ref());
        r.summary.simulation_s += t0.elapsed().as_secs_f64();
        for (i, (s, e)) in sampled.into_iter().zip(results).enumerate() {
            // Cut short by a stop: the loop's next check ends the run.
            let Some(e) = e else { continue };
            let generation_s = if i == 0 {
                (gap_s - later_s).max(s.generation_s)
            } else {
                s.generation_s
            };
            if !r.hand_over(generation_s) {
                // The competition would not have executed this test, nor any after it.
                break;
            }
            let charge = r.charge(generation_s, e.execution_time_s);
            let fitness = clamp_fitness(e.fitness);
            r.summary.invalid_candidates += s.invalid;
            r.summary.generation_s += s.generation_s;
            if !charge.beyond_budget {
                r.summary.executed += 1;
                if config.algorithm == Algorithm::Wogan {
                    executed_tests.push((s.test.clone(), fitness));
                }
            }
            on_event(test_event(
                r.summary.executed + usize::from(charge.beyond_budget),
                Phase::Random,
                s.test,
                fitness,
                Proposal {
                    predicted_fitness: None,
                    invalid_candidates: s.invalid,
                    ranked_candidates: 0,
                    generation_s: s.generation_s,
                },
                &charge,
                e.output,
            ));
            if charge.beyond_budget {
                break;
            }
        }
        r.restart_generation_clock();
    }

    if config.algorithm == Algorithm::Wogan && !r.should_stop() {
        let mut model = WoganModel::new(dim, w, &mut rng);
        for (t, f) in &executed_tests {
            model.add(t, *f);
        }
        drop(executed_tests);
        let mut since_train = usize::MAX;
        while !r.should_stop() {
            if since_train >= w.train_every {
                let alpha = r.budget.alpha(
                    w.init_fraction,
                    w.alpha_max,
                    r.summary.executed,
                    r.elapsed(),
                    &r.used,
                );
                let t0 = Instant::now();
                let stats = model.train(alpha, &mut rng)?;
                let train_s = t0.elapsed().as_secs_f64();
                r.summary.training_s += train_s;
                since_train = 0;
                on_event(Event::Train {
                    analyzer_loss: stats.analyzer_loss,
                    critic_loss: stats.critic_loss,
                    gradient_penalty: stats.gradient_penalty,
                    generator_loss: stats.generator_loss,
                    wasserstein_estimate: stats.wasserstein_estimate,
                    train_ms: train_s * 1e3,
                    tests: model.len(),
                });
                let losses = [
                    stats.analyzer_loss,
                    stats.critic_loss,
                    stats.generator_loss,
                    stats.wasserstein_estimate,
                ];
                if losses.iter().any(|loss| !loss.is_finite()) {
                    // The networks' weights are no longer numbers: every later proposal would be
                    // noise presented as WOGAN's.
                    return Err(Error::Diverged { tests: model.len() });
                }
                // Training can be long: honour a stop or an expired clock before proposing.
                if r.should_stop() {
                    break;
                }
            }
            let t0 = Instant::now();
            let p = match model.propose(sut, &sampler, &mut rng) {
                Ok(p) => p,
                Err(Error::Interrupted) => continue,
                Err(error) => return Err(error),
            };
            let generation_s = t0.elapsed().as_secs_f64();
            let gap_s = r.generation_gap_s();
            if !r.hand_over(gap_s) {
                break;
            }
            let t1 = Instant::now();
            let e = sut.execute(&p.test);
            r.summary.simulation_s += t1.elapsed().as_secs_f64();
            let Some(e) = e else {
                // Cut short by a stop: nothing to report, the run ends.
                r.summary.stopped_by_signal = true;
                break;
            };
            let charge = r.charge(gap_s, e.execution_time_s);
            let fitness = clamp_fitness(e.fitness);
            r.summary.invalid_candidates += p.invalid;
            r.summary.generation_s += generation_s;
            if !charge.beyond_budget {
                model.add(&p.test, fitness);
                since_train += 1;
                r.summary.executed += 1;
            }
            on_event(test_event(
                r.summary.executed + usize::from(charge.beyond_budget),
                if p.mutant {
                    Phase::Mutant
                } else {
                    Phase::Wogan
                },
                p.test,
                fitness,
                Proposal {
                    predicted_fitness: p.predicted,
                    invalid_candidates: p.invalid,
                    ranked_candidates: p.ranked,
                    generation_s,
                },
                &charge,
                e.output,
            ));
            if charge.beyond_budget {
                break;
            }
            r.restart_generation_clock();
        }
    }
    r.summary.wall_s = r.elapsed().as_secs_f64();
    r.summary.sbst_generation_s = r.used.generation.as_secs_f64();
    r.summary.execution_time_s = r.used.execution_s;
    Ok(r.summary)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Execution, SbstBudget};

    /// Fitness: a bump around a valid point; validity: a half-space through the bump's edge.
    struct Bump;
    const CENTRE: [f32; 5] = [0.6, 0.4, 0.6, 0.4, 0.5];
    impl Sut for Bump {
        type Output = f32;
        fn dim(&self) -> usize {
            5
        }
        fn is_valid(&self, t: &[f32]) -> bool {
            t.iter().sum::<f32>() <= 2.8
        }
        fn execute(&self, t: &[f32]) -> Option<Execution<f32>> {
            assert!(self.is_valid(t), "an invalid test was executed");
            let d2: f32 = t.iter().zip(CENTRE).map(|(a, b)| (a - b).powi(2)).sum();
            Some(Execution {
                fitness: f64::from((-d2 / 0.5).exp()),
                execution_time_s: 10.0,
                output: d2,
            })
        }
    }

    fn collect(config: &RunConfig, budget: Budget, seed: u64) -> (Vec<Event<f32>>, Summary) {
        let stop = AtomicBool::new(false);
        let mut events = Vec::new();
        let summary = run(&Bump, config, budget, seed, &stop, &mut |e| events.push(e)).unwrap();
        (events, summary)
    }

    fn tests_of(events: &[Event<f32>]) -> Vec<(usize, Phase, Vec<f32>, f64)> {
        events
            .iter()
            .filter_map(|e| match e {
                Event::Test {
                    id,
                    phase,
                    test,
                    fitness,
                    ..
                } => Some((*id, *phase, test.clone(), *fitness)),
                Event::Train { .. } => None,
            })
            .collect()
    }

    #[test]
    fn wogan_beats_random_on_a_bump() {
        let budget = Budget {
            max_tests: Some(200),
            wall: None,
            sbst: None,
        };
        let wogan = RunConfig::default();
        let random = RunConfig {
            algorithm: Algorithm::Random,
            ..RunConfig::default()
        };
        let mean_tail = |config: &RunConfig| {
            let (events, summary) = collect(config, budget, 5);
            assert_eq!(summary.executed, 200);
            let t = tests_of(&events);
            assert_eq!(t.len(), 200);
            for (i, (id, ..)) in t.iter().enumerate() {
                assert_eq!(*id, i + 1);
            }
            let tail = &t[160..];
            tail.iter().map(|x| x.3).sum::<f64>() / tail.len() as f64
        };
        let w = mean_tail(&wogan);
        let r = mean_tail(&random);
        eprintln!("tail mean fitness: WOGAN {w} random {r}");
        assert!(w > r + 0.05, "WOGAN {w} vs random {r}");
    }

    #[test]
    fn same_seed_same_tests() {
        let config = RunConfig {
            wogan: crate::WoganConfig {
                init_fraction: 0.5,
                ..Default::default()
            },
            ..RunConfig::default()
        };
        let budget = Budget {
            max_tests: Some(30),
            wall: None,
            sbst: None,
        };
        let (a, sa) = collect(&config, budget, 9);
        let (b, _) = collect(&config, budget, 9);
        let (c, _) = collect(&config, budget, 10);
        let (ta, tb, tc) = (tests_of(&a), tests_of(&b), tests_of(&c));
        assert_eq!(ta, tb);
        assert_ne!(ta, tc);
        assert_eq!(ta.iter().filter(|t| t.1 == Phase::Random).count(), 15);
        assert_eq!(ta.iter().filter(|t| t.1 == Phase::Wogan).count(), 15);
        let trains = a
            .iter()
            .filter(|e| matches!(e, Event::Train { .. }))
            .count();
        assert_eq!(trains, 5, "retrain every 3 tests");
        assert_eq!(sa.executed, 30);
        let invalid: usize = a
            .iter()
            .map(|e| match e {
                Event::Test {
                    invalid_candidates, ..
                } => *invalid_candidates,
                Event::Train { .. } => 0,
            })
            .sum();
        assert_eq!(invalid, sa.invalid_candidates);
        assert!(invalid > 0, "the half-space rejects some random walks");
    }

    #[test]
    fn events_serialise_as_tagged_json() {
        let budget = Budget {
            max_tests: Some(12),
            wall: None,
            sbst: None,
        };
        let (events, _) = collect(&RunConfig::default(), budget, 3);
        let lines: Vec<String> = events
            .iter()
            .map(|e| serde_json::to_string(e).unwrap())
            .collect();
        assert!(lines[0].starts_with(r#"{"type":"test","id":1,"phase":"random""#));
        assert!(lines.iter().any(|l| l.starts_with(r#"{"type":"train","#)));
        assert!(lines.last().unwrap().contains(r#""phase":"wogan""#));
    }

    /// One-dimensional, always valid: the smallest case the networks must handle.
    struct Line;
    impl Sut for Line {
        type Output = ();
        fn dim(&self) -> usize {
            1
        }
        fn is_valid(&self, _: &[f32]) -> bool {
            true
        }
        fn execute(&self, t: &[f32]) -> Option<Execution<()>> {
            Some(Execution {
                fitness: f64::from(t[0]) * 2.0, // partly outside [0, 1]: clamped
                execution_time_s: 0.0,
                output: (),
            })
        }
    }

    #[test]
    fn tiny_runs_work_at_the_edges_of_the_schedule() {
        let stop = AtomicBool::new(false);
        for init_fraction in [0.0, 1.0] {
            let config = RunConfig {
                wogan: crate::WoganConfig {
                    init_fraction,
                    ..Default::default()
                },
                ..RunConfig::default()
            };
            let budget = Budget {
                max_tests: Some(5),
                wall: None,
                sbst: None,
            };
            let mut phases = Vec::new();
            let s = run(&Line, &config, budget, 1, &stop, &mut |e| {
                if let Event::Test { phase, fitness, .. } = e {
                    assert!((0.0..=1.0).contains(&fitness));
                    phases.push(phase);
                }
            })
            .unwrap();
            assert_eq!(s.executed, 5);
            let random = phases.iter().filter(|p| **p == Phase::Random).count();
            assert_eq!(random, if init_fraction == 0.0 { 1 } else { 5 });
        }
        let zero = Budget {
            max_tests: Some(0),
            wall: None,
            sbst: None,
        };
        let s = run(&Line, &RunConfig::default(), zero, 1, &stop, &mut |_| {}).unwrap();
        assert_eq!(s.executed, 0);
    }

    #[test]
    fn parallel_random_phase_matches_serial() {
        let budget = Budget {
            max_tests: Some(25),
            wall: None,
            sbst: None,
        };
        let serial = RunConfig {
            algorithm: Algorithm::Random,
            ..RunConfig::default()
        };
        let parallel = RunConfig {
            jobs: 3,
            ..serial.clone()
        };
        let (a, _) = collect(&serial, budget, 1);
        let (b, sb) = collect(&parallel, budget, 1);
        assert_eq!(tests_of(&a), tests_of(&b));
        assert_eq!(sb.executed, 25);
    }

    #[test]
    fn stop_flag_ends_the_run_after_the_current_test() {
        let stop = AtomicBool::new(false);
        let mut n = 0;
        let summary = run(
            &Bump,
            &RunConfig::default(),
            Budget::default(),
            1,
            &stop,
            &mut |e| {
                if matches!(e, Event::Test { .. }) {
                    n += 1;
                    if n == 7 {
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            },
        )
        .unwrap();
        assert_eq!(summary.executed, 7);
        assert!(summary.stopped_by_signal);
    }

    #[test]
    fn wall_clock_budget_ends_the_run() {
        let budget = Budget {
            max_tests: None,
            wall: Some(Duration::from_millis(300)),
            sbst: None,
        };
        let (_, s) = collect(&RunConfig::default(), budget, 2);
        assert!(s.executed > 0);
        assert!(!s.stopped_by_signal);
        assert!(s.wall_s < 5.0);
    }

    /// The test events of a run: (id, beyond_budget, execution_time_s).
    fn charged(events: &[Event<f32>]) -> Vec<(usize, bool, f64)> {
        events
            .iter()
            .filter_map(|e| match e {
                Event::Test {
                    id,
                    beyond_budget,
                    execution_time_s,
                    ..
                } => Some((*id, *beyond_budget, *execution_time_s)),
                Event::Train { .. } => None,
            })
            .collect()
    }

    #[test]
    fn an_execution_budget_ends_the_run_as_the_pipeline_does() {
        // Each Bump test takes 10 simulated seconds: five fit in 55 s, the sixth ends with the
        // budget spent, is reported beyond it and is not kept.
        // With several jobs the random phase runs tests at once; they are charged in test order.
        for (algorithm, jobs) in [
            (Algorithm::Random, 1),
            (Algorithm::Random, 4),
            (Algorithm::Wogan, 1),
            (Algorithm::Wogan, 3),
        ] {
            let config = RunConfig {
                algorithm,
                jobs,
                ..RunConfig::default()
            };
            let budget = Budget {
                sbst: Some(SbstBudget {
                    generation: Duration::from_secs(3600),
                    execution_s: 55.0,
                }),
                ..Budget::default()
            };
            let (events, summary) = collect(&config, budget, 4);
            let tests = charged(&events);
            assert_eq!(tests.len(), 6, "{algorithm:?}, {jobs} jobs");
            let ids: Vec<usize> = tests.iter().map(|&(id, _, _)| id).collect();
            assert_eq!(ids, [1, 2, 3, 4, 5, 6]);
            assert!(tests[..5].iter().all(|&(_, beyond, _)| !beyond));
            assert_eq!(tests[5], (6, true, 10.0));
            assert_eq!(summary.executed, 5);
            assert_eq!(summary.beyond_budget, 1);
            assert_eq!(summary.execution_time_s, 60.0);
            assert!(summary.sbst_generation_s > 0.0);
        }
    }

    #[test]
    fn a_spent_generation_budget_discards_the_test_in_hand() {
        // The first test's generation already spends a budget of one nanosecond: the pipeline
        // still executes it (simulated time remains), then discards it and ends the run.
        let budget = Budget {
            sbst: Some(SbstBudget {
                generation: Duration::from_nanos(1),
                execution_s: 1000.0,
            }),
            ..Budget::default()
        };
        let (events, summary) = collect(&RunConfig::default(), budget, 1);
        assert_eq!(charged(&events), vec![(1, true, 10.0)]);
        assert_eq!(summary.executed, 0);
    }

    #[test]
    fn sbst_runs_are_reproducible_when_the_execution_budget_binds() {
        let budget = Budget {
            sbst: Some(SbstBudget {
                generation: Duration::from_secs(3600),
                execution_s: 205.0,
            }),
            ..Budget::default()
        };
        let tests = |(events, _): (Vec<Event<f32>>, Summary)| -> Vec<Vec<f32>> {
            events
                .into_iter()
                .filter_map(|e| match e {
                    Event::Test { test, .. } => Some(test),
                    Event::Train { .. } => None,
                })
                .collect()
        };
        let a = tests(collect(&RunConfig::default(), budget, 8));
        assert_eq!(a.len(), 21);
        assert_eq!(a, tests(collect(&RunConfig::default(), budget, 8)));
    }

    /// A SUT whose `n`-th execution is cut short by a stop raised during it.
    struct StoppedAt<'a> {
        n: usize,
        calls: std::sync::atomic::AtomicUsize,
        stop: &'a AtomicBool,
    }

    impl Sut for StoppedAt<'_> {
        type Output = usize;
        fn dim(&self) -> usize {
            2
        }
        fn is_valid(&self, _: &[f32]) -> bool {
            true
        }
        fn execute(&self, _: &[f32]) -> Option<Execution<usize>> {
            let call = self.calls.fetch_add(1, Ordering::SeqCst) + 1;
            if call == self.n {
                self.stop.store(true, Ordering::SeqCst);
                return None;
            }
            Some(Execution {
                fitness: 0.5,
                execution_time_s: 0.0,
                output: call,
            })
        }
    }

    #[test]
    fn an_execution_cut_short_by_a_stop_is_not_reported() {
        for (algorithm, n) in [(Algorithm::Random, 4), (Algorithm::Wogan, 70)] {
            let stop = AtomicBool::new(false);
            let sut = StoppedAt {
                n,
                calls: Default::default(),
                stop: &stop,
            };
            let config = RunConfig {
                algorithm,
                ..RunConfig::default()
            };
            let budget = Budget {
                max_tests: Some(300),
                wall: None,
                sbst: None,
            };
            let mut outputs = Vec::new();
            let summary = run(&sut, &config, budget, 1, &stop, &mut |e| {
                if let Event::Test { output, .. } = e {
                    outputs.push(output);
                }
            })
            .unwrap();
            assert_eq!(outputs, (1..n).collect::<Vec<_>>(), "{algorithm:?}");
            assert_eq!(summary.executed, n - 1);
            assert!(summary.stopped_by_signal);
        }
    }
}
