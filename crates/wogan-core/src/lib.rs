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
//! The networks run on burn's Flex CPU backend with autodiff. Every random choice, including
//! weight initialisation and GAN noise, flows from one ChaCha RNG seeded by the run seed, so a run
//! with `max_tests` and `jobs = 1` is reproducible from its seed.
//!
//! Scaling choice: each analyzer epoch is one Adam step on all tests while there are at most
//! [`AnalyzerConfig::max_batch`] (512) of them, and on that many tests sampled without
//! replacement once there are more, so a training round costs about the same at 300 and at
//! 100,000 tests.

mod analyzer;
mod bins;
mod budget;
mod config;
mod critic;
mod error;
mod generator;
mod nn;
mod random;
mod run;
mod sampler;
mod sut;
mod wgan;
mod wogan;

pub use bins::{bin_of, bin_weights, biased_batch};
pub use budget::Budget;
pub use config::{
    Algorithm, AnalyzerConfig, GeneratorConfig, CriticConfig, RunConfig, SamplerConfig, WganConfig,
    WoganConfig,
};
pub use error::Error;
pub use run::{run, Event, Phase, Summary};
pub use sampler::Sampler;
pub use sut::{Execution, Sut};
pub use wogan::{Proposal, TrainStats, WoganModel};
