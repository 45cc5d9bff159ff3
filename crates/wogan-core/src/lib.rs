//! Generic online test generation: random search and WOGAN.
//!
//! `wogan-core` knows nothing of roads or physics. It sees test vectors in `[-1, 1]^d`, a validity
//! predicate and a fitness in `[0, 1]` (higher = closer to failure), all supplied by a [`Sut`].
//! [`run`] drives one search under a [`Budget`] and streams an [`Event`] per executed test and per
//! training round, then returns a [`Summary`].
//!
//! WOGAN (Peltomäki, Spencer & Porres, SBST 2022) trains, every few tests, an *analyzer* that
//! predicts fitness and a Wasserstein GAN with gradient penalty on a batch biased towards high
//! fitness; the generator proposes candidates, the analyzer picks the most promising valid one.
//!
//! The networks run on plain `f32` matrices, their forward and backward passes written out
//! (`nets/`): they are so small that a tensor library's per-operation cost would dominate.
//! Every random choice, including weight initialisation and GAN noise, flows from one ChaCha RNG
//! seeded by the run seed, so a run with `max_tests` and `jobs = 1` is reproducible from its seed.
//!
//! ```
//! use std::sync::atomic::AtomicBool;
//! use wogan_core::{run, Algorithm, Budget, Event, Execution, RunConfig, Sut};
//!
//! struct Half;
//! impl Sut for Half {
//!     type Output = ();
//!     fn dim(&self) -> usize { 3 }
//!     fn is_valid(&self, t: &[f32]) -> bool { t[0] <= 0.5 }
//!     fn execute(&self, t: &[f32]) -> Option<Execution<()>> {
//!         Some(Execution { fitness: f64::from((t[1] + 1.0) / 2.0), execution_time_s: 0.0, output: () })
//!     }
//! }
//!
//! let config = RunConfig { algorithm: Algorithm::Random, ..RunConfig::default() };
//! let budget = Budget { max_tests: Some(5), ..Budget::default() };
//! let stop = AtomicBool::new(false);
//! let mut lines = Vec::new();
//! let summary = run(&Half, &config, budget, 42, &stop, &mut |e: Event<()>| {
//!     lines.push(serde_json::to_string(&e).unwrap());
//! })?;
//! assert_eq!(summary.executed, 5);
//! assert_eq!(lines.len(), 5);
//! # Ok::<(), wogan_core::Error>(())
//! ```
//!
//! # Faithful to the authors' code
//!
//! stgem (the authors' PyTorch implementation, SBST 2022 set-up in `problems/sbst/sbst.py`) is the
//! specification; `tests/reference/wogan/` holds vectors made by its own classes and the tests
//! in `stgem_parity.rs` replay them. What that pins down, where the paper's prose is silent or
//! reads otherwise:
//!
//! - The generator is `Linear → ReLU → Linear → BatchNorm → ReLU → Linear → BatchNorm → tanh`:
//!   the first hidden layer is not normalised and the output is, before tanh. The running
//!   variance takes the unbiased batch variance (PyTorch's), and every critic step's fakes move
//!   the running statistics, which is what candidates are drawn with.
//! - The critic's leaky ReLU has PyTorch's default slope, 0.01.
//! - The analyzer's loss compares `logit(0.98·p + 0.01)` of its sigmoid *output* `p` with that
//!   of the fitness; the L2 term covers weights and biases (applied as Adam's coupled weight
//!   decay `2·l2`, exactly the gradient of `l2·‖θ‖²`). Adam's epsilon is 1e-8 everywhere.
//! - Fitness bins are stgem's bins of `1 − fitness`, edges included. From the second round on,
//!   each of the 3 newest tests joins a WGAN batch when its bin is at most a drawn bin (stgem's
//!   code, which its comment contradicts), and may be drawn again by the rest of the batch.
//! - The acceptance rule: one valid candidate per round and per 0.95 decay of the target,
//!   accepted within 1e-4 (`wogan/acceptance.rs`).
//!
//! # Choices where the reference leaves room
//!
//! - Scaling: each analyzer epoch is one Adam step on all tests while there are at most
//!   [`AnalyzerConfig::max_batch`] (512) of them, and on that many tests sampled without
//!   replacement once there are more, so a training round costs about the same at 300 and at
//!   100,000 tests (`benches/iteration.rs`). stgem always trains on all tests.
//! - Critic steps use as many fake tests as the real batch has (at least 2, for batch
//!   normalisation); the generator step uses `noise_batch` noise vectors.
//! - The gradient penalty is exact: see *The critic* below.
//! - Candidates are computed 32 at a time in inference mode (stgem computes one at a time; in
//!   inference mode each is an independent draw either way).
//! - The reported Wasserstein estimate is the last critic step's `mean C(real) − mean C(fake)`.
//! - After `max_invalid_streak` (100) invalid candidates in a row, a random valid test is
//!   executed and reported with `predicted_fitness: None` (phase `wogan`). stgem means to give
//!   up after 100 invalid candidates in one choice and retrain, but raises an exception it never
//!   imported, which ends the run.
//! - Fitness values outside `[0, 1]` are clamped, NaN becomes 0.
//! - With `jobs > 1` WOGAN chooses rounds of up to `jobs` tests, executes them at once and
//!   trains on the schedule of tests executed ([`RoundAcceptance`]); `jobs = 1` is the paper's
//!   loop.
//!
//! # Beyond the paper: mutants among the candidates
//!
//! With [`MutationConfig::share`] above 0 (`wogan run --mutation-share`), that share of each
//! candidate batch are mutants of the highest-fitness tests so far that lie apart from one another
//! ([`MutationConfig`]); the analyzer ranks them with the generator's candidates and the test
//! line's `phase` says `"mutant"` when one is executed. The default, 0, is the paper's WOGAN. The
//! authors proposed mutating failing tests for diversity.
//!
//! # Beyond the paper: novelty
//!
//! With [`NoveltyConfig::distance`] above 0, a candidate is ranked only when it lies at least that
//! far (root mean square over the values, normalised units) from every test executed so far, or
//! from every one of at least [`NoveltyConfig::min_fitness`]; with
//! [`NoveltyConfig::allowed_neighbours`] above 0, only when more than that many lie nearer (a
//! neighbourhood holds that many before the search must leave it). Skipped candidates count
//! towards the invalid streak, not as invalid. WOGAN otherwise spends much of a budget re-finding
//! its first failures; the default, 0, is the paper's WOGAN.
//!
//! [`WoganConfig::shape_novelty`] is the same rule over what a test does rather than its values:
//! a candidate is compared by [`Sut::shape`] (for a road, its heading profile) with the shapes of
//! the executed tests. Off by default, and for a SUT without shapes.
//!
//! # Beyond the paper: niches
//!
//! With [`NicheConfig::quota`] above 0, failures fill niches one after another. A niche is a ball
//! of [`NicheConfig::radius`] around a seed failure's shape ([`Sut::shape`]); while it is open only
//! candidates inside it are ranked and only its failures are mutation parents. Once it holds
//! `quota` failures (or, with [`NicheConfig::stale`], once that many of its failures in a row
//! repeat earlier ones by [`Sut::failure_profile`]) it closes, and only candidates at least
//! [`NicheConfig::distance`] from every seed are ranked until a failure there seeds the next niche
//! (or, after [`NicheConfig::patience`] tests, the failure met farthest from the seeds); those
//! candidates come from the generator and mutants, or ([`BetweenNiches::Random`]) are random tests
//! ranked by the analyzer. A run ends with a few regions of failures about equal in size, far apart
//! by shape. Off by default, and for a SUT without shapes.
//!
//! # Beyond the paper: remakes of failures
//!
//! With [`RemakeConfig::enabled`], every failing test (of at least [`RemakeConfig::min_fitness`]),
//! unless itself a remake, is remade Frenetic's four ways: mirrored, its values reversed, driven
//! backwards (reversed and mirrored), its halves swapped. Each remake that is valid, not executed
//! before and novel by the novelty rules (the niches do not hold it back) is executed once, before
//! the networks choose again; its test line's `phase` is `"remake"` and it has no
//! `predicted_fitness`. Off by default.
//!
//! # The critic
//!
//! The gradient penalty needs the critic's gradient with respect to its input; it is written
//! out as an expression of the critic's weights and its leaky-ReLU slopes (constant between
//! kinks), and differentiating that by hand gives the exact parameter gradients of the WGAN-GP
//! loss (checked against f64 finite differences in a test).

mod budget;
mod config;
pub mod diversity;
mod error;
mod nets;
mod run;
mod sut;
mod test_sampler;
mod wogan;

#[cfg(test)]
mod stgem_parity;

pub use budget::{Budget, SbstBudget, SbstUsage};
pub use config::{
    limits, Algorithm, AnalyzerConfig, BetweenNiches, CriticConfig, GeneratorConfig,
    MutationConfig, NicheConfig, NoveltyConfig, RemakeConfig, RoundAcceptance, RunConfig,
    SamplerConfig, WganConfig, WoganConfig,
};
pub use error::Error;
pub use run::{run, run_from_snapshot, run_with_snapshot, Event, Phase, Summary};
pub use sut::{Execution, Sut};
pub use test_sampler::Sampler;
pub use wogan::{
    biased_batch, bin_of, bin_weights, BatchDraws, ModelSnapshot, NamedTensor, Origin, Proposal,
    RngDraws, TrainStats, WoganModel,
};
