//! WOGAN's networks on plain `f32` matrices, each with its forward and backward pass written
//! out: the generator, the critic with its exact gradient penalty, the analyzer, stgem's batch
//! normalisation, Adam, and the WGAN-GP training of generator against critic.

mod adam;
mod analyzer;
mod batch_norm;
mod critic;
mod dense;
mod generator;
mod matmul;
mod matrix;
mod wgan;

pub(crate) use analyzer::{logit_target, Analyzer, AnalyzerTrainer};
pub(crate) use batch_norm::BatchNorm;
#[cfg(test)]
pub(crate) use critic::Critic;
pub(crate) use dense::Dense;
pub(crate) use generator::{uniform_noise, Generator};
pub(crate) use matrix::Matrix;
pub(crate) use wgan::Wgan;
