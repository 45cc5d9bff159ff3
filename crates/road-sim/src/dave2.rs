//! DAVE-2 (Bojarski et al., NVIDIA 2016), the SBST competition's second system under test: a CNN
//! that steers from one front-camera frame.
//!
//! Input: a 66 x 200 grayscale frame (one channel instead of the paper's three YUV planes; see
//! [`crate::camera`]), normalised in the network to `x / 127.5 − 1`. Layers: convolutions 24 5x5
//! stride 2, 36 5x5 s2, 48 5x5 s2, 64 3x3, 64 3x3 (no padding), dense 100, 50, 10, 1, ReLU after
//! every layer but the last. The output is the steering in `[-1, 1]` of the car's maximum wheel
//! angle (the network's output is linear; drivers clamp it).
//!
//! Weights live in [`Dave2Weights`] (plain `f32` vectors in burn's layouts), which initialises
//! from a seed, converts to and from the burn model [`Dave2`] and saves as a compact byte blob
//! (about 1 MB). [`Dave2Trainer`] makes Adam steps on the mean squared error.

use burn::module::Param;
use burn::nn::conv::Conv2d;
use burn::nn::{Linear, PaddingConfig2d};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use burn::tensor::activation::relu;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;

use crate::camera::{FRAME_HEIGHT, FRAME_WIDTH};

/// The convolutions: `(channels in, channels out, kernel size, stride)`.
pub const CONVS: [(usize, usize, usize, usize); 5] = [
    (1, 24, 5, 2),
    (24, 36, 5, 2),
    (36, 48, 5, 2),
    (48, 64, 3, 1),
    (64, 64, 3, 1),
];
/// The dense layers: `(inputs, outputs)`; the first takes the flattened `64 x 1 x 18` features.
pub const DENSES: [(usize, usize); 4] = [(1152, 100), (100, 50), (50, 10), (10, 1)];

/// Pixels per input frame.
pub const FRAME_PIXELS: usize = FRAME_HEIGHT * FRAME_WIDTH;

const MAGIC: &[u8; 4] = b"DAV2";
const FORMAT_VERSION: u32 = 1;

/// A convolution's weights: `weight` is `[c_out][c_in][k][k]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ConvWeights {
    /// `[c_out][c_in][k][k]`, row-major.
    pub weight: Vec<f32>,
    /// `[c_out]`.
    pub bias: Vec<f32>,
}

/// A dense layer's weights: `y = x W + b`, `weight` is `[d_in][d_out]`.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseWeights {
    /// `[d_in][d_out]`, row-major.
    pub weight: Vec<f32>,
    /// `[d_out]`.
    pub bias: Vec<f32>,
}

/// All of DAVE-2's weights, shaped as [`CONVS`] and [`DENSES`] say.
#[derive(Debug, Clone, PartialEq)]
pub struct Dave2Weights {
    /// The five convolutions.
    pub convs: Vec<ConvWeights>,
    /// The four dense layers.
    pub denses: Vec<DenseWeights>,
}

/// Why a weight blob could not be read.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum WeightsError {
    /// Not a DAVE-2 weight blob.
    #[error("not a DAVE-2 weight blob (bad magic or version)")]
    BadHeader,
    /// The blob holds the wrong number of values.
    #[error("a DAVE-2 weight blob of {got} bytes, expected {expected}")]
    BadLength {
        /// Bytes expected.
        expected: usize,
        /// Bytes found.
        got: usize,
    },
}

impl Dave2Weights {
    /// Weights drawn from a ChaCha20 RNG seeded with `seed`: PyTorch's default
    /// `U(-1/√fan_in, 1/√fan_in)` for weights and biases.
    pub fn from_seed(seed: u64) -> Self {
        let mut rng = ChaCha20Rng::seed_from_u64(seed);
        let mut draw = |n: usize, fan_in: usize| -> Vec<f32> {
            let k = 1.0 / (fan_in as f32).sqrt();
            (0..n).map(|_| rng.random_range(-k..=k)).collect()
        };
        let convs = CONVS
            .iter()
            .map(|&(ci, co, k, _)| ConvWeights {
                weight: draw(co * ci * k * k, ci * k * k),
                bias: draw(co, ci * k * k),
            })
            .collect();
        let denses = DENSES
            .iter()
            .map(|&(di, dout)| DenseWeights {
                weight: draw(di * dout, di),
                bias: draw(dout, di),
            })
            .collect();
        Self { convs, denses }
    }

    /// Number of `f32` values.
    pub fn len() -> usize {
        CONVS
            .iter()
            .map(|&(ci, co, k, _)| co * ci * k * k + co)
            .sum::<usize>()
            + DENSES.iter().map(|&(i, o)| i * o + o).sum::<usize>()
    }

    fn slices(&self) -> impl Iterator<Item = &Vec<f32>> {
        self.convs
            .iter()
            .flat_map(|c| [&c.weight, &c.bias])
            .chain(self.denses.iter().flat_map(|d| [&d.weight, &d.bias]))
    }

    /// The blob: `b"DAV2"`, format version (u32 LE), number of values (u32 LE), then every
    /// value as f32 LE, layer by layer, weight before bias.
    pub fn to_bytes(&self) -> Vec<u8> {
        let n = Self::len();
        let mut out = Vec::with_capacity(12 + 4 * n);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        out.extend_from_slice(&(n as u32).to_le_bytes());
        for s in self.slices() {
            for v in s {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }

    /// Reads a blob written by [`Dave2Weights::to_bytes`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, WeightsError> {
        let n = Self::len();
        let expected = 12 + 4 * n;
        if bytes.len() < 12 || &bytes[..4] != MAGIC || bytes[4..8] != FORMAT_VERSION.to_le_bytes() {
            return Err(WeightsError::BadHeader);
        }
        if bytes.len() != expected || bytes[8..12] != (n as u32).to_le_bytes() {
            return Err(WeightsError::BadLength {
                expected,
                got: bytes.len(),
            });
        }
        let mut values = bytes[12..]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]));
        let mut take = |k: usize| -> Vec<f32> { values.by_ref().take(k).collect() };
        let convs = CONVS
            .iter()
            .map(|&(ci, co, k, _)| ConvWeights {
                weight: take(co * ci * k * k),
                bias: take(co),
            })
            .collect();
        let denses = DENSES
            .iter()
            .map(|&(di, dout)| DenseWeights {
                weight: take(di * dout),
                bias: take(dout),
            })
            .collect();
        Ok(Self { convs, denses })
    }
}

/// DAVE-2 as a burn module (for training; see [`crate::dave2_inference`] for fast driving).
#[derive(Module, Debug)]
pub struct Dave2 {
    convs: Vec<Conv2d>,
    denses: Vec<Linear>,
}

fn values<const D: usize>(t: Tensor<D>) -> Vec<f32> {
    t.into_data()
        .convert::<f32>()
        .try_into_vec_as::<f32>()
        .expect("f32 tensor data")
}

impl Dave2 {
    /// The model holding `weights`, on `device`.
    pub fn from_weights(weights: &Dave2Weights, device: &Device) -> Self {
        let convs = CONVS
            .iter()
            .zip(&weights.convs)
            .map(|(&(ci, co, k, s), w)| Conv2d {
                weight: Param::from_data(TensorData::new(w.weight.clone(), [co, ci, k, k]), device),
                bias: Some(Param::from_data(
                    TensorData::new(w.bias.clone(), [co]),
                    device,
                )),
                stride: [s, s],
                kernel_size: [k, k],
                dilation: [1, 1],
                groups: 1,
                padding: PaddingConfig2d::Valid,
            })
            .collect();
        let denses = DENSES
            .iter()
            .zip(&weights.denses)
            .map(|(&(di, dout), w)| Linear {
                weight: Param::from_data(TensorData::new(w.weight.clone(), [di, dout]), device),
                bias: Some(Param::from_data(
                    TensorData::new(w.bias.clone(), [dout]),
                    device,
                )),
            })
            .collect();
        Self { convs, denses }
    }

    /// The model's weights.
    pub fn weights(&self) -> Dave2Weights {
        let bias =
            |b: &Option<Param<Tensor<1>>>| b.as_ref().map(|b| values(b.val())).unwrap_or_default();
        Dave2Weights {
            convs: self
                .convs
                .iter()
                .map(|c| ConvWeights {
                    weight: values(c.weight.val()),
                    bias: bias(&c.bias),
                })
                .collect(),
            denses: self
                .denses
                .iter()
                .map(|d| DenseWeights {
                    weight: values(d.weight.val()),
                    bias: bias(&d.bias),
                })
                .collect(),
        }
    }

    /// Steering `[n, 1]` for raw pixel values `[n, 1, 66, 200]` in `[0, 255]`.
    pub fn forward(&self, frames: Tensor<4>) -> Tensor<2> {
        let mut x = frames.div_scalar(127.5).sub_scalar(1.0);
        for conv in &self.convs {
            x = relu(conv.forward(x));
        }
        let [n, c, h, w] = x.dims();
        let mut y = x.reshape([n, c * h * w]);
        let last = self.denses.len() - 1;
        for (i, dense) in self.denses.iter().enumerate() {
            y = dense.forward(y);
            if i < last {
                y = relu(y);
            }
        }
        y
    }
}

/// `[n, 1, 66, 200]` pixel values from `n` concatenated grayscale frames.
pub fn frames_tensor(frames: &[u8], device: &Device) -> Tensor<4> {
    let n = frames.len() / FRAME_PIXELS;
    assert_eq!(n * FRAME_PIXELS, frames.len(), "whole 66 x 200 frames");
    let v: Vec<f32> = frames.iter().map(|&p| f32::from(p)).collect();
    Tensor::from_data(
        TensorData::new(v, [n, 1, FRAME_HEIGHT, FRAME_WIDTH]),
        device,
    )
}

/// Burn's forward pass of `weights` on concatenated grayscale frames (slow; a reference).
pub fn predict_burn(weights: &Dave2Weights, frames: &[u8]) -> Vec<f32> {
    let device = Device::flex();
    let model = Dave2::from_weights(weights, &device);
    values(model.forward(frames_tensor(frames, &device)))
}

/// DAVE-2 with its Adam optimiser, trained on the mean squared error of the steering.
pub struct Dave2Trainer {
    model: Dave2,
    optim: ModuleOptimizer,
    lr: f64,
    device: Device,
}

impl Dave2Trainer {
    /// A trainer starting from `weights`, with Adam at learning rate `lr` (1e-4 is DAVE-2's
    /// usual choice; larger for quick tests).
    pub fn new(weights: &Dave2Weights, lr: f64) -> Self {
        let device = Device::flex().autodiff();
        Self {
            model: Dave2::from_weights(weights, &device),
            optim: AdamConfig::new().with_epsilon(1e-8).init(),
            lr,
            device,
        }
    }

    /// One Adam step on a batch: `frames` concatenated grayscale frames, `targets` their
    /// steering. Returns the batch's mean squared error before the step.
    pub fn step(&mut self, frames: &[u8], targets: &[f32]) -> f64 {
        let n = targets.len();
        let x = frames_tensor(frames, &self.device);
        assert_eq!(x.dims()[0], n, "one target per frame");
        let y = Tensor::<2>::from_data(TensorData::new(targets.to_vec(), [n, 1]), &self.device);
        let mse = (self.model.forward(x) - y).powi_scalar(2).mean();
        let loss = values(mse.clone().detach())[0];
        let grads = GradientsParams::from_grads(mse.backward(), &self.model);
        let model = self.model.clone();
        self.model = self.optim.step(self.lr, model, grads);
        f64::from(loss)
    }

    /// The current weights.
    pub fn weights(&self) -> Dave2Weights {
        self.model.weights()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_and_size() {
        let w = Dave2Weights::from_seed(1);
        let n: usize = w.slices().map(Vec::len).sum();
        assert_eq!(n, Dave2Weights::len());
        assert!(n * 4 < 2_000_000, "{n} values");
        assert_eq!(Dave2Weights::from_seed(1), w);
        assert_ne!(Dave2Weights::from_seed(2), w);
    }

    #[test]
    fn blob_round_trips() {
        let w = Dave2Weights::from_seed(3);
        let bytes = w.to_bytes();
        assert_eq!(Dave2Weights::from_bytes(&bytes), Ok(w.clone()));
        assert_eq!(
            Dave2Weights::from_bytes(&bytes[..100]).unwrap_err(),
            WeightsError::BadLength {
                expected: bytes.len(),
                got: 100
            }
        );
        assert_eq!(
            Dave2Weights::from_bytes(b"nope").unwrap_err(),
            WeightsError::BadHeader
        );
        // Through the burn model and back.
        let model = Dave2::from_weights(&w, &Device::flex());
        assert_eq!(model.weights(), w);
    }

    #[test]
    fn training_reduces_the_loss() {
        // Two synthetic frames (dark left / dark right) with opposite steering.
        let mut frames = vec![200u8; 2 * FRAME_PIXELS];
        for r in 0..FRAME_HEIGHT {
            for c in 0..FRAME_WIDTH / 2 {
                frames[r * FRAME_WIDTH + c] = 40;
                frames[FRAME_PIXELS + r * FRAME_WIDTH + FRAME_WIDTH / 2 + c] = 40;
            }
        }
        let targets = [0.5f32, -0.5];
        let mut t = Dave2Trainer::new(&Dave2Weights::from_seed(5), 1e-3);
        let first = t.step(&frames, &targets);
        let mut last = first;
        for _ in 0..30 {
            last = t.step(&frames, &targets);
        }
        assert!(last < 0.2 * first, "loss {first} -> {last}");
        let p = predict_burn(&t.weights(), &frames);
        assert!(p[0] > p[1], "{p:?}");
    }
}
