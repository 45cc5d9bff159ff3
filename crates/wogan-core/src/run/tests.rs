//! Tests of whole runs on small SUTs: schedules, seeds, budgets and stops.

use super::*;
use crate::{Execution, SbstBudget};
use std::time::Duration;

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
    assert_eq!(trains_of(&a), 5, "retrain every 3 tests");
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

fn trains_of<O>(events: &[Event<O>]) -> usize {
    events
        .iter()
        .filter(|e| matches!(e, Event::Train { .. }))
        .count()
}

fn ranked_of(events: &[Event<f32>]) -> usize {
    events
        .iter()
        .map(|e| match e {
            Event::Test {
                ranked_candidates, ..
            } => *ranked_candidates,
            Event::Train { .. } => 0,
        })
        .sum()
}

#[test]
fn parallel_wogan_rounds_are_reproducible_and_train_on_the_tests_executed() {
    let budget = Budget {
        max_tests: Some(30),
        wall: None,
        sbst: None,
    };
    // 15 random tests, then 15 WOGAN tests. One job trains before tests 1, 4, 7, 10 and 13 of
    // the phase. Rounds of 2 (2, 2, ..., 1) bring the count since training to 2, 4 (train), 3
    // (train), 2, 4 (train), 3 (train), 2: five as well. Rounds of 4 (4, 4, 4, 3): 4 (train),
    // 5 (train), 6 (train): four, one per round, as a round trains at most once.
    for (jobs, trains) in [(1, 5), (2, 5), (4, 4)] {
        let config = RunConfig {
            jobs,
            wogan: crate::WoganConfig {
                init_fraction: 0.5,
                ..Default::default()
            },
            ..RunConfig::default()
        };
        let (a, summary) = collect(&config, budget, 9);
        let (b, _) = collect(&config, budget, 9);
        assert_eq!(tests_of(&a), tests_of(&b), "jobs {jobs}");
        assert_eq!(summary.executed, 30, "jobs {jobs}");
        let t = tests_of(&a);
        assert!(t.iter().enumerate().all(|(i, x)| x.0 == i + 1));
        assert_eq!(t.iter().filter(|x| x.1 == Phase::Wogan).count(), 15);
        assert_eq!(trains_of(&a), trains, "jobs {jobs}");
    }
}

#[test]
fn a_restarted_round_ranks_more_candidates_than_a_continued_one() {
    let budget = Budget {
        max_tests: Some(60),
        wall: None,
        sbst: None,
    };
    let ranked = |round_acceptance| {
        let config = RunConfig {
            jobs: 4,
            wogan: crate::WoganConfig {
                round_acceptance,
                ..Default::default()
            },
            ..RunConfig::default()
        };
        ranked_of(&collect(&config, budget, 3).0)
    };
    let continued = ranked(crate::RoundAcceptance::Continue);
    let restarted = ranked(crate::RoundAcceptance::Restart);
    assert!(
        restarted > continued,
        "restarted {restarted}, continued {continued}"
    );
}

#[test]
fn each_wogan_failure_is_followed_by_its_new_remakes_and_remakes_are_not_remade() {
    use crate::wogan::remakes_of;
    let budget = Budget {
        max_tests: Some(160),
        wall: None,
        sbst: None,
    };
    let mut config = RunConfig::default();
    config.wogan.remakes = crate::RemakeConfig {
        enabled: true,
        min_fitness: 0.5,
    };
    let t = tests_of(&collect(&config, budget, 5).0);
    let is_failure = |fitness: f64| fitness >= 0.5;
    let mut followed = 0;
    for (i, (_, phase, test, fitness)) in t.iter().enumerate() {
        if *phase == Phase::Remake {
            assert!(
                t[..i].iter().any(|(_, p, parent, f)| *p != Phase::Remake
                    && is_failure(*f)
                    && remakes_of(parent).contains(test)),
                "test {} is no remake of an earlier failure that is not itself a remake",
                i + 1
            );
        }
        if matches!(phase, Phase::Wogan | Phase::Mutant) && is_failure(*fitness) {
            // One test a round: the queue was empty when this test was chosen, so its remakes
            // come next, less those equal to it, to one another or to a test executed before.
            let mut expected: Vec<Vec<f32>> = Vec::new();
            for remake in remakes_of(test) {
                let executed = t[..=i].iter().any(|x| x.2 == remake);
                if remake != *test && !executed && !expected.contains(&remake) {
                    expected.push(remake);
                }
            }
            let next: Vec<Vec<f32>> = t[i + 1..]
                .iter()
                .take(expected.len())
                .map(|x| x.2.clone())
                .collect();
            assert_eq!(next, expected[..next.len()], "after test {}", i + 1);
            followed += 1;
        }
    }
    assert!(followed > 0, "no failure in the WOGAN phase to follow");
    let plain = tests_of(&collect(&RunConfig::default(), budget, 5).0);
    assert!(plain.iter().all(|x| x.1 != Phase::Remake));
}
