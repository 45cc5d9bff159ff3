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
mod execution;
mod ledger;
mod random_phase;
#[cfg(test)]
mod tests;
mod wogan_phase;

use std::sync::atomic::{AtomicBool, Ordering};

use rand::SeedableRng;
use rand_chacha::ChaCha20Rng;

use crate::budget::Budget;
use crate::config::{Algorithm, RunConfig};
use crate::error::Error;
use crate::sut::Sut;
use crate::test_sampler::Sampler;
use crate::wogan::{ModelSnapshot, WoganModel};

pub use events::{Event, Phase, Summary};
use execution::worker_pool;
use ledger::RunLedger;
use random_phase::random_phase;
use wogan_phase::{wogan_phase, Training};

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
    run_inner(sut, config, budget, seed, stop, on_event, false).map(|(summary, _)| summary)
}

/// As [`run`], and also the snapshot of WOGAN's proposing networks as the run ends, for proposing
/// more tests later without training (`None` for random search, or a run that ended before its
/// first training round).
pub fn run_with_snapshot<S: Sut + ?Sized>(
    sut: &S,
    config: &RunConfig,
    budget: Budget,
    seed: u64,
    stop: &AtomicBool,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Result<(Summary, Option<ModelSnapshot>), Error> {
    run_inner(sut, config, budget, seed, stop, on_event, true)
}

/// Runs a search that chooses every test with a restored WOGAN (its proposing networks, saved
/// by [`run_with_snapshot`]): no random phase and no training, each test chosen as the trained
/// WOGAN chooses one. Its test events say `phase: wogan`; there are no train events.
pub fn run_from_snapshot<S: Sut + ?Sized>(
    sut: &S,
    snapshot: &ModelSnapshot,
    config: &RunConfig,
    budget: Budget,
    seed: u64,
    stop: &AtomicBool,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Result<Summary, Error> {
    config.validate()?;
    if sut.dim() != snapshot.dim {
        return Err(Error::Config(format!(
            "the snapshot proposes tests of {} values, the SUT takes {}",
            snapshot.dim,
            sut.dim()
        )));
    }
    let model = WoganModel::from_snapshot(snapshot)?;
    let pool = worker_pool(config)?;
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut r = RunLedger::start(budget.effective(), stop);
    let go_on = searching(&r);
    let sampler = Sampler::new(snapshot.dim, config.sampler.clone()).interruptible(&go_on);
    // The snapshot's own settings propose (its acceptance decay, candidate batch, ...).
    wogan_phase(
        sut,
        model,
        Training::Frozen,
        &sampler,
        &mut rng,
        pool.as_ref(),
        &mut r,
        on_event,
    )?;
    Ok(r.finish())
}

/// Whether a long search for a valid test may go on: no stop asked for and wall-clock time left.
/// (Not the generation budget: the competition lets a generator finish the test in hand, then
/// executes and discards it; the sampler's attempt limit bounds the search.)
fn searching<'a>(r: &RunLedger<'a>) -> impl Fn() -> bool + 'a {
    let (stop, wall, start) = (r.stop, r.budget.wall, r.start);
    move || !stop.load(Ordering::Relaxed) && wall.is_none_or(|w| start.elapsed() < w)
}

/// The run, keeping the model's snapshot when `keep_snapshot`.
fn run_inner<S: Sut + ?Sized>(
    sut: &S,
    config: &RunConfig,
    budget: Budget,
    seed: u64,
    stop: &AtomicBool,
    on_event: &mut dyn FnMut(Event<S::Output>),
    keep_snapshot: bool,
) -> Result<(Summary, Option<ModelSnapshot>), Error> {
    config.validate()?;
    let dim = sut.dim();
    if dim == 0 {
        return Err(Error::Config("the SUT's dimension is 0".into()));
    }
    let pool = worker_pool(config)?;
    let mut rng = ChaCha20Rng::seed_from_u64(seed);
    let mut r = RunLedger::start(budget.effective(), stop);
    let go_on = searching(&r);
    let sampler = Sampler::new(dim, config.sampler.clone()).interruptible(&go_on);

    let executed_tests = random_phase(
        sut,
        config,
        &sampler,
        &mut rng,
        pool.as_ref(),
        &mut r,
        on_event,
    )?;
    let mut snapshot = None;
    if config.algorithm == Algorithm::Wogan && !r.should_stop() {
        let mut model = WoganModel::new(dim, &config.wogan, &mut rng);
        // With more than one job the analyzer trains beside the WGAN (the same numbers).
        model.set_concurrent_training(config.jobs > 1);
        for t in &executed_tests {
            model.add_executed(sut, &t.test, t.fitness, t.failure_profile.as_deref());
            model.queue_remakes(&t.test, t.fitness);
        }
        drop(executed_tests);
        let model = wogan_phase(
            sut,
            model,
            Training::Retrain,
            &sampler,
            &mut rng,
            pool.as_ref(),
            &mut r,
            on_event,
        )?;
        if keep_snapshot {
            snapshot = model.snapshot().ok();
        }
    }
    Ok((r.finish(), snapshot))
}
