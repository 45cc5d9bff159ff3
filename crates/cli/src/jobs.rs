//! The one `--jobs` loop of the commands that answer roads one by one (`validate`, `simulate`,
//! `replay`): items are answered up to N at a time on a thread pool of N threads, and each answer
//! is handed on in the items' order as soon as its batch is done, so output order never depends
//! on N. (A search runs its own tests in parallel inside wogan-core.)

use anyhow::Result;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// What the source of items has next.
pub enum Next<T> {
    /// These items, at most as many as were asked for.
    Items(Vec<T>),
    /// Nothing yet (input not arrived): look at the stop flag and ask again.
    Waiting,
    /// No more items.
    End,
}

/// How [`Jobs::answer_in_order`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ended {
    /// Every item was answered.
    AllAnswered,
    /// The stop flag was set: the answers finished before it were handed on.
    Stopped,
}

/// `--jobs N`: N items answered at once, on a pool of N threads (none for one job).
pub struct Jobs {
    count: usize,
    pool: Option<rayon::ThreadPool>,
}

impl Jobs {
    /// `count` jobs at once (0 counts as 1).
    pub fn new(count: usize) -> Result<Self> {
        let count = count.max(1);
        let pool = if count == 1 {
            None
        } else {
            Some(rayon::ThreadPoolBuilder::new().num_threads(count).build()?)
        };
        Ok(Self { count, pool })
    }

    /// How many items are answered at once.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Answers the items `next` gives (asked for at most N at a time) with `answer`, N at once,
    /// and hands each item with its answer to `write` in the items' order. Before each batch it
    /// looks at `stop`, and ends with [`Ended::Stopped`] once it is set.
    pub fn answer_in_order<T, A>(
        &self,
        stop: &AtomicBool,
        mut next: impl FnMut(usize) -> Result<Next<T>>,
        answer: impl Fn(&T) -> A + Sync,
        mut write: impl FnMut(&T, A) -> Result<()>,
    ) -> Result<Ended>
    where
        T: Sync,
        A: Send,
    {
        loop {
            if stop.load(Ordering::SeqCst) {
                return Ok(Ended::Stopped);
            }
            let batch = match next(self.count)? {
                Next::Items(items) => items,
                Next::Waiting => continue,
                Next::End => break,
            };
            let answers: Vec<A> = match &self.pool {
                Some(pool) => pool.install(|| batch.par_iter().map(&answer).collect()),
                None => batch.iter().map(&answer).collect(),
            };
            for (item, answer) in batch.iter().zip(answers) {
                write(item, answer)?;
            }
        }
        Ok(if stop.load(Ordering::SeqCst) {
            Ended::Stopped
        } else {
            Ended::AllAnswered
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::AtomicUsize;

    /// Items from `0..n`, `asked` at a time.
    fn counting(n: usize) -> impl FnMut(usize) -> Result<Next<usize>> {
        let mut at = 0;
        move |asked| {
            if at == n {
                return Ok(Next::End);
            }
            let end = (at + asked).min(n);
            let items = (at..end).collect();
            at = end;
            Ok(Next::Items(items))
        }
    }

    #[test]
    fn answers_come_in_item_order_whatever_the_jobs() {
        for jobs in [1, 2, 5] {
            let mut seen = Vec::new();
            let ended = Jobs::new(jobs)
                .unwrap()
                .answer_in_order(
                    &AtomicBool::new(false),
                    counting(23),
                    |&item| item * 10,
                    |&item, answer| {
                        seen.push((item, answer));
                        Ok(())
                    },
                )
                .unwrap();
            assert_eq!(ended, Ended::AllAnswered);
            let expected: Vec<_> = (0..23).map(|i| (i, i * 10)).collect();
            assert_eq!(seen, expected, "jobs {jobs}");
        }
    }

    #[test]
    fn batches_hold_at_most_the_jobs_and_waiting_is_asked_again() {
        let largest = AtomicUsize::new(0);
        let mut calls = 0;
        let mut items = counting(7);
        let next = |asked: usize| {
            calls += 1;
            // Every other call finds nothing yet.
            if calls % 2 == 1 {
                return Ok(Next::Waiting);
            }
            let got = items(asked)?;
            if let Next::Items(batch) = &got {
                largest.fetch_max(batch.len(), Ordering::SeqCst);
            }
            Ok(got)
        };
        let mut written = 0;
        Jobs::new(3)
            .unwrap()
            .answer_in_order(
                &AtomicBool::new(false),
                next,
                |_| (),
                |_, ()| {
                    written += 1;
                    Ok(())
                },
            )
            .unwrap();
        assert_eq!(written, 7);
        assert_eq!(largest.load(Ordering::SeqCst), 3);
    }

    #[test]
    fn a_stop_ends_before_the_next_batch_with_what_was_answered() {
        let stop = AtomicBool::new(false);
        let mut seen = Vec::new();
        let ended = Jobs::new(2)
            .unwrap()
            .answer_in_order(
                &stop,
                counting(10),
                |&item| item,
                |&item, _| {
                    seen.push(item);
                    if item == 3 {
                        stop.store(true, Ordering::SeqCst);
                    }
                    Ok(())
                },
            )
            .unwrap();
        assert_eq!(ended, Ended::Stopped);
        assert_eq!(seen, vec![0, 1, 2, 3]);
    }
}
