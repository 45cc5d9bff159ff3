//! How long a run may go on, and where in its schedule it is.
//!
//! The schedule (end of the random phase, bin bias α) follows `max_tests` when it is given, so
//! runs with a test budget are reproducible; it follows elapsed wall time otherwise.

use std::time::Duration;

/// Test count and/or wall-clock limit; the run stops at whichever comes first.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Budget {
    /// Largest number of executed tests.
    pub max_tests: Option<usize>,
    /// Largest wall-clock time.
    pub wall: Option<Duration>,
}

/// Test count used when neither limit is given.
pub const DEFAULT_MAX_TESTS: usize = 300;

impl Budget {
    /// The limits actually applied: with neither limit, `max_tests = 300`.
    pub fn effective(self) -> Self {
        if self.max_tests.is_none() && self.wall.is_none() {
            Self {
                max_tests: Some(DEFAULT_MAX_TESTS),
                wall: None,
            }
        } else {
            self
        }
    }

    /// Whether no further test may start.
    pub fn exhausted(&self, executed: usize, elapsed: Duration) -> bool {
        self.max_tests.is_some_and(|m| executed >= m) || self.wall.is_some_and(|w| elapsed >= w)
    }

    /// Fraction of the schedule used, in `[0, 1]`.
    pub fn progress(&self, executed: usize, elapsed: Duration) -> f64 {
        let p = match (self.max_tests, self.wall) {
            (Some(m), _) => executed as f64 / m.max(1) as f64,
            (None, Some(w)) => elapsed.as_secs_f64() / w.as_secs_f64().max(1e-9),
            (None, None) => 0.0,
        };
        p.clamp(0.0, 1.0)
    }

    /// Whether the random initial phase (a share `init` of the schedule) is over.
    ///
    /// At least one test is always random, so the networks have data to learn from.
    pub fn initial_phase_over(&self, init: f64, executed: usize, elapsed: Duration) -> bool {
        if executed == 0 {
            return false;
        }
        match self.max_tests {
            Some(m) => executed as f64 >= (init * m as f64).round(),
            None => self.progress(executed, elapsed) >= init,
        }
    }

    /// Bin bias α: 0 at the end of the random phase, rising linearly to `alpha_max` at the end.
    pub fn alpha(&self, init: f64, alpha_max: f64, executed: usize, elapsed: Duration) -> f64 {
        let p = self.progress(executed, elapsed);
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
        assert_eq!(b.max_tests, Some(300));
        assert!(b.exhausted(300, Duration::ZERO));
        assert!(!b.exhausted(299, Duration::from_secs(1_000_000)));
    }

    #[test]
    fn alpha_rises_linearly_after_random_phase() {
        let b = Budget {
            max_tests: Some(100),
            wall: None,
        };
        let z = Duration::ZERO;
        assert_eq!(b.alpha(0.2, 3.0, 10, z), 0.0);
        assert_eq!(b.alpha(0.2, 3.0, 20, z), 0.0);
        assert!((b.alpha(0.2, 3.0, 60, z) - 1.5).abs() < 1e-12);
        assert!((b.alpha(0.2, 3.0, 100, z) - 3.0).abs() < 1e-12);
        assert!(!b.initial_phase_over(0.2, 19, z));
        assert!(b.initial_phase_over(0.2, 20, z));
        assert!(!b.initial_phase_over(0.0, 0, z));
    }

    #[test]
    fn wall_clock_schedule() {
        let b = Budget {
            max_tests: None,
            wall: Some(Duration::from_secs(10)),
        };
        assert!((b.alpha(0.2, 3.0, 5, Duration::from_secs(6)) - 1.5).abs() < 1e-9);
        assert!(b.exhausted(1, Duration::from_secs(10)));
        let both = Budget {
            max_tests: Some(5),
            wall: Some(Duration::from_secs(10)),
        };
        assert!(both.exhausted(5, Duration::ZERO));
        assert!(both.exhausted(1, Duration::from_secs(11)));
    }
}
