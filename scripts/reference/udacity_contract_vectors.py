#!/usr/bin/env python3
"""Reference vectors for the ONNX driver's `udacity` contract, made by the Udacity course's own
behavioural-cloning code: `utils.py` of naokishibuya/car-behavioral-cloning (`preprocess`: crop
rows 60 to 135 of the simulator's 320 x 160 frame, resize to 200 x 66, RGB to YUV), which its
`drive.py` applies to every frame before `model.predict`.

Development-time only: the Rust tests read the committed JSON and need no Python. Needs a checkout
of naokishibuya/car-behavioral-cloning and numpy and OpenCV (`pip install numpy
opencv-python-headless`):

    python3 scripts/reference/udacity_contract_vectors.py --course /tmp/car-behavioral-cloning

writes tests/reference/udacity_contract.json: for each input image (made by the formula of
dave2_contract_vectors.py, which the Rust test repeats: `pattern` names it, 160 rows x 320 columns
x 3 RGB bytes) the preprocessed frame, whole: one hex string per row (66 rows of 200 YUV pixels).

Every answer is computed by the course's code. utils.py imports `matplotlib.image` for loading
training pictures, which `preprocess` does not use: it is stood in for.
"""

import argparse
import os
import sys
import types

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dave2_contract_vectors import pattern  # noqa: E402


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--course", required=True, help="a checkout of naokishibuya/car-behavioral-cloning")
    parser.add_argument("--out", default=os.path.join(root, "tests/reference/udacity_contract.json"))
    args = parser.parse_args()

    sys.modules.setdefault("matplotlib", types.ModuleType("matplotlib"))
    sys.modules.setdefault("matplotlib.image", types.ModuleType("matplotlib.image"))
    sys.path.insert(0, args.course)
    import cv2
    import utils

    images = []
    for name in ["stripes", "blocks"]:
        out = utils.preprocess(pattern(name))
        assert out.shape == (66, 200, 3) and out.dtype == np.uint8, (out.shape, out.dtype)
        images.append({"pattern": name, "rows": [row.tobytes().hex() for row in out]})

    import json
    with open(args.out, "w") as f:
        json.dump({"source": "naokishibuya/car-behavioral-cloning utils.py preprocess",
                   "opencv": cv2.__version__, "numpy": np.__version__, "images": images},
                  f, separators=(",", ":"))
        f.write("\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
