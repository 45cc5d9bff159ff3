#!/usr/bin/env python3
"""ONNX fixtures for `--oracle onnx:FILE`: the built-in dave2-proxy student as an ONNX graph, and a
few small broken or unusual models for the tests of the loader.

Development-time only (CI reads the committed .onnx files and needs no Python). Needs the `onnx`
and `numpy` packages:

    python3 -m venv /tmp/onnxvenv && /tmp/onnxvenv/bin/pip install onnx numpy
    /tmp/onnxvenv/bin/python scripts/reference/export_dave2_onnx.py

Writes to tests/fixtures/onnx/:
- `dave2-proxy.onnx`: the weights of crates/road-sim/weights/dave2-proxy.bin (the DAV2 blob:
  magic, format version and value count as u32 LE, then every f32 LE, layer by layer, weight
  before bias; convolutions `[out][in][k][k]`, dense layers `[in][out]`) in the graph a Keras
  DAVE-2 converted by tf2onnx looks like: one NHWC float input of raw pixels `[N, 66, 200, 1]`
  (gray, 0..255), a transpose to NCHW, the normalisation `x / 127.5 - 1` inside the graph, five
  convolutions and four dense layers with ReLU between, and one output `[N, 1]`: the steering.
- `rgb_mean.onnx`: NCHW `[1, 3, 16, 32]`; answers (mean of channel 1 - 128) / 128, the mean U of
  a YUV frame as a steering, and a constant throttle of 0.5 as a second number.
- `nan_on_road.onnx`: NHWC `[1, 66, 200, 1]`; answers sqrt(-mean(x)): 0 on a blank frame, NaN on
  any frame with a lit pixel.
- `rank2.onnx`: a `[1, 200]` input (not an image).
- `three_outputs.onnx`: NCHW `[1, 1, 66, 200]` answering three numbers.
"""

import argparse
import os
import struct

import numpy as np
import onnx
from onnx import TensorProto, helper, numpy_helper

CONVS = [(1, 24, 5, 2), (24, 36, 5, 2), (36, 48, 5, 2), (48, 64, 3, 1), (64, 64, 3, 1)]
DENSES = [(1152, 100), (100, 50), (50, 10), (10, 1)]
OPSET = 13


def read_blob(path):
    data = open(path, "rb").read()
    assert data[:4] == b"DAV2", "not a DAV2 blob"
    version, count = struct.unpack("<II", data[4:12])
    assert version == 1, version
    values = np.frombuffer(data[12:], dtype="<f4")
    assert values.size == count, (values.size, count)
    layers, at = [], 0

    def take(n):
        nonlocal at
        out = values[at : at + n]
        at += n
        return out

    for ci, co, k, _ in CONVS:
        layers.append((take(co * ci * k * k).reshape(co, ci, k, k), take(co)))
    for di, do in DENSES:
        layers.append((take(di * do).reshape(di, do), take(do)))
    assert at == count
    return layers


def save(graph, path):
    model = helper.make_model(
        graph, producer_name="wogan export_dave2_onnx.py", opset_imports=[helper.make_opsetid("", OPSET)]
    )
    model.ir_version = 8
    onnx.checker.check_model(model)
    onnx.save(model, path)
    print(f"wrote {path} ({os.path.getsize(path)} bytes)")


def const(name, value):
    return numpy_helper.from_array(np.asarray(value, dtype=np.float32), name)


def dave2(weights, path):
    layers = read_blob(weights)
    inits = [const("scale", 127.5), const("one", 1.0)]
    nodes = [
        helper.make_node("Transpose", ["frame"], ["nchw"], perm=[0, 3, 1, 2]),
        helper.make_node("Div", ["nchw", "scale"], ["scaled"]),
        helper.make_node("Sub", ["scaled", "one"], ["x0"]),
    ]
    x = "x0"
    for i, ((w, b), (_, _, _, s)) in enumerate(zip(layers[:5], CONVS)):
        inits += [const(f"conv{i}.w", w), const(f"conv{i}.b", b)]
        nodes.append(helper.make_node("Conv", [x, f"conv{i}.w", f"conv{i}.b"], [f"conv{i}"], strides=[s, s]))
        nodes.append(helper.make_node("Relu", [f"conv{i}"], [f"relu{i}"]))
        x = f"relu{i}"
    nodes.append(helper.make_node("Flatten", [x], ["features"], axis=1))
    x = "features"
    for i, (w, b) in enumerate(layers[5:]):
        inits += [const(f"dense{i}.w", w), const(f"dense{i}.b", b)]
        last = i == len(DENSES) - 1
        out = "steering" if last else f"dense{i}"
        nodes.append(helper.make_node("Gemm", [x, f"dense{i}.w", f"dense{i}.b"], [out]))
        if not last:
            nodes.append(helper.make_node("Relu", [out], [f"drelu{i}"]))
            x = f"drelu{i}"
    graph = helper.make_graph(
        nodes,
        "dave2-proxy",
        [helper.make_tensor_value_info("frame", TensorProto.FLOAT, ["N", 66, 200, 1])],
        [helper.make_tensor_value_info("steering", TensorProto.FLOAT, ["N", 1])],
        inits,
    )
    save(graph, path)


def rgb_mean(path):
    inits = [
        numpy_helper.from_array(np.array([1], dtype=np.int64), "c1"),
        numpy_helper.from_array(np.array([2], dtype=np.int64), "c2"),
        numpy_helper.from_array(np.array([1], dtype=np.int64), "axis"),
        const("mid", 128.0),
        const("throttle", [[0.5]]),
    ]
    nodes = [
        helper.make_node("Slice", ["frame", "c1", "c2", "axis"], ["u"]),
        helper.make_node("ReduceMean", ["u"], ["mean"], axes=[1, 2, 3], keepdims=1),
        helper.make_node("Reshape", ["mean", "shape"], ["mean2"]),
        helper.make_node("Sub", ["mean2", "mid"], ["centred"]),
        helper.make_node("Div", ["centred", "mid"], ["steering"]),
        helper.make_node("Concat", ["steering", "throttle"], ["out"], axis=1),
    ]
    inits.append(numpy_helper.from_array(np.array([1, 1], dtype=np.int64), "shape"))
    graph = helper.make_graph(
        nodes,
        "rgb-mean",
        [helper.make_tensor_value_info("frame", TensorProto.FLOAT, [1, 3, 16, 32])],
        [helper.make_tensor_value_info("out", TensorProto.FLOAT, [1, 2])],
        inits,
    )
    save(graph, path)


def nan_on_road(path):
    nodes = [
        helper.make_node("ReduceMean", ["frame"], ["mean"], axes=[1, 2, 3], keepdims=0),
        helper.make_node("Neg", ["mean"], ["negative"]),
        helper.make_node("Sqrt", ["negative"], ["steering"]),
    ]
    graph = helper.make_graph(
        nodes,
        "nan-on-road",
        [helper.make_tensor_value_info("frame", TensorProto.FLOAT, [1, 66, 200, 1])],
        [helper.make_tensor_value_info("steering", TensorProto.FLOAT, [1])],
    )
    save(graph, path)


def rank2(path):
    nodes = [helper.make_node("ReduceMean", ["frame"], ["steering"], axes=[1], keepdims=1)]
    graph = helper.make_graph(
        nodes,
        "rank2",
        [helper.make_tensor_value_info("frame", TensorProto.FLOAT, [1, 200])],
        [helper.make_tensor_value_info("steering", TensorProto.FLOAT, [1, 1])],
    )
    save(graph, path)


def three_outputs(path):
    nodes = [
        helper.make_node("ReduceMean", ["frame"], ["mean"], axes=[2, 3], keepdims=0),
        helper.make_node("Concat", ["mean", "mean", "mean"], ["out"], axis=1),
    ]
    graph = helper.make_graph(
        nodes,
        "three-outputs",
        [helper.make_tensor_value_info("frame", TensorProto.FLOAT, [1, 1, 66, 200])],
        [helper.make_tensor_value_info("out", TensorProto.FLOAT, [1, 3])],
    )
    save(graph, path)


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--weights", default=os.path.join(root, "crates/road-sim/weights/dave2-proxy.bin"))
    parser.add_argument("--out", default=os.path.join(root, "tests/fixtures/onnx"))
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    dave2(args.weights, os.path.join(args.out, "dave2-proxy.onnx"))
    rgb_mean(os.path.join(args.out, "rgb_mean.onnx"))
    nan_on_road(os.path.join(args.out, "nan_on_road.onnx"))
    rank2(os.path.join(args.out, "rank2.onnx"))
    three_outputs(os.path.join(args.out, "three_outputs.onnx"))


if __name__ == "__main__":
    main()
