//! DAVE-2 (Bojarski et al., NVIDIA 2016), the SBST competition's second system under test: a CNN
//! that steers from one front-camera frame.
//!
//! Input: a 66 x 200 grayscale frame (one channel instead of the paper's three YUV planes; see
//! [`road_sim::vision::Camera`]), normalised in the network to `x / 127.5 − 1`. Layers: convolutions 24 5x5
//! stride 2, 36 5x5 s2, 48 5x5 s2, 64 3x3, 64 3x3 (no padding), dense 100, 50, 10, 1, ReLU after
//! every layer but the last. The output is the steering in `[-1, 1]` of the car's maximum wheel
//! angle (the network's output is linear; drivers clamp it).
//!
//! [`Dave2`] is the network as a burn module, converted to and from road-sim's plain
//! [`Dave2Weights`]; [`Dave2Trainer`] makes Adam steps on the mean squared error.

use burn::module::Param;
use burn::nn::conv::Conv2d;
use burn::nn::{Linear, PaddingConfig2d};
use burn::optim::{AdamConfig, GradientsParams, ModuleOptimizer};
use burn::prelude::*;
use burn::tensor::activation::relu;
use road_sim::vision::{
    ConvWeights, Dave2Weights, DenseWeights, CONVS, DENSES, FRAME_HEIGHT, FRAME_PIXELS, FRAME_WIDTH,
};

/// DAVE-2 as a burn module (for training; see [`road_sim::vision::Dave2Net`] for fast driving).
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
    use road_sim::vision::{Camera, Dave2Net, RoadScene};
    use road_sim::Road;

    /// Three camera frames along a bend.
    fn camera_frames() -> Vec<u8> {
        let pts = [[100.0, 10.0], [100.0, 40.0], [120.0, 70.0], [150.0, 80.0]];
        let road = Road::new(&pts).unwrap();
        let scene = RoadScene::new(&road);
        let cam = Camera::default();
        let mut out = Vec::new();
        for (i, h) in [1.5, 1.7, 1.3].into_iter().enumerate() {
            out.extend(
                cam.render(&scene, [101.0 + i as f64, 20.0 + 5.0 * i as f64], h)
                    .data,
            );
        }
        out
    }

    /// The simulator's fast inference computes what the burn model computes.
    #[test]
    fn fast_inference_matches_burn() {
        let frames = camera_frames();
        for seed in [1, 2] {
            let w = Dave2Weights::from_seed(seed);
            let reference = predict_burn(&w, &frames);
            let mut net = Dave2Net::new(&w);
            for (i, f) in frames.chunks_exact(FRAME_PIXELS).enumerate() {
                let p = net.predict(f);
                assert!(
                    (p - reference[i]).abs() < 1e-4,
                    "seed {seed} frame {i}: {p} vs {}",
                    reference[i]
                );
            }
        }
    }

    #[test]
    fn weights_round_trip_through_the_burn_model() {
        let w = Dave2Weights::from_seed(3);
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
