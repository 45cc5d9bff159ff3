//! An ONNX camera network loaded for driving: the file read and checked once (one image input of
//! rank 4, NCHW or NHWC, 1 or 3 channels; outputs that hold one or two numbers; a finite answer to
//! a blank frame), optimised by tract, and run one frame at a time.

use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use tract_onnx::prelude::*;
use tract_onnx::tract_hir::infer::Factoid;

/// Largest model file read, bytes (a DAVE-2 is a few MB; this keeps a wrong file from filling
/// memory).
pub const MAX_MODEL_BYTES: u64 = 1 << 30;
/// Largest camera frame a model may ask for, pixels per side.
pub const MAX_SIDE: usize = 2048;
/// Smallest camera frame a model may ask for, pixels per side.
pub const MIN_SIDE: usize = 8;

/// How the input tensor orders its axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Layout {
    /// Read from the input shape: the axis of size 1 or 3 after the batch (NCHW) or last (NHWC).
    #[default]
    Auto,
    /// `[N, C, H, W]` (PyTorch's).
    Nchw,
    /// `[N, H, W, C]` (Keras's, kept by tf2onnx).
    Nhwc,
}

/// The image a model takes, read from its input shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputShape {
    /// NCHW or NHWC (never [`Layout::Auto`]).
    pub layout: Layout,
    /// 1 (gray) or 3 (colour).
    pub channels: usize,
    /// Rows.
    pub height: usize,
    /// Columns.
    pub width: usize,
}

impl InputShape {
    /// The tensor shape, batch of one.
    pub fn dims(&self) -> [usize; 4] {
        match self.layout {
            Layout::Nhwc => [1, self.height, self.width, self.channels],
            _ => [1, self.channels, self.height, self.width],
        }
    }
}

impl std::fmt::Display for InputShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let layout = if self.layout == Layout::Nhwc {
            "NHWC"
        } else {
            "NCHW"
        };
        let d = self.dims();
        write!(f, "{layout} [{}, {}, {}, {}]", d[0], d[1], d[2], d[3])
    }
}

/// Why a model cannot drive; every message names the file.
#[derive(Debug, thiserror::Error)]
pub enum OnnxError {
    /// The file cannot be read.
    #[error("cannot read ONNX model {path}: {reason}")]
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        reason: String,
    },
    /// The file is larger than [`MAX_MODEL_BYTES`].
    #[error("ONNX model {path}: {bytes} bytes, more than the 1 GiB wogan reads")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size.
        bytes: u64,
    },
    /// The file is not an ONNX model tract can read.
    #[error("{path} is not an ONNX model wogan can run: {reason}")]
    NotOnnx {
        /// The file.
        path: PathBuf,
        /// What tract said.
        reason: String,
    },
    /// The input is not one camera frame.
    #[error("ONNX model {path}: {problem}")]
    Input {
        /// The file.
        path: PathBuf,
        /// What is wrong with the input.
        problem: String,
    },
    /// The outputs are not one or two numbers.
    #[error("ONNX model {path}: {problem}")]
    Output {
        /// The file.
        path: PathBuf,
        /// What is wrong with the outputs.
        problem: String,
    },
    /// A setting does not fit the model.
    #[error("ONNX model {path}: {problem}")]
    Setting {
        /// The file.
        path: PathBuf,
        /// Which setting, and why.
        problem: String,
    },
    /// The model failed to run, or answered a non-finite number.
    #[error("ONNX model {path}: {problem}")]
    Run {
        /// The file.
        path: PathBuf,
        /// What happened.
        problem: String,
    },
}

/// A camera network ready to run: its plan, what it takes and what it answers.
#[derive(Debug)]
pub struct OnnxModel {
    path: PathBuf,
    sha256: String,
    input: InputShape,
    outputs: usize,
    plan: Arc<TypedRunnableModel>,
}

impl OnnxModel {
    /// Reads, checks and optimises the model at `path`; `layout` says how to read its input
    /// shape. The model then answers a blank frame, which must give one or two finite numbers.
    pub fn load(path: &Path, layout: Layout) -> Result<Self, OnnxError> {
        let read_error = |e: std::io::Error| OnnxError::Read {
            path: path.to_owned(),
            reason: e.to_string(),
        };
        let bytes = std::fs::metadata(path).map_err(read_error)?.len();
        if bytes > MAX_MODEL_BYTES {
            return Err(OnnxError::TooLarge {
                path: path.to_owned(),
                bytes,
            });
        }
        let data = std::fs::read(path).map_err(read_error)?;
        let sha256 = Sha256::digest(&data)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        // tract may panic on a malformed graph: that is a bad file, not a crash.
        let loaded = catch_quietly(|| prepare(path, &data, layout)).unwrap_or_else(|_| {
            Err(OnnxError::NotOnnx {
                path: path.to_owned(),
                reason: "tract failed reading it".into(),
            })
        })?;
        let (input, outputs, plan) = loaded;
        let model = Self {
            path: path.to_owned(),
            sha256,
            input,
            outputs,
            plan,
        };
        let mut state = model.spawn()?;
        let blank = vec![0.0f32; input.height * input.width * input.channels];
        let answer = state.run(&blank).map_err(|problem| OnnxError::Run {
            path: path.to_owned(),
            problem,
        })?;
        if let Some(v) = answer[..outputs].iter().find(|v| !v.is_finite()) {
            return Err(OnnxError::Run {
                path: path.to_owned(),
                problem: format!("answers {v} to a blank frame (all inputs 0)"),
            });
        }
        Ok(model)
    }

    /// The file it was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The SHA-256 of the file, lower-case hex.
    pub fn sha256(&self) -> &str {
        &self.sha256
    }

    /// The frame it takes.
    pub fn input(&self) -> InputShape {
        self.input
    }

    /// How many numbers it answers: 1 (steering) or 2 (steering, throttle).
    pub fn outputs(&self) -> usize {
        self.outputs
    }

    /// A state to run frames with (one per drive: it keeps tract's buffers).
    pub fn spawn(&self) -> Result<ModelState, OnnxError> {
        let state = self.plan.spawn().map_err(|e| OnnxError::Run {
            path: self.path.clone(),
            problem: format!("{e:#}"),
        })?;
        Ok(ModelState {
            state,
            dims: self.input.dims(),
            outputs: self.outputs,
        })
    }
}

/// One drive's use of a model.
#[derive(Debug)]
pub struct ModelState {
    state: TypedSimpleState,
    dims: [usize; 4],
    outputs: usize,
}

thread_local! {
    /// Set while this thread runs tract under [`catch_quietly`].
    static QUIET: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// `f`, a panic of tract's caught (a malformed model is a bad file, not a crash) without the
/// panic hook printing it as if the program had crashed; panics elsewhere print as before.
fn catch_quietly<R>(f: impl FnOnce() -> R + std::panic::UnwindSafe) -> std::thread::Result<R> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !QUIET.with(std::cell::Cell::get) {
                previous(info);
            }
        }));
    });
    QUIET.with(|quiet| quiet.set(true));
    let result = std::panic::catch_unwind(f);
    QUIET.with(|quiet| quiet.set(false));
    result
}

impl ModelState {
    /// The model's answer (one or two numbers) to `input`, laid out as the model's input shape.
    pub fn run(&mut self, input: &[f32]) -> Result<[f32; 2], String> {
        let tensor = Tensor::from_shape(&self.dims, input).map_err(|e| format!("{e:#}"))?;
        let state = &mut self.state;
        let result = catch_quietly(std::panic::AssertUnwindSafe(|| {
            state.run(tvec![tensor.into_tvalue()])
        }))
        .map_err(|_| "tract failed running it".to_string())?
        .map_err(|e| format!("{e:#}"))?;
        let mut answer = [f32::NAN; 2];
        let mut n = 0;
        for value in &result {
            let view = value
                .to_plain_array_view::<f32>()
                .map_err(|e| format!("{e:#}"))?;
            for &v in view.iter() {
                if n < 2 {
                    answer[n] = v;
                }
                n += 1;
            }
        }
        if n != self.outputs {
            return Err(format!(
                "answered {n} numbers where its output shape says {}",
                self.outputs
            ));
        }
        Ok(answer)
    }
}

/// Parses, checks the input and outputs, and optimises.
fn prepare(
    path: &Path,
    data: &[u8],
    layout: Layout,
) -> Result<(InputShape, usize, Arc<TypedRunnableModel>), OnnxError> {
    let not_onnx = |e: TractError| OnnxError::NotOnnx {
        path: path.to_owned(),
        reason: format!("{e:#}"),
    };
    let input_problem = |problem: String| OnnxError::Input {
        path: path.to_owned(),
        problem,
    };
    let mut model = tract_onnx::onnx()
        .model_for_read(&mut &data[..])
        .map_err(not_onnx)?;
    let inputs = model.input_outlets().map_err(not_onnx)?.len();
    if inputs != 1 {
        return Err(input_problem(format!(
            "{inputs} inputs; a camera network takes one, the frame"
        )));
    }
    let fact = model.input_fact(0).map_err(not_onnx)?.clone();
    if let Some(dt) = fact.datum_type.concretize() {
        if dt != f32::datum_type() {
            return Err(input_problem(format!(
                "the input is of type {dt:?}; wogan feeds float (f32) pixels"
            )));
        }
    }
    let dims: Vec<Option<i64>> = fact
        .shape
        .dims()
        .map(|d| d.concretize().and_then(|d| d.to_i64().ok()))
        .collect();
    let shown = || {
        let d: Vec<String> = dims
            .iter()
            .map(|d| d.map_or("?".into(), |d| d.to_string()))
            .collect();
        format!("[{}]", d.join(", "))
    };
    if fact.shape.is_open() || dims.len() != 4 {
        return Err(input_problem(format!(
            "the input shape is {}{}; a camera network takes one frame of rank 4, [N, C, H, W] \
             (NCHW) or [N, H, W, C] (NHWC)",
            shown(),
            if fact.shape.is_open() {
                " (of unknown rank)"
            } else {
                ""
            }
        )));
    }
    if !matches!(dims[0], None | Some(1)) {
        return Err(input_problem(format!(
            "the input shape is {}: its batch axis must be 1 or free",
            shown()
        )));
    }
    let is_channels = |d: Option<i64>| matches!(d, Some(1) | Some(3));
    let layout = match layout {
        Layout::Auto => match (is_channels(dims[1]), is_channels(dims[3])) {
            (true, false) => Layout::Nchw,
            (false, true) => Layout::Nhwc,
            (true, true) => {
                return Err(input_problem(format!(
                    "the input shape {} may be NCHW or NHWC: set driver.layout",
                    shown()
                )))
            }
            (false, false) => {
                return Err(input_problem(format!(
                    "the input shape {} has no axis of 1 or 3 channels after the batch (NCHW) \
                     or last (NHWC)",
                    shown()
                )))
            }
        },
        given => given,
    };
    let (c, h, w) = match layout {
        Layout::Nhwc => (dims[3], dims[1], dims[2]),
        _ => (dims[1], dims[2], dims[3]),
    };
    let channels = match c {
        Some(1) => 1,
        Some(3) => 3,
        _ => {
            return Err(input_problem(format!(
                "the input shape {} as {layout:?} has {} channels; wogan's camera gives 1 (gray) \
                 or 3 (colour)",
                shown(),
                c.map_or("unknown".into(), |c| c.to_string())
            )))
        }
    };
    let side = |d: Option<i64>| {
        d.and_then(|d| usize::try_from(d).ok())
            .filter(|d| (MIN_SIDE..=MAX_SIDE).contains(d))
    };
    let (Some(height), Some(width)) = (side(h), side(w)) else {
        return Err(input_problem(format!(
            "the input shape {} asks for a frame of {} x {} pixels; the camera renders from \
             {MIN_SIDE} to {MAX_SIDE} pixels a side, fixed in the model",
            shown(),
            h.map_or("?".into(), |h| h.to_string()),
            w.map_or("?".into(), |w| w.to_string())
        )));
    };
    let input = InputShape {
        layout,
        channels,
        height,
        width,
    };
    model
        .set_input_fact(0, f32::fact(input.dims()).into())
        .map_err(not_onnx)?;
    let typed = model.into_optimized().map_err(not_onnx)?;
    let mut outputs = 0usize;
    for i in 0..typed.output_outlets().map_err(not_onnx)?.len() {
        let fact = typed.output_fact(i).map_err(not_onnx)?;
        let n = fact
            .shape
            .as_concrete()
            .map(|s| s.iter().product::<usize>());
        match n {
            Some(n) => outputs += n,
            None => {
                return Err(OnnxError::Output {
                    path: path.to_owned(),
                    problem: format!(
                        "output {i} has shape {:?}, unknown for a batch of one; a camera network \
                         answers one or two numbers",
                        fact.shape
                    ),
                })
            }
        }
    }
    if !(1..=2).contains(&outputs) {
        return Err(OnnxError::Output {
            path: path.to_owned(),
            problem: format!(
                "its outputs hold {outputs} numbers; a camera network answers one (steering) or \
                 two (steering, throttle)"
            ),
        });
    }
    let plan = typed.into_runnable().map_err(not_onnx)?;
    Ok((input, outputs, plan))
}
