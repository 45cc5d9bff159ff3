//! WOGAN's rule for when to stop ranking candidates and execute the best one.
//!
//! As stgem's `do_generate_next_test` does it: each valid candidate joins a pool ranked by the
//! analyzer's prediction; then the acceptance target, which starts at 1, is multiplied by the
//! decay (0.95), and the pool's best is accepted once its prediction is within 1e-4 of the
//! target. (stgem works on the objective `1 − fitness` with a target rising from 0; this is the
//! same rule in fitness terms.) The first-ranked of equal predictions wins. A confident analyzer
//! so executes one of the first candidates; a pessimistic one ranks up to about 180.

use crate::config::RoundAcceptance;

/// Slack in the acceptance test (stgem's), so a saturated prediction cannot stall the rule.
const ACCEPT_EPS: f64 = 1e-4;

/// The state of one choice: the target and the best prediction ranked so far.
#[derive(Debug, Clone)]
pub(crate) struct Acceptance {
    decay: f64,
    target: f64,
    best: f64,
    ranked: usize,
}

/// What ranking one candidate decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Ranked {
    /// The candidate is the best so far (keep it).
    pub best: bool,
    /// The best so far is accepted: stop and execute it.
    pub accept: bool,
}

impl Acceptance {
    /// A choice whose target decays by `decay` (in `(0, 1)`) per ranked candidate.
    pub fn new(decay: f64) -> Self {
        Self {
            decay,
            target: 1.0,
            best: f64::NEG_INFINITY,
            ranked: 0,
        }
    }

    /// Ranks one valid candidate with predicted fitness `predicted`.
    ///
    /// Predictions are taken in `[0, 1]` (NaN as 0, so a diverged analyzer cannot stall the
    /// search), so a test is always accepted once the target falls below 1e-4.
    pub fn rank(&mut self, predicted: f64) -> Ranked {
        let p = if predicted.is_nan() {
            0.0
        } else {
            predicted.clamp(0.0, 1.0)
        };
        self.ranked += 1;
        let best = p > self.best;
        if best {
            self.best = p;
        }
        self.target *= self.decay;
        Ranked {
            best,
            accept: self.best + ACCEPT_EPS >= self.target,
        }
    }

    /// Starts the next choice of a round in which several tests are chosen at once: the best
    /// and the count start afresh; the target starts afresh too, or, with
    /// [`RoundAcceptance::Continue`], goes on from where the last choice left it.
    pub fn next_choice(&mut self, rule: RoundAcceptance) {
        self.best = f64::NEG_INFINITY;
        self.ranked = 0;
        if rule == RoundAcceptance::Restart {
            self.target = 1.0;
        }
    }

    /// Valid candidates ranked so far.
    pub fn ranked(&self) -> usize {
        self.ranked
    }

    /// The best prediction ranked so far (−∞ before the first).
    pub fn best(&self) -> f64 {
        self.best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_once_the_target_reaches_the_best_prediction() {
        let mut a = Acceptance::new(0.5);
        // Targets 0.5, 0.25, 0.125: 0.2 is accepted at the third candidate.
        assert_eq!(
            a.rank(0.1),
            Ranked {
                best: true,
                accept: false
            }
        );
        assert_eq!(
            a.rank(0.2),
            Ranked {
                best: true,
                accept: false
            }
        );
        assert_eq!(
            a.rank(0.15),
            Ranked {
                best: false,
                accept: true
            }
        );
        assert_eq!((a.ranked(), a.best()), (3, 0.2));
    }

    #[test]
    fn a_round_continues_or_restarts_the_target() {
        // Targets 0.5, 0.25: 0.3 is accepted at the second candidate.
        let mut a = Acceptance::new(0.5);
        assert!(!a.rank(0.3).accept);
        assert!(a.rank(0.2).accept);
        let mut restarted = a.clone();
        // Continued, the target goes on to 0.125: 0.2 is accepted at once.
        a.next_choice(RoundAcceptance::Continue);
        assert!(a.rank(0.2).accept);
        assert_eq!((a.ranked(), a.best()), (1, 0.2));
        // Restarted, the targets are 0.5, 0.25, 0.125 again: 0.2 is accepted at the third.
        restarted.next_choice(RoundAcceptance::Restart);
        assert!(!restarted.rank(0.2).accept);
        assert!(!restarted.rank(0.1).accept);
        assert!(restarted.rank(0.1).accept);
        assert_eq!((restarted.ranked(), restarted.best()), (3, 0.2));
    }

    #[test]
    fn a_hopeless_or_diverged_analyzer_still_ends() {
        for p in [0.0, f64::NAN, -3.0] {
            let mut a = Acceptance::new(0.95);
            let rounds = (1..).find(|_| a.rank(p).accept).unwrap();
            // 0.95^k <= 1e-4 first at k = 180.
            assert_eq!(rounds, 180, "prediction {p}");
        }
    }
}
