//! DAVE-2's weights as plain data: the layer shapes, the `f32` vectors in burn's layouts, and the
//! compact byte blob `wogan train-driver` writes and `--driver-weights` reads.
//!
//! The network (Bojarski et al., NVIDIA 2016): a 66 x 200 grayscale frame normalised to
//! `x / 127.5 − 1`; convolutions 24 5x5 stride 2, 36 5x5 s2, 48 5x5 s2, 64 3x3, 64 3x3 (no
//! padding); dense 100, 50, 10, 1; ReLU after every layer but the last. The output is the steering
//! in `[-1, 1]` of the car's maximum wheel angle. [`super::Dave2Net`] runs it for driving; the
//! `driver-training` crate trains it in burn.

use super::camera::{FRAME_HEIGHT, FRAME_WIDTH};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha20Rng;

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

/// Largest weight magnitude a blob may hold (trained weights stay far below it).
pub const MAX_ABS_WEIGHT: f32 = 1e4;
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
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum WeightsError {
    /// Not a DAVE-2 weight blob.
    #[error("not a DAVE-2 weight blob (bad magic or version)")]
    BadHeader,
    /// A value is not finite or larger than `MAX_ABS_WEIGHT` in magnitude: not weights any
    /// training makes, and a network that would answer with nonsense.
    #[error("DAVE-2 weight {index} is {value}: every weight must be finite and at most 1e4 in magnitude")]
    BadValue {
        /// Position of the value in the blob, from 0.
        index: usize,
        /// The value.
        value: f32,
    },
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
        let weights = Self { convs, denses };
        let bad = weights
            .slices()
            .flatten()
            .enumerate()
            .find(|(_, v)| !(v.is_finite() && v.abs() <= MAX_ABS_WEIGHT))
            .map(|(index, &value)| WeightsError::BadValue { index, value });
        match bad {
            Some(error) => Err(error),
            None => Ok(weights),
        }
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
    }

    #[test]
    fn non_finite_or_huge_weights_are_refused() {
        let mut bytes = Dave2Weights::from_seed(3).to_bytes();
        // The fifth value of the blob (after the 12-byte header).
        bytes[12 + 16..12 + 20].copy_from_slice(&f32::INFINITY.to_le_bytes());
        assert_eq!(
            Dave2Weights::from_bytes(&bytes).unwrap_err(),
            WeightsError::BadValue {
                index: 4,
                value: f32::INFINITY
            }
        );
        bytes[12 + 16..12 + 20].copy_from_slice(&2e4f32.to_le_bytes());
        assert!(matches!(
            Dave2Weights::from_bytes(&bytes),
            Err(WeightsError::BadValue { index: 4, .. })
        ));
    }
}
