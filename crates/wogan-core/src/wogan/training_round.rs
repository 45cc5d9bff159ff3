//! What one training round reads and the analyzer's side of it: the data as the round sees it,
//! and the analyzer's steps in order, which may run on a thread of their own beside the WGAN's
//! (the model's `set_concurrent_training`).

use burn::prelude::*;

use crate::error::Error;
use crate::nets::{matrix, AnalyzerTrainer};

/// The data a training round reads, shared by the threads that train.
pub(super) struct TrainingData<'a> {
    pub dim: usize,
    pub tests: &'a [f32],
    pub targets: &'a [f32],
    pub device: &'a Device,
}

impl TrainingData<'_> {
    /// The tests `idx` as a matrix, one row each.
    pub fn rows(&self, idx: &[usize]) -> Tensor<2> {
        let mut v = Vec::with_capacity(idx.len() * self.dim);
        for &i in idx {
            v.extend_from_slice(&self.tests[i * self.dim..(i + 1) * self.dim]);
        }
        matrix(v, idx.len(), self.dim, self.device)
    }

    /// The analyzer's inputs and logit targets for the tests `idx` (`None`: all tests).
    fn analyzer_batch(&self, idx: Option<&[usize]>) -> (Tensor<2>, Tensor<2>) {
        match idx {
            None => {
                let n = self.targets.len();
                let x = matrix(self.tests.to_vec(), n, self.dim, self.device);
                let y = matrix(self.targets.to_vec(), n, 1, self.device);
                (x, y)
            }
            Some(idx) => {
                let y: Vec<f32> = idx.iter().map(|&i| self.targets[i]).collect();
                (self.rows(idx), matrix(y, idx.len(), 1, self.device))
            }
        }
    }
}

/// A round's analyzer steps, in order: all the data as one fixed batch (built once) or the
/// batches drawn for it; the last step reports the loss.
pub(super) struct AnalyzerSteps<'a> {
    analyzer: &'a mut AnalyzerTrainer,
    data: &'a TrainingData<'a>,
    fixed: Option<(Tensor<2>, Tensor<2>)>,
    left: usize,
    /// The loss the last step reported (0 before it).
    pub loss: f64,
}

impl<'a> AnalyzerSteps<'a> {
    pub fn new(
        analyzer: &'a mut AnalyzerTrainer,
        data: &'a TrainingData<'a>,
        steps: usize,
    ) -> Self {
        Self {
            analyzer,
            data,
            fixed: None,
            left: steps,
            loss: 0.0,
        }
    }

    /// One step on `batch` (`None`: all the data).
    pub fn step(&mut self, batch: Option<Vec<usize>>) -> Result<(), Error> {
        let (x, y) = match batch {
            Some(idx) => self.data.analyzer_batch(Some(&idx)),
            None => self
                .fixed
                .get_or_insert_with(|| self.data.analyzer_batch(None))
                .clone(),
        };
        self.left = self.left.saturating_sub(1);
        if let Some(loss) = self.analyzer.step(x, y, self.left == 0)? {
            self.loss = loss;
        }
        Ok(())
    }
}
