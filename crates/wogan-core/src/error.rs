//! Errors a run can end with.

/// Why a run could not start or continue.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A configuration value is out of range.
    #[error("invalid configuration: {0}")]
    Config(String),
    /// The random sampler found no valid test within its attempt limit.
    #[error("no valid test found in {attempts} random samples")]
    NoValidTest {
        /// How many samples were tried.
        attempts: usize,
    },
    /// A search for a valid test was given up because the run is being stopped (a signal or an
    /// expired budget); the run ends normally.
    #[error("stopped while searching for a valid test")]
    Interrupted,
    /// The worker thread pool for `jobs > 1` could not be built.
    #[error("could not start {jobs} worker threads: {message}")]
    ThreadPool {
        /// Requested number of workers.
        jobs: usize,
        /// The pool builder's message.
        message: String,
    },
    /// Training produced a non-finite loss (a learning rate too large for the data, say).
    #[error("training diverged (a non-finite loss) after {tests} tests; lower the learning rates")]
    Diverged {
        /// Tests the diverging round learnt from.
        tests: usize,
    },
    /// A model snapshot does not fit WOGAN's networks (a tensor missing, of another shape, or not
    /// numbers), or there is nothing trained to snapshot yet.
    #[error("model snapshot: {0}")]
    Snapshot(String),
}
