"""Section `keras`: a Keras DAVE-2 trained on `wogan dataset` frames and tested under the `udacity`
contract (target/keras-loop/, made by scripts/experiments/keras_loop.sh).
"""

import os

from common import out, read_jsonl
from field import compared, runs_of


# ---------------------------------------------------------------------------------------------
# Camera networks trained elsewhere (issue 63): a Keras DAVE-2 trained on `wogan dataset` frames,
# converted without TensorFlow, under the `udacity` contract (scripts/experiments/keras_loop.sh).
def keras_section():
    out()
    out("## A Keras network trained on wogan's frames")
    out()
    base = "target/keras-loop"
    if not os.path.exists(f"{base}/reference.keras.jsonl"):
        out("No runs on this machine: `scripts/experiments/keras_loop.sh`.")
        return
    out("A Keras DAVE-2 (the Udacity course's architecture and training, tensorflow-cpu 2.15) "
        "trained on frames of `wogan dataset` (beamng-ai-proxy on random roads at 40 km/h), "
        "converted by `examples/onnx/keras_to_onnx.py` and driven with `--oracle onnx:` under "
        "`{\"driver\": {\"contract\": \"udacity\"}}`: `scripts/experiments/keras_loop.sh` "
        "(docs/experiments/2026-11-28-keras-loop.md).")
    out()
    out("| driver | reference roads failed (of 300) | lane exits | not moving | time-outs |")
    out("|---|---|---|---|---|")
    for name, label in (("keras", "the Keras DAVE-2 (`udacity` contract)"), ("dave2-proxy", "dave2-proxy")):
        results = [r for r in read_jsonl(f"{base}/reference.{name}.jsonl") if r.get("type") == "result"]
        failed = [r for r in results if r.get("outcome") == "FAIL"]
        reasons = [sum(r.get("reason") == k for r in failed) for k in ("out_of_lane", "not_moving", "timeout")]
        out(f"| {label} | {len(failed)} of {len(results)} | " + " | ".join(str(v) for v in reasons) + " |")
    wogan_runs, random_runs = runs_of(f"{base}/wogan"), runs_of(f"{base}/random")
    if wogan_runs and random_runs:
        rows = compared(wogan_runs, random_runs, ("failures per run", "distinct failures per run", "diversity"))
        out()
        out(f"WOGAN (A, {len(wogan_runs)} runs of 300 tests) against random search (B, "
            f"{len(random_runs)} runs) on it: " + "; ".join(f"{m} {rows.get(m, '–')}" for m in rows) + ".")
