//! Remakes of failing tests: Frenetic's four operators applied to every failure once, each way.
//!
//! Frenetic (SBST 2021) remakes each road that failed by a clear margin four ways that keep its
//! bends and change where and how the car meets them; each remake is a likely failure of another
//! kind (docs/experiments/2026-11-28-frenetic-2021-whole-budget.md measured the four together
//! adding about 11 distinct failures a run to its random roads'). The mutants of
//! [`crate::MutationConfig`] apply the same reshapes to a random few of the best tests, ranked by
//! the analyzer; here every failure's remakes are queued and executed in turn, before the
//! networks propose again, without the analyzer's say (it has seen none of them).
//!
//! A test is a sequence of values along a road (curvatures, headings' changes), so the four ways
//! are operations on the sequence: negated (the mirror image), reversed (the bends met in the
//! other order), reversed and negated (the same road driven the other way), and rotated by half
//! (its halves swapped).

use std::collections::VecDeque;

/// The four remakes of `test`, in the order they are executed.
pub(crate) fn remakes_of(test: &[f32]) -> [Vec<f32>; 4] {
    let mirrored: Vec<f32> = test.iter().map(|v| -v).collect();
    let reversed: Vec<f32> = test.iter().rev().copied().collect();
    let backwards: Vec<f32> = reversed.iter().map(|v| -v).collect();
    let mut swapped = test.to_vec();
    swapped.rotate_left(test.len() / 2);
    [mirrored, reversed, backwards, swapped]
}

/// The remakes waiting to be executed, oldest failure's first.
#[derive(Debug, Default)]
pub(crate) struct RemakeQueue {
    pending: VecDeque<Vec<f32>>,
}

impl RemakeQueue {
    /// Queues the remakes of the failing `test`, skipping any equal to `test` itself or to one
    /// already waiting (a symmetric road's mirror may be the road reversed, say).
    pub(crate) fn queue_remakes_of(&mut self, test: &[f32]) {
        for remake in remakes_of(test) {
            if remake != test && !self.pending.contains(&remake) {
                self.pending.push_back(remake);
            }
        }
    }

    /// The next remake waiting, if any.
    pub(crate) fn pop(&mut self) -> Option<Vec<f32>> {
        self.pending.pop_front()
    }

    /// How many remakes are waiting.
    #[cfg(test)]
    fn len(&self) -> usize {
        self.pending.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_four_ways_keep_the_values_and_move_or_mirror_them() {
        let [mirrored, reversed, backwards, swapped] = remakes_of(&[0.1, 0.2, -0.3, 0.4]);
        assert_eq!(mirrored, [-0.1, -0.2, 0.3, -0.4]);
        assert_eq!(reversed, [0.4, -0.3, 0.2, 0.1]);
        assert_eq!(backwards, [-0.4, 0.3, -0.2, -0.1]);
        assert_eq!(swapped, [-0.3, 0.4, 0.1, 0.2]);
    }

    #[test]
    fn the_queue_skips_remakes_equal_to_the_test_or_to_one_waiting() {
        let mut queue = RemakeQueue::default();
        // A palindrome: reversed is itself, backwards is its mirror.
        queue.queue_remakes_of(&[0.5, 0.0, 0.5]);
        assert_eq!(queue.len(), 2);
        assert_eq!(queue.pop(), Some(vec![-0.5, -0.0, -0.5]));
        assert_eq!(queue.pop(), Some(vec![0.0, 0.5, 0.5]));
        assert_eq!(queue.pop(), None);
        // Two values: swapping the halves is reversing them.
        queue.queue_remakes_of(&[0.1, 0.2]);
        queue.queue_remakes_of(&[0.1, 0.2]);
        assert_eq!(queue.len(), 3);
    }
}
