//! The WOGAN phase: after the random share, retrain every `train_every` tests and execute the
//! tests the networks propose, until the run ends; or, from a restored snapshot, propose with
//! networks that do not train.
//!
//! With `jobs` = N > 1 the phase goes in rounds: it chooses up to N tests one after another
//! (each through the acceptance rule, whose target starts afresh for each or carries over
//! between them, as `round_acceptance` says), executes them at once, and learns from all of them before the next
//! round. Training follows the count of tests executed: a round that brings the tests since the
//! last training to `train_every` or more retrains once, and the remainder counts towards the
//! next. With N = 1 every round is one test and this is the paper's loop, step for step. With
//! N > 1 the analyzer also trains on a second thread beside the WGAN, which changes no number.

use std::time::Instant;

use rand_chacha::ChaCha20Rng;
use rayon::ThreadPool;

use crate::error::Error;
use crate::sut::{clamp_fitness, Sut};
use crate::test_sampler::Sampler;
use crate::wogan::{Origin, Proposal, WoganModel};

use super::events::{test_event, Choice, Event, Phase};
use super::execution::execute_all;
use super::ledger::RunLedger;

/// Whether the WOGAN phase trains its model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Training {
    /// Retrain every `train_every` tests, first before the first proposal (the paper's WOGAN).
    Retrain,
    /// Never: propose with the model as given (a restored snapshot's networks).
    Frozen,
}

/// Runs WOGAN's loop with `model` (holding the random phase's tests, or a restored snapshot) and
/// its settings until the run ends, executing rounds of up to `jobs` tests on `pool`; returns
/// the model as the run leaves it.
#[allow(clippy::too_many_arguments)]
pub(super) fn wogan_phase<S: Sut + ?Sized>(
    sut: &S,
    mut model: WoganModel,
    training: Training,
    sampler: &Sampler,
    rng: &mut ChaCha20Rng,
    pool: Option<&ThreadPool>,
    r: &mut RunLedger,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Result<WoganModel, Error> {
    // The settings the model was built (or trained) with.
    let w = &model.config().clone();
    let jobs = pool.map_or(1, ThreadPool::current_num_threads);
    // Tests executed since the last training; the first round trains first.
    let mut since_train = w.train_every;
    while !r.should_stop() {
        if training == Training::Retrain && since_train >= w.train_every {
            train(&mut model, rng, r, on_event)?;
            since_train %= w.train_every;
            // Training can be long: honour a stop or an expired clock before proposing.
            if r.should_stop() {
                break;
            }
        }
        let count = jobs.min(r.remaining_tests()).max(1);
        let round = match choose_round(&mut model, sut, sampler, rng, count) {
            Ok(round) => round,
            // The loop's next check says why it ends.
            Err(Error::Interrupted) => continue,
            Err(error) => return Err(error),
        };
        let Some(learnt) = execute_round(&mut model, sut, round, pool, r, on_event) else {
            break;
        };
        since_train += learnt;
        r.restart_generation_clock();
    }
    Ok(model)
}

/// One training round, reported as a train event; a diverged network ends the run.
fn train<O>(
    model: &mut WoganModel,
    rng: &mut ChaCha20Rng,
    r: &mut RunLedger,
    on_event: &mut dyn FnMut(Event<O>),
) -> Result<(), Error> {
    let w = model.config();
    let alpha = r.budget.alpha(
        w.init_fraction,
        w.alpha_max,
        r.summary.executed,
        r.elapsed(),
        &r.used,
    );
    let t0 = Instant::now();
    let stats = model.train(alpha, rng)?;
    let train_s = t0.elapsed().as_secs_f64();
    r.summary.training_s += train_s;
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
        // The networks' weights are no longer numbers: every later proposal would be noise
        // presented as WOGAN's.
        return Err(Error::Diverged { tests: model.len() });
    }
    Ok(())
}

/// A chosen test and the time its choice took.
struct Chosen {
    proposal: Proposal,
    generation_s: f64,
}

/// Chooses `count` tests one after another: the failures' remakes waiting first, then the
/// networks' choices, the acceptance target carried between those as the model's
/// `round_acceptance` says.
fn choose_round<S: Sut + ?Sized>(
    model: &mut WoganModel,
    sut: &S,
    sampler: &Sampler,
    rng: &mut ChaCha20Rng,
    count: usize,
) -> Result<Vec<Chosen>, Error> {
    let rule = model.config().round_acceptance;
    let mut acceptance = model.acceptance();
    let mut round = Vec::with_capacity(count);
    let mut chosen_by_networks = 0;
    for _ in 0..count {
        let t0 = Instant::now();
        if let Some(remake) = model.next_remake(sut) {
            round.push(Chosen {
                proposal: remake,
                generation_s: t0.elapsed().as_secs_f64(),
            });
            continue;
        }
        if chosen_by_networks > 0 {
            acceptance.next_choice(rule);
        }
        let mut proposal = model.propose_with(sut, sampler, rng, &mut acceptance)?;
        proposal.invalid += model.take_invalid_remakes();
        chosen_by_networks += 1;
        round.push(Chosen {
            proposal,
            generation_s: t0.elapsed().as_secs_f64(),
        });
    }
    Ok(round)
}

/// Executes a round's tests at once, charges and reports them in order and learns from those
/// within the budget. Returns how many were learnt from, or `None` when the run ends with this
/// round (a stop, or a budget spent).
fn execute_round<S: Sut + ?Sized>(
    model: &mut WoganModel,
    sut: &S,
    round: Vec<Chosen>,
    pool: Option<&ThreadPool>,
    r: &mut RunLedger,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Option<usize> {
    // Tests chosen together are charged in test order: each its own choice's time, the first
    // also the rest of the time since the previous execution ended (as the random phase does).
    let gap_s = r.generation_gap_s();
    let later_s: f64 = round.iter().skip(1).map(|c| c.generation_s).sum();
    let tests: Vec<&[f32]> = round.iter().map(|c| c.proposal.test.as_slice()).collect();
    let t0 = Instant::now();
    let results = execute_all(sut, &tests, pool);
    r.summary.simulation_s += t0.elapsed().as_secs_f64();
    let mut learnt = 0;
    let mut run_ends = false;
    for (
        i,
        (
            Chosen {
                proposal: p,
                generation_s: choice_s,
            },
            e,
        ),
    ) in round.into_iter().zip(results).enumerate()
    {
        let Some(e) = e else {
            // Cut short by a stop: nothing to report for this test; the run ends with the round.
            r.summary.stopped_by_signal = true;
            run_ends = true;
            continue;
        };
        let generation_s = if i == 0 {
            (gap_s - later_s).max(choice_s)
        } else {
            choice_s
        };
        if !r.hand_over(generation_s) {
            // The competition would not have executed this test, nor any after it.
            return None;
        }
        let charge = r.charge(generation_s, e.execution_time_s);
        let fitness = clamp_fitness(e.fitness);
        r.summary.invalid_candidates += p.invalid;
        r.summary.generation_s += choice_s;
        if !charge.beyond_budget {
            let niches = &model.config().niches;
            let failure_profile = niches.failure_profile(sut, fitness, &e.output);
            model.add_executed(sut, &p.test, fitness, failure_profile.as_deref());
            if p.origin != Origin::Remake {
                model.queue_remakes(&p.test, fitness);
            }
            learnt += 1;
            r.summary.executed += 1;
        }
        on_event(test_event(
            r.summary.executed + usize::from(charge.beyond_budget),
            match p.origin {
                Origin::Generator => Phase::Wogan,
                Origin::Mutant => Phase::Mutant,
                Origin::Remake => Phase::Remake,
            },
            p.test,
            fitness,
            Choice {
                predicted_fitness: p.predicted,
                invalid_candidates: p.invalid,
                ranked_candidates: p.ranked,
                generation_s: choice_s,
            },
            &charge,
            e.output,
        ));
        if charge.beyond_budget {
            return None;
        }
    }
    (!run_ends).then_some(learnt)
}
