//! Small helpers shared by the networks: seeded initialisation and tensor conversion.
//!
//! Weights are drawn from the run's own RNG (PyTorch's default `U(-1/√fan_in, 1/√fan_in)`), not
//! from burn's device RNG, so a run is reproducible from its seed whatever else uses the device.

use burn::module::Param;
use burn::nn::Linear;
use burn::prelude::*;
use rand::{Rng, RngExt};

use crate::error::Error;

/// A dense layer `x W + b` with `W: [d_in, d_out]` initialised from `rng`.
pub(crate) fn linear<R: Rng + ?Sized>(
    rng: &mut R,
    d_in: usize,
    d_out: usize,
    device: &Device,
) -> Linear {
    let k = 1.0 / (d_in as f32).sqrt();
    let w: Vec<f32> = (0..d_in * d_out)
        .map(|_| rng.random_range(-k..=k))
        .collect();
    let b: Vec<f32> = (0..d_out).map(|_| rng.random_range(-k..=k)).collect();
    Linear {
        weight: Param::from_data(TensorData::new(w, [d_in, d_out]), device),
        bias: Some(Param::from_data(TensorData::new(b, [d_out]), device)),
    }
}

/// The three dense layers `d → hidden → hidden → 1` of the critic and the analyzer, initialised
/// from `rng` in that order.
pub(crate) fn three_layers<R: Rng + ?Sized>(
    rng: &mut R,
    dim: usize,
    hidden: usize,
    device: &Device,
) -> [Linear; 3] {
    [
        linear(rng, dim, hidden, device),
        linear(rng, hidden, hidden, device),
        linear(rng, hidden, 1, device),
    ]
}

/// A `[rows, cols]` tensor from row-major values.
pub(crate) fn matrix(values: Vec<f32>, rows: usize, cols: usize, device: &Device) -> Tensor<2> {
    Tensor::from_data(TensorData::new(values, [rows, cols]), device)
}

/// Uniform noise in `[-1, 1]` from the run's RNG.
pub(crate) fn uniform_noise<R: Rng + ?Sized>(
    rng: &mut R,
    rows: usize,
    cols: usize,
    device: &Device,
) -> Tensor<2> {
    let v: Vec<f32> = (0..rows * cols)
        .map(|_| rng.random_range(-1.0f32..=1.0))
        .collect();
    matrix(v, rows, cols, device)
}

/// Reads a tensor back as `f32` values.
pub(crate) fn values<const D: usize>(t: Tensor<D>) -> Result<Vec<f32>, Error> {
    t.into_data()
        .try_into_vec_as::<f32>()
        .map_err(|e| Error::Tensor(format!("{e:?}")))
}

/// Reads a one-element tensor back as a scalar.
pub(crate) fn scalar(t: Tensor<1>) -> Result<f64, Error> {
    values(t)?
        .first()
        .map(|v| f64::from(*v))
        .ok_or_else(|| Error::Tensor("empty scalar".into()))
}

/// Leaky-ReLU slopes (1 or `slope`) at pre-activations, as a constant (detached) tensor.
pub(crate) fn slopes<const D: usize>(pre: Tensor<D>, slope: f64) -> Tensor<D> {
    pre.detach()
        .greater_elem(0.0)
        .float()
        .mul_scalar(1.0 - slope)
        .add_scalar(slope)
}
