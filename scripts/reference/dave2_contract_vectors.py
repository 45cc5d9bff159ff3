#!/usr/bin/env python3
"""Reference vectors for the ONNX driver's contract, made by the competition's own DAVE-2 code:
`self_driving/image_processing.py` (`preprocess`: crop, resize, RGB to YUV) and
`self_driving/nvidia_prediction.py` (`NvidiaPrediction.predict`: the throttle rule).

Development-time only: the Rust tests read the committed JSON and need no Python. Needs a checkout
of se2p/tool-competition-av and numpy and OpenCV (`pip install numpy opencv-python-headless`):

    python3 scripts/reference/dave2_contract_vectors.py --pipeline /tmp/tca

writes tests/reference/dave2_contract.json:
- `images`: for each input image (made by a formula the Rust test repeats: `pattern` names it,
  160 rows x 320 columns x 3 RGB bytes, the competition camera's size) the preprocessed pixels
  (YUV bytes) at every 3rd row and 7th column;
- `throttle`: for a max speed, a sequence of (steering, speed km/h) calls of one
  `NvidiaPrediction` and the throttle each call returns (its speed limit is state).

Every answer is computed by the pipeline's code. Two imports the functions do not use at run time
are stood in for: `matplotlib.image` (imported by image_processing.py) and
`self_driving.simulation_data` (imported by nvidia_prediction.py for a type name, and importing
BeamNG modules); the model is a stand-in whose `predict` returns the steering given (as a rank-0 array: see
`Steers.predict`).
"""

import argparse
import collections
import json
import os
import sys
import types

import numpy as np


def pattern(name, rows=160, cols=320):
    r = np.arange(rows, dtype=np.int64)[:, None, None]
    c = np.arange(cols, dtype=np.int64)[None, :, None]
    k = np.arange(3, dtype=np.int64)[None, None, :]
    if name == "stripes":
        v = (r * 7 + c * 13 + k * 71 + (r * c) % 29) % 256
    elif name == "gradient":
        v = (r + c // 2 + 60 * k) % 256
    elif name == "blocks":
        v = ((r // 9 + c // 11) % 5) * 50 + k * 2
    else:
        raise ValueError(name)
    return v.astype(np.uint8)


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pipeline", required=True, help="a checkout of se2p/tool-competition-av")
    parser.add_argument("--out", default=os.path.join(root, "tests/reference/dave2_contract.json"))
    args = parser.parse_args()

    sys.modules["matplotlib"] = types.ModuleType("matplotlib")
    sys.modules["matplotlib.image"] = types.ModuleType("matplotlib.image")
    stand_in = types.ModuleType("self_driving.simulation_data")
    stand_in.SimulationDataRecord = collections.namedtuple("SimulationDataRecord", ["vel_kmh"])
    sys.modules["self_driving.simulation_data"] = stand_in
    sys.path.insert(0, args.pipeline)
    import cv2
    from self_driving import image_processing, nvidia_prediction

    images = []
    for name in ["stripes", "gradient", "blocks"]:
        out = image_processing.preprocess(pattern(name))
        assert out.shape == (160, 320, 3) and out.dtype == np.uint8, (out.shape, out.dtype)
        samples = [
            [int(r), int(c), [int(v) for v in out[r, c]]]
            for r in range(0, 160, 3)
            for c in range(0, 320, 7)
        ]
        images.append({"pattern": name, "samples": samples})

    class Steers:
        def __init__(self):
            self.value = 0.0

        def predict(self, image, batch_size):
            # Keras answers [[steering]]; numpy 2 no longer converts a 1-element array of rank 2
            # with float(), which numpy 1 (the pipeline's) did: the rank-0 array gives the same.
            return np.array(self.value)

    throttle = []
    blank = np.zeros((160, 320, 3), dtype=np.uint8)
    for max_speed in [25, 70]:
        model = Steers()
        prediction = nvidia_prediction.NvidiaPrediction(model, max_speed)
        calls = []
        speeds = [0, 5, 12, 20, 24.9, 25.5, 30, 18, 11, 10, 9.5, 15, 26, 40, 71, 65, 9, 3]
        for i, speed in enumerate(speeds):
            model.value = [0.0, 0.3, -0.5, 0.9, -1.2][i % 5]
            steering, value = prediction.predict(blank, stand_in.SimulationDataRecord(vel_kmh=speed))
            calls.append([model.value, speed, value])
        throttle.append({"max_speed_kmh": max_speed, "calls": calls})

    with open(args.out, "w") as f:
        json.dump(
            {
                "source": "se2p/tool-competition-av self_driving/image_processing.py, self_driving/nvidia_prediction.py",
                "opencv": cv2.__version__,
                "numpy": np.__version__,
                "images": images,
                "throttle": throttle,
            },
            f,
            separators=(",", ":"),
        )
        f.write("\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
