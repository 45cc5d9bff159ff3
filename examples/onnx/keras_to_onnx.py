#!/usr/bin/env python3
"""Converts a Keras `.h5` camera network of the DAVE-2 family to ONNX, without TensorFlow.

    python3 examples/onnx/keras_to_onnx.py IN.h5 OUT.onnx [--lambda SCALE,OFFSET]

then `wogan run --oracle onnx:OUT.onnx --config udacity.json` (`{"driver": {"contract":
"udacity"}}`) drives with it. Needs h5py, numpy and onnx (examples/onnx/requirements.txt).

Reads what Keras 1.x and 2.x write for a `Sequential` model with TensorFlow dimension ordering
(`dim_ordering` / `data_format` "tf" / "channels_last"): the model's JSON (`model_config`) and its
weights (`model_weights`). Layers understood, as the Udacity course's DAVE-2 solutions use them:

- `Lambda`: the normalisation `x * SCALE + OFFSET`. Keras stores a Lambda as marshalled Python
  bytecode, which no other Python can run safely; its constants are read from it instead, and the
  two normalisations DAVE-2 solutions write are recognised: `x / 127.5 - 1.0` and `x / 255.0 -
  0.5`. Any other Lambda is refused, naming it, unless `--lambda SCALE,OFFSET` says what it does.
- `Cropping2D`, `Convolution2D` / `Conv2D` (valid or same padding, strides), `MaxPooling2D`,
  `Dense`, `Dropout` and `SpatialDropout2D` (nothing at inference), `Flatten`, `Activation` and
  each layer's `activation` (linear, relu, elu, tanh, sigmoid, softmax), `ELU`.

The ONNX model takes what the Keras model takes, NHWC float32 `[1, H, W, C]`, and answers what it
answers (`[1, N]`). Convolutions run NCHW inside (ONNX's layout); before `Flatten` the tensor goes
back to NHWC, so the flattened order, and so the first Dense layer's weights, are Keras's. Anything
else (another layer, a functional model, Theano ordering) stops with a message naming the layer;
tf2onnx (`python -m tf2onnx.convert --keras IN.h5`) converts any Keras model, with TensorFlow.
"""
from __future__ import annotations

import argparse
import json
import struct
import sys
from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

OPSET = 13
ACTIVATIONS = ("linear", "relu", "elu", "tanh", "sigmoid", "softmax")
# The normalisations of DAVE-2 solutions: the constants in a Lambda's bytecode, and what they do.
KNOWN_LAMBDAS = {
    (127.5, 1.0): (1.0 / 127.5, -1.0),  # x / 127.5 - 1.0
    (255.0, 0.5): (1.0 / 255.0, -0.5),  # x / 255.0 - 0.5
}
TF2ONNX = "convert it with tf2onnx (python -m tf2onnx.convert --keras IN.h5 --output OUT.onnx)"


class ConversionError(Exception):
    """The model is not one this converter understands; the message says which part."""


@dataclass
class Layer:
    """One layer of the model's config: its class, name and config."""

    kind: str
    name: str
    config: dict


# ----------------------------------------------------------------------------------------------
# Reading the .h5 file
# ----------------------------------------------------------------------------------------------

def text(value: Any) -> str:
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


def read_layers(h5: Any) -> tuple[list[Layer], str]:
    """The layers of a Sequential model, and the Keras version that wrote it."""
    if "model_config" not in h5.attrs:
        raise ConversionError("the file has no model_config: it holds weights only (save the "
                              "whole model with model.save), or it is not a Keras model")
    config = json.loads(text(h5.attrs["model_config"]))
    version = text(h5.attrs.get("keras_version", "1 (no keras_version)"))
    if config.get("class_name") != "Sequential":
        raise ConversionError(f"the model is a {config.get('class_name')}, not a Sequential one: "
                              f"{TF2ONNX}")
    layers = config["config"]
    if isinstance(layers, dict):  # Keras 2.2 and later: {"name": ..., "layers": [...]}
        layers = layers["layers"]
    return [Layer(entry["class_name"], entry["config"]["name"], entry["config"]) for entry in layers], version


def layer_weights(h5: Any, name: str) -> list[np.ndarray]:
    """A layer's weight arrays in their stored order (`weight_names`)."""
    group = h5["model_weights"] if "model_weights" in h5 else h5
    if name not in group:
        return []
    g = group[name]
    names = [text(n) for n in g.attrs.get("weight_names", [])]
    return [np.asarray(g[n], dtype=np.float32) for n in names]


def input_shape(layers: list[Layer]) -> tuple[int, int, int]:
    """(H, W, C) of the first layer's `batch_input_shape`."""
    shape = layers[0].config.get("batch_input_shape")
    if not shape or len(shape) != 4 or any(v is None for v in shape[1:]):
        raise ConversionError(f"layer {layers[0].name}: no image input shape "
                              f"(batch_input_shape {shape})")
    return int(shape[1]), int(shape[2]), int(shape[3])


def channels_last(layer: Layer) -> None:
    ordering = layer.config.get("dim_ordering") or layer.config.get("data_format")
    if ordering not in (None, "tf", "channels_last", "default"):
        raise ConversionError(f"layer {layer.name} ({layer.kind}): {ordering} ordering; this "
                              f"converter reads TensorFlow ordering only: {TF2ONNX}")


def marshalled_floats(blob: bytes) -> list[float]:
    """The float constants in marshalled Python bytecode: `g` (binary, 8 bytes) and `f` (text)."""
    found = []
    for i, byte in enumerate(blob):
        kind = byte & 0x7F  # the high bit flags a reference
        if kind == ord("g") and i + 9 <= len(blob):
            value = struct.unpack("<d", blob[i + 1:i + 9])[0]
            if np.isfinite(value) and value != 0.0 and 1e-6 < abs(value) < 1e6:
                found.append(value)
        elif kind == ord("f") and i + 2 <= len(blob):
            n = blob[i + 1]
            try:
                found.append(float(blob[i + 2:i + 2 + n].decode("ascii")))
            except (UnicodeDecodeError, ValueError):
                pass
    return found


def lambda_affine(layer: Layer, override: Optional[tuple[float, float]]) -> tuple[float, float]:
    """(scale, offset) of a normalising Lambda."""
    if override is not None:
        return override
    function = layer.config.get("function")
    if isinstance(function, (list, tuple)):  # Keras 2: [code, defaults, closure]
        function = function[0]
    blob = b""
    if isinstance(function, str):
        import base64
        import codecs
        try:
            blob = codecs.decode(function.encode("ascii"), "base64")
        except (ValueError, base64.binascii.Error):
            # Keras 1 on Python 2 wrote raw marshal bytes as a latin-1 string.
            blob = function.encode("latin-1", errors="ignore")
    constants = marshalled_floats(blob)
    for (divisor, subtrahend), affine in KNOWN_LAMBDAS.items():
        if divisor in constants and subtrahend in constants:
            return affine
    raise ConversionError(
        f"layer {layer.name} (Lambda): its bytecode's constants {sorted(set(constants))} are "
        "not a normalisation this converter knows (x / 127.5 - 1.0, x / 255.0 - 0.5); say what "
        f"it does with --lambda SCALE,OFFSET (y = x * SCALE + OFFSET), or {TF2ONNX}")


# ----------------------------------------------------------------------------------------------
# Building the ONNX graph
# ----------------------------------------------------------------------------------------------

class Graph:
    """The ONNX nodes and initialisers being built, and the running tensor's name and shape."""

    def __init__(self, shape_hwc: tuple[int, int, int]) -> None:
        from onnx import helper
        self.helper = helper
        self.nodes: list = []
        self.initialisers: list = []
        self.tensor = "input"
        self.nchw = False
        self.shape = list(shape_hwc)  # H, W, C (or a flat [N] after Flatten)
        self.count = 0

    def name(self, hint: str) -> str:
        self.count += 1
        return f"{hint}_{self.count}"

    def constant(self, hint: str, array: np.ndarray) -> str:
        from onnx import numpy_helper
        name = self.name(hint)
        self.initialisers.append(numpy_helper.from_array(np.asarray(array, dtype=np.float32), name))
        return name

    def int_constant(self, hint: str, values: list) -> str:
        from onnx import numpy_helper
        name = self.name(hint)
        self.initialisers.append(numpy_helper.from_array(np.asarray(values, dtype=np.int64), name))
        return name

    def node(self, op: str, inputs: list[str], hint: str, **attributes: Any) -> str:
        out = self.name(hint)
        self.nodes.append(self.helper.make_node(op, inputs, [out], **attributes))
        self.tensor = out
        return out

    def to_nchw(self) -> None:
        if not self.nchw:
            self.node("Transpose", [self.tensor], "to_nchw", perm=[0, 3, 1, 2])
            self.nchw = True

    def to_nhwc(self) -> None:
        if self.nchw:
            self.node("Transpose", [self.tensor], "to_nhwc", perm=[0, 2, 3, 1])
            self.nchw = False

    def activation(self, name: str, layer: Layer) -> None:
        if name not in ACTIVATIONS:
            raise ConversionError(f"layer {layer.name} ({layer.kind}): activation {name!r} "
                                  f"(known: {', '.join(ACTIVATIONS)}): {TF2ONNX}")
        if name == "relu":
            self.node("Relu", [self.tensor], "relu")
        elif name == "elu":
            self.node("Elu", [self.tensor], "elu", alpha=float(layer.config.get("alpha", 1.0)))
        elif name == "tanh":
            self.node("Tanh", [self.tensor], "tanh")
        elif name == "sigmoid":
            self.node("Sigmoid", [self.tensor], "sigmoid")
        elif name == "softmax":
            self.node("Softmax", [self.tensor], "softmax", axis=-1)


def conv_settings(layer: Layer) -> tuple[int, tuple[int, int], tuple[int, int], str]:
    """(filters, kernel, strides, padding) of a Keras 1 or 2 convolution."""
    c = layer.config
    if "filters" in c:  # Keras 2
        filters, kernel, strides, padding = c["filters"], tuple(c["kernel_size"]), tuple(c["strides"]), c["padding"]
    else:  # Keras 1
        filters, kernel = c["nb_filter"], (c["nb_row"], c["nb_col"])
        strides, padding = tuple(c.get("subsample", (1, 1))), c.get("border_mode", "valid")
    if c.get("dilation_rate", (1, 1)) not in ((1, 1), [1, 1]):
        raise ConversionError(f"layer {layer.name} ({layer.kind}): dilated convolution: {TF2ONNX}")
    return int(filters), kernel, strides, padding


def out_size(size: int, kernel: int, stride: int, padding: str) -> int:
    return -(-size // stride) if padding == "same" else (size - kernel) // stride + 1


def convert(path: str, out_path: str, lambda_override: Optional[tuple[float, float]] = None) -> str:
    """Writes the ONNX model of the .h5 file at `path` to `out_path`; returns a one-line summary."""
    import h5py
    import onnx
    from onnx import TensorProto, helper

    with h5py.File(path, "r") as h5:
        layers, version = read_layers(h5)
        h, w, c = input_shape(layers)
        g = Graph((h, w, c))
        for layer in layers:
            kind = layer.kind
            weights = layer_weights(h5, layer.name)
            if kind in ("Dropout", "SpatialDropout2D", "InputLayer"):
                continue
            if kind == "Lambda":
                scale, offset = lambda_affine(layer, lambda_override)
                g.node("Mul", [g.tensor, g.constant("scale", np.array(scale))], "lambda_scale")
                g.node("Add", [g.tensor, g.constant("offset", np.array(offset))], "lambda_offset")
            elif kind == "Cropping2D":
                channels_last(layer)
                (top, bottom), (left, right) = layer.config["cropping"]
                g.to_nhwc()
                hh, ww, cc = g.shape
                g.node("Slice", [g.tensor, g.int_constant("starts", [top, left]),
                                 g.int_constant("ends", [hh - bottom, ww - right]),
                                 g.int_constant("axes", [1, 2])], "crop")
                g.shape = [hh - top - bottom, ww - left - right, cc]
            elif kind in ("Convolution2D", "Conv2D"):
                channels_last(layer)
                filters, (kh, kw), (sh, sw), padding = conv_settings(layer)
                if padding not in ("valid", "same"):
                    raise ConversionError(f"layer {layer.name}: padding {padding!r}: {TF2ONNX}")
                kernel = weights[0]  # (kh, kw, in, out), TensorFlow ordering
                if kernel.shape != (kh, kw, g.shape[2], filters):
                    raise ConversionError(f"layer {layer.name}: kernel of shape {kernel.shape}, not "
                                          f"{(kh, kw, g.shape[2], filters)}")
                g.to_nchw()
                inputs = [g.tensor, g.constant("kernel", kernel.transpose(3, 2, 0, 1))]
                if len(weights) > 1:
                    inputs.append(g.constant("bias", weights[1]))
                attributes = dict(kernel_shape=[kh, kw], strides=[sh, sw])
                if padding == "same":
                    attributes["auto_pad"] = "SAME_UPPER"
                g.node("Conv", inputs, "conv", **attributes)
                g.shape = [out_size(g.shape[0], kh, sh, padding), out_size(g.shape[1], kw, sw, padding), filters]
                g.activation(layer.config.get("activation", "linear"), layer)
            elif kind == "MaxPooling2D":
                channels_last(layer)
                pool = tuple(layer.config.get("pool_size", (2, 2)))
                strides = tuple(layer.config.get("strides") or pool)
                padding = layer.config.get("padding") or layer.config.get("border_mode", "valid")
                g.to_nchw()
                attributes = dict(kernel_shape=list(pool), strides=list(strides))
                if padding == "same":
                    attributes["auto_pad"] = "SAME_UPPER"
                g.node("MaxPool", [g.tensor], "pool", **attributes)
                g.shape = [out_size(g.shape[0], pool[0], strides[0], padding),
                           out_size(g.shape[1], pool[1], strides[1], padding), g.shape[2]]
            elif kind == "Flatten":
                g.to_nhwc()  # Keras flattens H, W, C in that order
                g.node("Flatten", [g.tensor], "flatten", axis=1)
                g.shape = [int(np.prod(g.shape))]
            elif kind == "Dense":
                if len(g.shape) != 1:
                    raise ConversionError(f"layer {layer.name} (Dense) on an image: put a Flatten "
                                          f"before it, or {TF2ONNX}")
                kernel = weights[0]  # (in, out)
                if kernel.shape[0] != g.shape[0]:
                    raise ConversionError(f"layer {layer.name}: kernel of shape {kernel.shape} "
                                          f"after {g.shape[0]} values")
                bias = weights[1] if len(weights) > 1 else np.zeros(kernel.shape[1], np.float32)
                g.node("Gemm", [g.tensor, g.constant("kernel", kernel), g.constant("bias", bias)], "dense")
                g.shape = [kernel.shape[1]]
                g.activation(layer.config.get("activation", "linear"), layer)
            elif kind == "Activation":
                g.activation(layer.config["activation"], layer)
            elif kind == "ELU":
                g.node("Elu", [g.tensor], "elu", alpha=float(layer.config.get("alpha", 1.0)))
            else:
                raise ConversionError(f"layer {layer.name}: {kind} is not a layer this converter "
                                      f"knows: {TF2ONNX}")
    if len(g.shape) != 1:
        raise ConversionError("the model does not end in a vector (no Flatten and Dense at its end)")
    g.node("Identity", [g.tensor], "output")
    g.nodes[-1].output[0] = "output"
    graph = helper.make_graph(
        g.nodes, "keras_to_onnx",
        [helper.make_tensor_value_info("input", TensorProto.FLOAT, [1, h, w, c])],
        [helper.make_tensor_value_info("output", TensorProto.FLOAT, [1, g.shape[0]])],
        g.initialisers)
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", OPSET)],
                              producer_name="wogan keras_to_onnx.py")
    model.ir_version = 8
    onnx.checker.check_model(model)
    onnx.save(model, out_path)
    return (f"{path} (Keras {version}, {len(layers)} layers, input {h}x{w}x{c}) -> {out_path} "
            f"(ONNX opset {OPSET}, output [1, {g.shape[0]}])")


def parse_lambda(value: str) -> tuple[float, float]:
    try:
        scale, offset = (float(v) for v in value.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"{value!r} is not SCALE,OFFSET (two numbers)") from None
    return scale, offset


def main(argv: Optional[list] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("model", metavar="IN.h5", help="a Keras model saved by model.save")
    parser.add_argument("out", metavar="OUT.onnx", help="written; must not be IN.h5")
    parser.add_argument("--lambda", dest="lambda_affine", type=parse_lambda, metavar="SCALE,OFFSET",
                        help="what the model's Lambda layer does: y = x * SCALE + OFFSET")
    args = parser.parse_args(argv)
    import os
    if os.path.abspath(args.model) == os.path.abspath(args.out):
        parser.error("OUT.onnx is IN.h5: an output never overwrites an input")
    try:
        print(convert(args.model, args.out, args.lambda_affine))
    except ConversionError as error:
        print(f"keras_to_onnx.py: {args.model}: {error}", file=sys.stderr)
        return 1
    except OSError as error:
        print(f"keras_to_onnx.py: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
