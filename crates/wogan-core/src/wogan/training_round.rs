//! What one training round reads and the analyzer's side of it: the data as the round sees it,
//! and the analyzer's steps in order, which may run on a thread of their own beside the WGAN's
//! (the model's `set_concurrent_training`).

use crate::nets::{AnalyzerTrainer, Matrix};

/// The data a training round reads, shared by the threads that train.
pub(super) struct TrainingData<'a> {
    pub dim: usize,
    pub tests: &'a [f32],
    pub targets: &'a [f32],
}

impl TrainingData<'_> {
    /// The tests `idx` as a matrix, one row each.
    pub fn rows(&self, idx: &[usize]) -> Matrix {
        let mut v = Vec::with_capacity(idx.len() * self.dim);
        for &i in idx {
            v.extend_from_slice(&self.tests[i * self.dim..(i + 1) * self.dim]);
        }
        Matrix::new(v, idx.len(), self.dim)
    }

    /// The analyzer's inputs and logit targets for the tests `idx` (`None`: all tests).
    fn analyzer_batch(&self, idx: Option<&[usize]>) -> (Matrix, Vec<f32>) {
        match idx {
            None => {
                let n = self.targets.len();
                (
                    Matrix::new(self.tests.to_vec(), n, self.dim),
                    self.targets.to_vec(),
                )
            }
            Some(idx) => {
                let y: Vec<f32> = idx.iter().map(|&i| self.targets[i]).collect();
                (self.rows(idx), y)
            }
        }
    }
}

/// A round's analyzer steps, in order: all the data as one fixed batch (built once) or the
/// batches drawn for it; the last step reports the loss.
pub(super) struct AnalyzerSteps<'a> {
    analyzer: &'a mut AnalyzerTrainer,
    data: &'a TrainingData<'a>,
    fixed: Option<(Matrix, Vec<f32>)>,
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
    pub fn step(&mut self, batch: Option<Vec<usize>>) {
        self.left = self.left.saturating_sub(1);
        let report = self.left == 0;
        let loss = match batch {
            Some(idx) => {
                let (x, y) = self.data.analyzer_batch(Some(&idx));
                self.analyzer.step(&x, &y, report)
            }
            None => {
                let data = self.data;
                let (x, y) = self.fixed.get_or_insert_with(|| data.analyzer_batch(None));
                self.analyzer.step(x, y, report)
            }
        };
        if let Some(loss) = loss {
            self.loss = loss;
        }
    }
}
