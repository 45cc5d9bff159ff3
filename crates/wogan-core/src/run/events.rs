//! What a run reports: an [`Event`] per executed test and per training round, and a [`Summary`].

use serde::{Deserialize, Serialize};

#[cfg(doc)]
use crate::budget::SbstBudget;

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
    /// A remake of a failure, executed without the analyzer's say (see
    /// [`crate::RemakeConfig`]).
    Remake,
}

impl Phase {
    /// The name, as test records spell it (`random`, `wogan`, `mutant`, `remake`).
    pub fn name(self) -> &'static str {
        match self {
            Phase::Random => "random",
            Phase::Wogan => "wogan",
            Phase::Mutant => "mutant",
            Phase::Remake => "remake",
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

/// What handing a test to execution charged.
pub(super) struct Charge {
    pub generation_s: f64,
    pub execution_time_s: f64,
    pub beyond_budget: bool,
}

/// How a test was chosen, for its event.
pub(super) struct Choice {
    pub predicted_fitness: Option<f64>,
    pub invalid_candidates: usize,
    pub ranked_candidates: usize,
    pub generation_s: f64,
}

/// The event of an executed test.
pub(super) fn test_event<O>(
    id: usize,
    phase: Phase,
    test: Vec<f32>,
    fitness: f64,
    choice: Choice,
    charge: &Charge,
    output: O,
) -> Event<O> {
    Event::Test {
        id,
        phase,
        test,
        fitness,
        predicted_fitness: choice.predicted_fitness,
        invalid_candidates: choice.invalid_candidates,
        ranked_candidates: choice.ranked_candidates,
        generation_ms: choice.generation_s * 1e3,
        sbst_generation_ms: charge.generation_s * 1e3,
        execution_time_s: charge.execution_time_s,
        beyond_budget: charge.beyond_budget,
        output,
    }
}
