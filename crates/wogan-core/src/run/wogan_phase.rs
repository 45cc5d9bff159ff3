//! The WOGAN phase: after the random share, retrain every `train_every` tests and execute the
//! test the networks propose, until the run ends; or, from a restored snapshot, propose with
//! networks that do not train.

use std::time::Instant;

use rand_chacha::ChaCha20Rng;

use crate::error::Error;
use crate::sut::{clamp_fitness, Sut};
use crate::test_sampler::Sampler;
use crate::wogan::WoganModel;

use super::events::{test_event, Choice, Event, Phase};
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
/// its settings until the run ends; returns the model as the run leaves it.
pub(super) fn wogan_phase<S: Sut + ?Sized>(
    sut: &S,
    mut model: WoganModel,
    training: Training,
    sampler: &Sampler,
    rng: &mut ChaCha20Rng,
    r: &mut RunLedger,
    on_event: &mut dyn FnMut(Event<S::Output>),
) -> Result<WoganModel, Error> {
    // The settings the model was built (or trained) with.
    let w = &model.config().clone();
    let mut since_train = usize::MAX;
    while !r.should_stop() {
        if training == Training::Retrain && since_train >= w.train_every {
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
        let p = match model.propose(sut, sampler, rng) {
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
            Choice {
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
    Ok(model)
}
