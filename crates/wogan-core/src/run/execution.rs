//! Executing a group of tests at once: on a rayon pool when the run has one, in order otherwise;
//! results always come back in the tests' order, so a run's records do not depend on `jobs`
//! beyond how its tests were grouped.

use rayon::prelude::*;
use rayon::ThreadPool;

use crate::config::RunConfig;
use crate::error::Error;
use crate::sut::{Execution, Sut};

/// The pool a run with `jobs` > 1 executes its groups of tests on (`None` for one job).
pub(super) fn worker_pool(config: &RunConfig) -> Result<Option<ThreadPool>, Error> {
    if config.jobs <= 1 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(config.jobs)
        .build()
        .map(Some)
        .map_err(|e| Error::ThreadPool {
            jobs: config.jobs,
            message: e.to_string(),
        })
}

/// Executes `tests`, in parallel when a pool is given; results are in input order (`None` where
/// a stop cut a drive short).
pub(super) fn execute_all<S: Sut + ?Sized>(
    sut: &S,
    tests: &[&[f32]],
    pool: Option<&ThreadPool>,
) -> Vec<Option<Execution<S::Output>>> {
    match pool {
        Some(pool) if tests.len() > 1 => {
            pool.install(|| tests.par_iter().map(|t| sut.execute(t)).collect())
        }
        _ => tests.iter().map(|t| sut.execute(t)).collect(),
    }
}
