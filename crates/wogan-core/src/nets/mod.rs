//! WOGAN's networks in burn: the generator, the critic with its exact gradient penalty, the
//! analyzer, stgem's batch normalisation, and the WGAN-GP training of generator against critic.

mod analyzer;
mod batch_norm;
mod critic;
mod generator;
mod layers;
mod wgan;

pub(crate) use analyzer::{logit_target, Analyzer, AnalyzerTrainer};
pub(crate) use batch_norm::BatchNorm;
#[cfg(test)]
pub(crate) use critic::Critic;
pub(crate) use generator::Generator;
pub(crate) use layers::{matrix, uniform_noise, values};
pub(crate) use wgan::Wgan;
