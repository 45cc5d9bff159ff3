//! What a run has spent and done: its budget, its clocks, the SBST competition's charges and the
//! running totals, and the one place that decides whether the run goes on.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::budget::{Budget, SbstUsage};

use super::events::{Charge, Summary};

/// The state every phase of a run shares.
pub(super) struct RunLedger<'a> {
    pub budget: Budget,
    pub stop: &'a AtomicBool,
    pub start: Instant,
    pub summary: Summary,
    /// The SBST budgets used so far.
    pub used: SbstUsage,
    /// When the current test's generation began (the end of the previous test's execution).
    pub generation_clock: Instant,
}

impl<'a> RunLedger<'a> {
    /// A run starting now under `budget`, stopped early by `stop`.
    pub fn start(budget: Budget, stop: &'a AtomicBool) -> Self {
        let start = Instant::now();
        Self {
            budget,
            stop,
            start,
            summary: Summary::default(),
            used: SbstUsage::default(),
            generation_clock: start,
        }
    }

    /// The run's totals, its clocks read now.
    pub fn finish(mut self) -> Summary {
        self.summary.wall_s = self.elapsed().as_secs_f64();
        self.summary.sbst_generation_s = self.used.generation.as_secs_f64();
        self.summary.execution_time_s = self.used.execution_s;
        self.summary
    }

    pub fn elapsed(&self) -> Duration {
        self.start.elapsed()
    }

    /// The generation time of the test being handed over now: since the generation clock began.
    pub fn generation_gap_s(&self) -> f64 {
        self.generation_clock.elapsed().as_secs_f64()
    }

    /// Whether a test charged `generation_s` may still be executed (the competition's check
    /// before execution: simulated time remains). Charges the generation time.
    pub fn hand_over(&mut self, generation_s: f64) -> bool {
        self.used.generation += Duration::from_secs_f64(generation_s.max(0.0));
        self.budget
            .sbst
            .is_none_or(|b| b.can_run_a_test(&self.used))
    }

    /// Charges an executed test's execution time; the test is beyond the budget when a budget
    /// is now spent.
    pub fn charge(&mut self, generation_s: f64, execution_time_s: f64) -> Charge {
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
    pub fn restart_generation_clock(&mut self) {
        self.generation_clock = Instant::now();
    }

    /// Whether the run must end now (and why, recorded in the summary).
    pub fn should_stop(&mut self) -> bool {
        if self.stop.load(Ordering::Relaxed) {
            self.summary.stopped_by_signal = true;
            return true;
        }
        self.budget
            .exhausted(self.summary.executed, self.elapsed(), &self.used)
    }

    pub fn remaining_tests(&self) -> usize {
        self.budget
            .max_tests
            .map_or(usize::MAX, |m| m.saturating_sub(self.summary.executed))
    }
}
