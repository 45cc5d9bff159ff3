#!/usr/bin/env python3
"""Checks keras_to_onnx.py: the ONNX model it writes answers as the Keras model's own weights do.

    PYTHON examples/onnx/check_keras_to_onnx.py [MODEL.h5 ...]

For each model (default: the committed fixture, tests/fixtures/keras/): converts it, then runs the
ONNX model (onnx's reference evaluator) and an independent numpy forward pass of the `.h5` weights
(written here from Keras's definitions of each layer, sharing no code with the converter) on 20
frames, and requires the answers to agree within 1e-5. Then checks that what the converter cannot
convert is refused with a message naming the layer: a model with an unknown layer and one with an
unknown Lambda, written here in Keras's file layout. Exit status 0 when every check passed.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.join(HERE, "..", "..")
FIXTURES = os.path.join(REPO, "tests", "fixtures", "keras")
FRAMES = 20
TOLERANCE = 1e-5

sys.path.insert(0, HERE)
import keras_to_onnx  # noqa: E402


# ----------------------------------------------------------------------------------------------
# The independent forward pass
# ----------------------------------------------------------------------------------------------

def conv2d_nhwc(x: np.ndarray, kernel: np.ndarray, bias: np.ndarray, stride: tuple, same: bool) -> np.ndarray:
    """Keras's Conv2D (channels last, cross-correlation) on one image `x` (H, W, C)."""
    kh, kw, _, out = kernel.shape
    sh, sw = stride
    if same:
        h, w = x.shape[:2]
        oh, ow = -(-h // sh), -(-w // sw)
        ph = max((oh - 1) * sh + kh - h, 0)
        pw = max((ow - 1) * sw + kw - w, 0)
        x = np.pad(x, ((ph // 2, ph - ph // 2), (pw // 2, pw - pw // 2), (0, 0)))
    h, w = x.shape[:2]
    oh, ow = (h - kh) // sh + 1, (w - kw) // sw + 1
    y = np.zeros((oh, ow, out), dtype=np.float64)
    for i in range(kh):
        for j in range(kw):
            patch = x[i:i + sh * (oh - 1) + 1:sh, j:j + sw * (ow - 1) + 1:sw, :]
            y += patch.astype(np.float64) @ kernel[i, j].astype(np.float64)
    return y + bias


def activation(x: np.ndarray, name: str, alpha: float = 1.0) -> np.ndarray:
    if name == "linear":
        return x
    if name == "relu":
        return np.maximum(x, 0.0)
    if name == "elu":
        return np.where(x > 0, x, alpha * (np.exp(np.minimum(x, 0.0)) - 1.0))
    if name == "tanh":
        return np.tanh(x)
    if name == "sigmoid":
        return 1.0 / (1.0 + np.exp(-x))
    raise ValueError(name)


def keras_forward(path: str, image: np.ndarray, affine: tuple) -> np.ndarray:
    """The model of `path` on one image (H, W, C), in float64, from its config and weights."""
    import h5py

    with h5py.File(path, "r") as h5:
        config = json.loads(h5.attrs["model_config"])
        layers = config["config"]
        layers = layers["layers"] if isinstance(layers, dict) else layers
        weights_root = h5["model_weights"]
        x = image.astype(np.float64)
        for entry in layers:
            kind, c = entry["class_name"], entry["config"]
            group = weights_root[c["name"]] if c["name"] in weights_root else None
            w = [np.asarray(group[n]) for n in group.attrs["weight_names"]] if group is not None else []
            if kind == "Lambda":
                x = x * affine[0] + affine[1]
            elif kind in ("Convolution2D", "Conv2D"):
                stride = tuple(c.get("strides") or c.get("subsample") or (1, 1))
                same = (c.get("padding") or c.get("border_mode")) == "same"
                x = activation(conv2d_nhwc(x, w[0], w[1], stride, same), c.get("activation", "linear"))
            elif kind == "Flatten":
                x = x.reshape(-1)
            elif kind == "Dense":
                x = activation(x @ w[0] + w[1], c.get("activation", "linear"))
            elif kind == "Activation":
                x = activation(x, c["activation"])
            elif kind in ("Dropout", "SpatialDropout2D", "InputLayer"):
                pass
            else:
                raise ValueError(f"the check's forward pass has no {kind}")
    return x.reshape(1, -1)


# ----------------------------------------------------------------------------------------------
# The checks
# ----------------------------------------------------------------------------------------------

def frames(shape: tuple, count: int, seed: int = 7) -> list:
    """Camera-like YUV frames: smooth bands and noise, bytes as floats."""
    rng = np.random.default_rng(seed)
    h, w, c = shape
    out = []
    for k in range(count):
        rows = np.linspace(0, 1, h)[:, None, None]
        cols = np.linspace(0, 1, w)[None, :, None]
        base = 128 + 100 * np.sin(3 * rows + (k + 1) * cols + np.arange(c) * 0.7)
        out.append(np.clip(base + rng.normal(0, 20, (h, w, c)), 0, 255).round().astype(np.float32))
    return out


def check_model(path: str) -> None:
    from onnx.reference import ReferenceEvaluator

    with tempfile.TemporaryDirectory() as tmp:
        onnx_path = os.path.join(tmp, "model.onnx")
        print(keras_to_onnx.convert(path, onnx_path))
        evaluator = ReferenceEvaluator(onnx_path)
        import h5py
        with h5py.File(path, "r") as h5:
            layers, _ = keras_to_onnx.read_layers(h5)
        shape = keras_to_onnx.input_shape(layers)
        affine = next((keras_to_onnx.lambda_affine(l, None) for l in layers if l.kind == "Lambda"), (1.0, 0.0))
        worst = 0.0
        for i, frame in enumerate(frames(shape, FRAMES)):
            got = evaluator.run(None, {"input": frame[None]})[0]
            want = keras_forward(path, frame, affine)
            assert got.shape == want.shape, f"frame {i}: shape {got.shape} vs {want.shape}"
            worst = max(worst, float(np.max(np.abs(got - want))))
        assert worst <= TOLERANCE, f"{path}: ONNX and the numpy forward pass differ by {worst}"
        print(f"{path}: {FRAMES} frames, largest difference {worst:.2e} (at most {TOLERANCE})")


def write_keras2(path: str, layers: list, weights: dict, shape=(8, 16, 3)) -> None:
    """A Sequential model in Keras 2's file layout (model_config, model_weights)."""
    import h5py

    first = layers[0][1]
    first["batch_input_shape"] = [None, *shape]
    config = {"class_name": "Sequential", "config": [{"class_name": k, "config": c} for k, c in layers]}
    with h5py.File(path, "w") as h5:
        h5.attrs["keras_version"] = b"2.0.8"
        h5.attrs["backend"] = b"tensorflow"
        h5.attrs["model_config"] = json.dumps(config).encode()
        root = h5.create_group("model_weights")
        for _, c in layers:
            group = root.create_group(c["name"])
            arrays = weights.get(c["name"], {})
            names = [f"{c['name']}/{n}:0" for n in arrays]
            group.attrs["weight_names"] = [n.encode() for n in names]
            for n, (short, array) in zip(names, arrays.items()):
                group.create_dataset(n, data=array)


def check_refusals(tmp: str) -> None:
    script = os.path.join(HERE, "keras_to_onnx.py")
    rng = np.random.default_rng(1)
    conv = ("Conv2D", {"name": "conv", "filters": 2, "kernel_size": [3, 3], "strides": [1, 1],
                       "padding": "valid", "activation": "elu", "data_format": "channels_last"})
    # Weights at a trained network's scale for byte inputs (the first layer sees 0..255).
    conv_w = {"conv": {"kernel": (rng.normal(size=(3, 3, 3, 2)) * 1e-3).astype(np.float32),
                       "bias": np.zeros(2, np.float32)}}
    cases = [
        ("lstm", [conv, ("LSTM", {"name": "memory"})], "layer memory: LSTM is not a layer"),
        ("lambda", [("Lambda", {"name": "odd", "function": "YWJj"}), conv],
         "layer odd (Lambda): its bytecode's constants"),
        ("theano", [(conv[0], dict(conv[1], data_format="channels_first"))], "channels_first ordering"),
    ]
    for name, layers, says in cases:
        path = os.path.join(tmp, f"{name}.h5")
        write_keras2(path, layers, conv_w)
        run = subprocess.run([sys.executable, script, path, os.path.join(tmp, f"{name}.onnx")],
                             capture_output=True, text=True)
        assert run.returncode == 1, f"{name}: exit {run.returncode}: {run.stderr}"
        assert says in run.stderr and "tf2onnx" in run.stderr, f"{name}: {run.stderr}"
        print(f"refused as it should be ({name}): {run.stderr.strip()[:120]}")
    # A model written here in Keras 2's layout converts and agrees with the forward pass too.
    path = os.path.join(tmp, "small.h5")
    layers = [conv, ("Flatten", {"name": "flat"}),
              ("Dense", {"name": "out", "units": 1, "activation": "linear"})]
    weights = dict(conv_w, out={"kernel": (rng.normal(size=(6 * 14 * 2, 1)) * 0.1).astype(np.float32),
                                "bias": np.array([0.1], np.float32)})
    write_keras2(path, layers, weights)
    check_model(path)
    # And the output never overwrites the input.
    run = subprocess.run([sys.executable, script, path, path], capture_output=True, text=True)
    assert run.returncode == 2 and "overwrites an input" in run.stderr, run.stderr


def main() -> int:
    models = sys.argv[1:] or sorted(os.path.join(FIXTURES, f) for f in os.listdir(FIXTURES) if f.endswith(".h5"))
    assert models, f"no .h5 model in {FIXTURES}"
    for path in models:
        check_model(path)
    with tempfile.TemporaryDirectory() as tmp:
        check_refusals(tmp)
    print("keras_to_onnx.py: every check passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
