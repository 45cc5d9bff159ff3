//! Random tests executed in order, several at once when `jobs > 1`.
//!
//! Tests are independent here, so they are sampled one after another from the run's RNG (the
//! same sequence whatever `jobs` is), executed in parallel on a rayon pool, and reported in id
//! order: a run with `jobs = N` yields the same tests and results as with `jobs = 1`.

use std::time::Instant;

use rayon::prelude::*;
use rayon::ThreadPool;

use crate::error::Error;
use crate::sampler::Sampler;
use crate::sut::{Execution, Sut};

/// One sampled test waiting for execution.
pub(crate) struct Sampled {
    pub test: Vec<f32>,
    pub invalid: usize,
    pub generation_s: f64,
}

/// Samples `count` valid tests in order.
pub(crate) fn sample_tests<S: Sut + ?Sized, R: rand::Rng + ?Sized>(
    sut: &S,
    sampler: &Sampler,
    rng: &mut R,
    count: usize,
) -> Result<Vec<Sampled>, Error> {
    (0..count)
        .map(|_| {
            let t0 = Instant::now();
            let mut invalid = 0;
            let test = sampler.sample_valid(sut, rng, &mut invalid)?;
            Ok(Sampled {
                test,
                invalid,
                generation_s: t0.elapsed().as_secs_f64(),
            })
        })
        .collect()
}

/// Executes tests, in parallel when a pool is given; results are in input order.
pub(crate) fn execute_all<S: Sut + ?Sized>(
    sut: &S,
    tests: &[Sampled],
    pool: Option<&ThreadPool>,
) -> Vec<Option<Execution<S::Output>>> {
    match pool {
        Some(pool) if tests.len() > 1 => {
            pool.install(|| tests.par_iter().map(|s| sut.execute(&s.test)).collect())
        }
        _ => tests.iter().map(|s| sut.execute(&s.test)).collect(),
    }
}
