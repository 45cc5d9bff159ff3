//! WOGAN's test choice: the learning state ([`WoganModel`]), the fitness bins that bias its GAN
//! batches, the acceptance rule that picks a candidate, the optional mutants, novelty rule,
//! niches and failures' remakes, and the snapshot of its trained networks that proposes later without training.

mod acceptance;
mod bins;
mod model;
mod mutation;
mod niches;
mod novelty;
mod remakes;
mod snapshot;
mod training_round;

#[cfg(test)]
pub(crate) use acceptance::Acceptance;
pub use bins::{biased_batch, bin_of, bin_weights, BatchDraws, RngDraws};
pub use model::{Origin, Proposal, TrainStats, WoganModel};
#[cfg(test)]
pub(crate) use remakes::remakes_of;
pub use snapshot::{ModelSnapshot, NamedTensor};
