//! The random phase: random valid tests executed in order, several at once when `jobs > 1`. It
//! is the whole of a random search and the first share of a WOGAN run.
//!
//! Tests are independent here, so they are sampled one after another from the run's RNG (the
//! same sequence whatever `jobs` is), executed in parallel on a rayon pool, and reported in id
//! order: a run with `jobs = N` yields the same tests and results as with `jobs = 1`.

use std::time::Instant;

use rand_chacha::ChaCha20Rng;
use rayon::ThreadPool;

use crate::config::{Algorithm, RunConfig};
use crate::error::Error;
use crate::sut::{clamp_fitness, Sut};
use crate::test_sampler::Sampler;

use super::events::{test_event, Choice, Event, Phase};
use super::execution::execute_all;
use super::ledger::RunLedger;

/// A test of the random phase as a WOGAN run learns from it.
pub(super) struct ExecutedTest {
    /// The test's values.
    pub test: Vec<f32>,
    /// Its fitness, clamped.
    pub fitness: f64,
    /// How it failed, when it did and the niches want to know ([`Sut::failure_profile`]).
    pub failure_profile: Option<Vec<f32>>,
}

/// Executes random valid tests until the run (random search) or its random share (WOGAN) ends.
/// Returns the tests a WOGAN run learns from (none for random search).
pub(super) fn random_phase<S: Sut + ?Sized>(
    sut: &S,
    config: &RunConfig,
    sampler: &Sampler,
    rng: &mut ChaCha20Rng,
    pool: Option<&ThreadPool>,
    r: &mut RunLedger,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Result<Vec<ExecutedTest>, Error> {
    let w = &config.wogan;
    // Random phase: the whole run for `random`, the first share for `wogan`.
    let mut executed_tests: Vec<ExecutedTest> = Vec::new();
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
        let sampled = match sample_tests(sut, sampler, rng, count) {
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
        let tests: Vec<&[f32]> = sampled.iter().map(|s| s.test.as_slice()).collect();
        let results = execute_all(sut, &tests, pool);
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
                    executed_tests.push(ExecutedTest {
                        test: s.test.clone(),
                        fitness,
                        failure_profile: config
                            .wogan
                            .niches
                            .failure_profile(sut, fitness, &e.output),
                    });
                }
            }
            on_event(test_event(
                r.summary.executed + usize::from(charge.beyond_budget),
                Phase::Random,
                s.test,
                fitness,
                Choice {
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
    Ok(executed_tests)
}

/// One sampled test waiting for execution.
struct Sampled {
    pub test: Vec<f32>,
    pub invalid: usize,
    pub generation_s: f64,
}

/// Samples `count` valid tests in order.
fn sample_tests<S: Sut + ?Sized, R: rand::Rng + ?Sized>(
    sut: &S,
    sampler: &Sampler,
    rng: &mut R,
    count: usize,
) -> Result<Vec<Sampled>, Error> {
    (0..count)
        .map(|_| {
            let t0 = Instant::now();
            let mut invalid = 0;
            let test = sampler.sample_valid(sut, rng, &mut invalid)?;
            Ok(Sampled {
                test,
                invalid,
                generation_s: t0.elapsed().as_secs_f64(),
            })
        })
        .collect()
}
