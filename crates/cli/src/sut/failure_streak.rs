//! Drives failed in a row by a program outside wogan (a controller process, an executor): after
//! `limit` of them the run gives up, stopped cleanly with every finished test written, and says
//! why.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

/// The count of failed drives in a row, and the reason the run gave up, if it did.
#[derive(Debug)]
pub struct FailureStreak {
    limit: usize,
    in_a_row: AtomicUsize,
    gave_up: Mutex<Option<String>>,
}

impl FailureStreak {
    /// Gives up after `limit` failed drives in a row.
    pub fn new(limit: usize) -> Self {
        Self {
            limit,
            in_a_row: AtomicUsize::new(0),
            gave_up: Mutex::new(None),
        }
    }

    /// A drive went through: the streak is broken.
    pub fn passed(&self) {
        self.in_a_row.store(0, Ordering::SeqCst);
    }

    /// A drive failed because of `reason`; at the limit, the run is stopped through `stop`.
    pub fn failed(&self, what: &str, reason: &str, stop: &AtomicBool) {
        let in_a_row = self.in_a_row.fetch_add(1, Ordering::SeqCst) + 1;
        if in_a_row >= self.limit {
            let mut gave_up = self.gave_up.lock().unwrap_or_else(|p| p.into_inner());
            gave_up.get_or_insert_with(|| {
                format!("{what} failed {in_a_row} roads in a row; the last: {reason}")
            });
            stop.store(true, Ordering::SeqCst);
        }
    }

    /// Why the run gave up, if it did.
    pub fn gave_up(&self) -> Option<String> {
        self.gave_up
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gives_up_after_the_limit_in_a_row_only() {
        let stop = AtomicBool::new(false);
        let streak = FailureStreak::new(2);
        streak.failed("it", "one", &stop);
        streak.passed();
        streak.failed("it", "two", &stop);
        assert!(!stop.load(Ordering::SeqCst) && streak.gave_up().is_none());
        streak.failed("it", "three", &stop);
        assert!(stop.load(Ordering::SeqCst));
        assert_eq!(
            streak.gave_up().unwrap(),
            "it failed 2 roads in a row; the last: three"
        );
    }
}
