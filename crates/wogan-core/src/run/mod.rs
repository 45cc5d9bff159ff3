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

mod events;
mod ledger;
mod random_phase;
#[cfg(test)]
mod tests;
mod wogan_phase;

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;

use crate::budget::{Budget, SbstUsage};
use crate::config::{Algorithm, RunConfig};
use crate::error::Error;
use crate::sut::Sut;
use crate::test_sampler::Sampler;

pub use events::{Event, Phase, Summary};
use ledger::RunLedger;
use random_phase::random_phase;
use wogan_phase::wogan_phase;

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
    let mut r = RunLedger {
        budget,
        stop,
        start,
        summary: Summary::default(),
        used: SbstUsage::default(),
        generation_clock: start,
    };

    let executed_tests = random_phase(
        sut,
        config,
        &sampler,
        &mut rng,
        pool.as_ref(),
        &mut r,
        on_event,
    )?;
    if config.algorithm == Algorithm::Wogan && !r.should_stop() {
        wogan_phase(
            sut,
            config,
            executed_tests,
            &sampler,
            &mut rng,
            &mut r,
            on_event,
        )?;
    }
    r.summary.wall_s = r.elapsed().as_secs_f64();
    r.summary.sbst_generation_s = r.used.generation.as_secs_f64();
    r.summary.execution_time_s = r.used.execution_s;
    Ok(r.summary)
}
