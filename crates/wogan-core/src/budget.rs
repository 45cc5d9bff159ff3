//! How long a run may go on, and where in its schedule it is.
//!
//! Three kinds of limit, the run stopping at whichever comes first: a test count, a wall clock,
//! and the SBST competition's pair of budgets ([`SbstBudget`]). The schedule (end of the random
//! phase, bin bias α) follows `max_tests` when it is given, else the competition's execution
//! budget (simulated time), else the wall clock: the first two make runs reproducible.

use std::time::Duration;

/// Limits of a run; it stops at whichever comes first.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Budget {
    /// Largest number of executed tests.
    pub max_tests: Option<usize>,
    /// Largest wall-clock time.
    pub wall: Option<Duration>,
    /// The SBST competition's generation and execution budgets.
    pub sbst: Option<SbstBudget>,
}

/// The SBST 2022 competition's budgets (`code_pipeline/executors.py`, `Budget`).
///
/// Generation time is real time spent between tests: from the start of the run, and then from
/// the end of one test's execution to the start of the next, so that proposing, validating
/// candidates and training all count. Execution time is each executed test's simulated time.
/// A test may start while simulated time remains; a test that ends with either budget spent is
/// not kept (it still counts as generated) and the run ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SbstBudget {
    /// Real time for generating tests.
    pub generation: Duration,
    /// Simulated time for executing them, seconds.
    pub execution_s: f64,
}

/// How much of the SBST budgets a run has used.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SbstUsage {
    /// Generation time charged so far.
    pub generation: Duration,
    /// Execution time charged so far, seconds (the test that went over included).
    pub execution_s: f64,
}

impl SbstBudget {
    /// Whether another test may start (the competition's `can_run_a_test`: simulated time left).
    pub fn can_run_a_test(&self, used: &SbstUsage) -> bool {
        self.execution_s - used.execution_s > 0.0
    }

    /// Whether either budget is spent (the competition's `is_over`).
    pub fn is_over(&self, used: &SbstUsage) -> bool {
        self.generation.as_secs_f64() - used.generation.as_secs_f64() <= 0.0
            || self.execution_s - used.execution_s <= 0.0
    }
}

/// Test count used when neither limit is given.
pub const DEFAULT_MAX_TESTS: usize = 300;

impl Budget {
    /// The limits actually applied: with no limit at all, `max_tests = 300`.
    pub fn effective(self) -> Self {
        if self.max_tests.is_none() && self.wall.is_none() && self.sbst.is_none() {
            Self {
                max_tests: Some(DEFAULT_MAX_TESTS),
                ..self
            }
        } else {
            self
        }
    }

    /// Whether no further test may start.
    pub fn exhausted(&self, executed: usize, elapsed: Duration, used: &SbstUsage) -> bool {
        self.max_tests.is_some_and(|m| executed >= m)
            || self.wall.is_some_and(|w| elapsed >= w)
            || self.sbst.is_some_and(|b| b.is_over(used))
    }

    /// Fraction of the schedule used, in `[0, 1]`.
    pub fn progress(&self, executed: usize, elapsed: Duration, used: &SbstUsage) -> f64 {
        let p = match (self.max_tests, self.sbst, self.wall) {
            (Some(m), _, _) => executed as f64 / m.max(1) as f64,
            (None, Some(b), _) => used.execution_s / b.execution_s.max(1e-9),
            (None, None, Some(w)) => elapsed.as_secs_f64() / w.as_secs_f64().max(1e-9),
            (None, None, None) => 0.0,
        };
        p.clamp(0.0, 1.0)
    }

    /// Whether the random initial phase (a share `init` of the schedule) is over.
    ///
    /// At least one test is always random, so the networks have data to learn from.
    pub fn initial_phase_over(
        &self,
        init: f64,
        executed: usize,
        elapsed: Duration,
        used: &SbstUsage,
    ) -> bool {
        if executed == 0 {
            return false;
        }
        match self.max_tests {
            Some(m) => executed as f64 >= (init * m as f64).round(),
            None => self.progress(executed, elapsed, used) >= init,
        }
    }

    /// Bin bias α: 0 at the end of the random phase, rising linearly to `alpha_max` at the end.
    pub fn alpha(
        &self,
        init: f64,
        alpha_max: f64,
        executed: usize,
        elapsed: Duration,
        used: &SbstUsage,
    ) -> f64 {
        let p = self.progress(executed, elapsed, used);
        let rest = 1.0 - init;
        let t = if rest <= 0.0 {
            1.0
        } else {
            ((p - init) / rest).clamp(0.0, 1.0)
        };
        alpha_max * t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_300_tests() {
        let b = Budget::default().effective();
        let none = SbstUsage::default();
        assert_eq!(b.max_tests, Some(300));
        assert!(b.exhausted(300, Duration::ZERO, &none));
        assert!(!b.exhausted(299, Duration::from_secs(1_000_000), &none));
    }

    #[test]
    fn alpha_rises_linearly_after_random_phase() {
        let b = Budget {
            max_tests: Some(100),
            ..Budget::default()
        };
        let z = Duration::ZERO;
        let none = SbstUsage::default();
        assert_eq!(b.alpha(0.2, 3.0, 10, z, &none), 0.0);
        assert_eq!(b.alpha(0.2, 3.0, 20, z, &none), 0.0);
        assert!((b.alpha(0.2, 3.0, 60, z, &none) - 1.5).abs() < 1e-12);
        assert!((b.alpha(0.2, 3.0, 100, z, &none) - 3.0).abs() < 1e-12);
        assert!(!b.initial_phase_over(0.2, 19, z, &none));
        assert!(b.initial_phase_over(0.2, 20, z, &none));
        assert!(!b.initial_phase_over(0.0, 0, z, &none));
    }

    #[test]
    fn wall_clock_schedule() {
        let none = SbstUsage::default();
        let b = Budget {
            wall: Some(Duration::from_secs(10)),
            ..Budget::default()
        };
        assert!((b.alpha(0.2, 3.0, 5, Duration::from_secs(6), &none) - 1.5).abs() < 1e-9);
        assert!(b.exhausted(1, Duration::from_secs(10), &none));
        let both = Budget {
            max_tests: Some(5),
            wall: Some(Duration::from_secs(10)),
            sbst: None,
        };
        assert!(both.exhausted(5, Duration::ZERO, &none));
        assert!(both.exhausted(1, Duration::from_secs(11), &none));
    }

    #[test]
    fn sbst_budgets_follow_the_pipeline() {
        let b = SbstBudget {
            generation: Duration::from_secs(60),
            execution_s: 600.0,
        };
        let used = |generation_s: u64, execution_s: f64| SbstUsage {
            generation: Duration::from_secs(generation_s),
            execution_s,
        };
        // A test may start while simulated time remains, whatever the generation clock says.
        assert!(b.can_run_a_test(&used(61, 599.9)));
        assert!(!b.can_run_a_test(&used(0, 600.0)));
        // Either budget reaching zero ends the run.
        assert!(!b.is_over(&used(59, 599.9)));
        assert!(b.is_over(&used(60, 0.0)));
        assert!(b.is_over(&used(0, 600.0)));
    }

    #[test]
    fn sbst_schedule_follows_simulated_time() {
        let b = Budget {
            sbst: Some(SbstBudget {
                generation: Duration::from_secs(3600),
                execution_s: 1000.0,
            }),
            ..Budget::default()
        };
        assert_eq!(b.effective().max_tests, None);
        let at = |execution_s: f64| SbstUsage {
            generation: Duration::from_secs(3000),
            execution_s,
        };
        // Wall and generation time do not move the schedule; simulated time does.
        let late = Duration::from_secs(100_000);
        assert!(!b.initial_phase_over(0.2, 10, late, &at(199.0)));
        assert!(b.initial_phase_over(0.2, 10, Duration::ZERO, &at(200.0)));
        assert!((b.alpha(0.2, 3.0, 50, late, &at(600.0)) - 1.5).abs() < 1e-12);
    }
}
