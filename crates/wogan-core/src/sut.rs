//! The system under test as wogan-core sees it: a dimension, a validity predicate and an
//! execution that yields a fitness plus whatever the SUT wants to report.

/// What one execution of a test produced.
#[derive(Debug, Clone, PartialEq)]
pub struct Execution<O> {
    /// Fitness in `[0, 1]`, higher = closer to failure. Values outside are clamped (NaN counts as 0).
    pub fitness: f64,
    /// Time the execution charges to an execution budget, seconds: simulated seconds for a
    /// simulator (the SBST competition's accounting), 0 for a SUT without such a clock.
    pub execution_time_s: f64,
    /// SUT-specific report, passed through to the caller untouched.
    pub output: O,
}

/// A black-box system under test over normalised test vectors in `[-1, 1]^dim`.
///
/// `Sync` because the random phase may execute several tests at once (`jobs > 1`).
pub trait Sut: Sync {
    /// What an execution reports besides the fitness.
    type Output: Send;
    /// Length of a test vector.
    fn dim(&self) -> usize;
    /// Whether a test may be executed; invalid tests are never executed.
    fn is_valid(&self, test: &[f32]) -> bool;
    /// Executes a valid test; `None` when the execution was cut short because the run is being
    /// stopped (the run's `stop` flag, which the SUT may watch), so that no half-done result is
    /// reported as a test.
    fn execute(&self, test: &[f32]) -> Option<Execution<Self::Output>>;
    /// What a valid test does, as values that compare tests by effect rather than by their own
    /// values (for a road: its heading profile, radians), of one length for every test; `None`,
    /// the default, when the SUT has no such description. Only the shape novelty rule and the
    /// niches use it (`WoganConfig::shape_novelty`, `WoganConfig::niches`).
    fn shape(&self, _test: &[f32]) -> Option<Vec<f32>> {
        None
    }
    /// How a failing execution failed, as values of one length that compare failures where
    /// they happened (for a road: its exit profile, radians, around where the car left its
    /// lane); `None`, the default, when the SUT has no such description. Only niches closed when
    /// they stop yielding new failures use it (`NicheConfig::stale`).
    fn failure_profile(&self, _output: &Self::Output) -> Option<Vec<f32>> {
        None
    }
}

/// Clamps a reported fitness into `[0, 1]`; NaN becomes 0 so it can never look like a failure.
pub(crate) fn clamp_fitness(f: f64) -> f64 {
    if f.is_nan() {
        0.0
    } else {
        f.clamp(0.0, 1.0)
    }
}
