#!/usr/bin/env python3
"""Run stgem's own WOGAN (the authors' PyTorch implementation) against our simulator.

Dev-time only: CI never runs this. It needs torch, numpy, dill, shapely, scipy, click and
multiprocess (`pip install torch==2.15.0 dill shapely scipy click multiprocess`: the figures in
docs/results.md were made under torch 2.15.0; under another version the same seeds gave other
figures) and a checkout of stgem (the public `mshaheryarmalik/stgem`, unpacked with
`git archive`; default /work/stgem or $STGEM_DIR). Nothing of stgem is copied here: the script
imports stgem, and reads the SBST 2022 set-up (`wogan_parameters`, `wogan_model_parameters`,
`UniformDependent`, `MaxOOB`, `ScaledDistance`) from the checkout's problems/sbst/sbst.py.

Set-up per seed, as in the paper's SBST experiments but with an execution budget:
  STGEM(sut=WoganSUT, budget=Budget(), objectives=[MaxOOB()], ObjectiveSelectorAll(), steps=[
      Search(budget_threshold={"executions": 60}, Random(UniformDependent)),
      Search(budget_threshold={"executions": 300}, WOGAN(WOGAN_Model(sbst.wogan_model_parameters),
                                                           sbst.wogan_parameters))]).run(seed)
The SUT answers validity with `wogan validate` and executions with `wogan simulate --trace`
(one process per call): stgem's normalised tests in [-1, 1]^5 are denormalised by stgem's own
SUT.descale to curvature in [-0.07, 0.07]^5 (1/m), as problems/sbst/sut.py does, and sent as
{"curvature": [...]} (same road mapping as stgem's test_to_road_points). The output signals are the
trace's per-sample bolp, dist_left_m, dist_right_m, steering_deg, so MaxOOB = 1 - max_bolp.

Each seed writes OUT/<oracle>.stgem.<seed>.jsonl (a header, one `test` record per executed test,
`train` records, a summary) which `wogan report` reads as its own group (algorithm
"stgem-wogan"):
  python3 scripts/reference/stgem_search.py --oracle beamng-ai-proxy --seeds 1-20
  python3 scripts/reference/stgem_search.py --oracle dave2-proxy --seeds 1-20
  wogan report target/stgem/beamng-ai-proxy.stgem.*.jsonl \
      --vs target/effectiveness/beamng-ai-proxy.wogan.*.jsonl --out report/
Options: --stgem DIR, --wogan PATH (default target/release/wogan), --out DIR (target/stgem),
--objective bolp|distance, --torch-threads N (1).

stgem's WOGAN raises GenerationException after 100 invalid candidates in one generation call but
does not import that name, so the run ends with a NameError. stgem is not patched: the seed is
recorded as crashed (summary `crashed: true`, `error`) with the tests it had executed.
"""

import argparse
import copy
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import traceback
import types

ORACLE_DEFAULTS = {
    # oracle: (oob tolerance, speed limit km/h): `wogan simulate`'s defaults, passed explicitly.
    "beamng-ai-proxy": (0.85, 70.0),
    "dave2-proxy": (0.10, 25.0),
}
RANDOM_TESTS = 60
TOTAL_TESTS = 300
CURVATURE_POINTS = 5
CURVATURE_RANGE = 0.07
STEP_M = 15.0
MAP_SIZE_M = 200.0


def parse_seeds(text):
    seeds = []
    for part in text.replace(" ", ",").split(","):
        if not part:
            continue
        if "-" in part:
            lo, hi = part.split("-", 1)
            seeds.extend(range(int(lo), int(hi) + 1))
        else:
            seeds.append(int(part))
    return seeds


def import_stgem(stgem_dir):
    """Imports stgem and the checkout's problems/sbst/sbst.py, working around what is missing."""
    sys.path[:0] = [stgem_dir, os.path.join(stgem_dir, "problems", "sbst")]
    # stgem.objective imports stgem's STL package (a git submodule, absent from the checkout) for
    # FalsifySTL, which the SBST set-up does not use: stub the names it imports.
    try:
        import stl.robustness  # noqa: F401
        import stl.parser  # noqa: F401
    except ImportError:
        for name in ["stl", "stl.robustness", "stl.parser"]:
            sys.modules[name] = types.ModuleType(name)
        sys.modules["stl.parser"].parse = None
        sys.modules["stl"].robustness = sys.modules["stl.robustness"]
        sys.modules["stl"].parser = sys.modules["stl.parser"]
    # sbst.py imports SBSTSUT from sut.py, whose BeamNG imports happen only under __main__;
    # it needs shapely and the checkout's code_pipeline, which are importable. numpy >= 2 lacks
    # np.math, used by util.test_to_road_points, which this script does not call.
    import sbst
    return sbst


def float_betas(params):
    """A deep copy of stgem model parameters with Adam betas as float tuples (current torch
    rejects [0, 0.9])."""
    params = copy.deepcopy(params)

    def fix(d):
        for k, v in d.items():
            if isinstance(v, dict):
                fix(v)
            elif k.endswith("betas") and isinstance(v, (list, tuple)):
                d[k] = tuple(float(x) for x in v)

    fix(params)
    return params


def make_sut_class(SUT, SUTOutput, np):
    class WoganSUT(SUT):
        """stgem SUT answered by the wogan binary (validate / simulate)."""

        def __init__(self, wogan, oracle, tolerance, speed, workdir):
            super().__init__({"curvature_points": CURVATURE_POINTS,
                              "curvature_range": CURVATURE_RANGE,
                              "step_length": STEP_M, "map_size": MAP_SIZE_M})
            self.wogan = wogan
            self.oracle = oracle
            self.tolerance = tolerance
            self.speed = speed
            self.workdir = workdir
            self.input_type = "vector"
            self.idim = CURVATURE_POINTS
            self.input_range = [[-CURVATURE_RANGE, CURVATURE_RANGE]] * self.idim
            # As SBSTSUT: signal outputs bolp, distance_left, distance_right, steering_angle.
            self.output_type = "signal"
            self.odim = 4
            self.outputs = ["bolp", "distance_left", "distance_right", "steering_angle"]
            self.output_range = [[0, 1], [-4, 4], [-4, 4], [-180, 180]]
            self.reset_log()

        def reset_log(self):
            self.executions = []          # per executed test: dict for the run file
            self.invalid_since_last = 0   # invalid validity answers since the last execution
            self.valid_since_last = 0
            self.validity_calls = 0
            self.bolp_mismatches = 0

        def curvature(self, normalised):
            # Exactly as SBSTSUT: stgem's descale (float32 tests stay float32).
            return self.descale(np.asarray(normalised).reshape(1, -1), self.input_range).reshape(-1)

        def _road(self, curvature):
            return json.dumps({"curvature": [float(c) for c in curvature]}) + "\n"

        def validity(self, test):
            self.validity_calls += 1
            answer = subprocess.run([self.wogan, "validate", "--map-size", str(MAP_SIZE_M)],
                                    input=self._road(self.curvature(test)),
                                    capture_output=True, text=True)
            verdict = json.loads(answer.stdout.splitlines()[0])
            if verdict.get("type") != "verdict":
                raise RuntimeError("wogan validate: {}".format(answer.stdout + answer.stderr))
            valid = 1 if verdict["valid"] else 0
            if valid:
                self.valid_since_last += 1
            else:
                self.invalid_since_last += 1
            return valid

        def _execute_test(self, test):
            normalised = np.asarray(test.inputs).reshape(-1)
            curvature = self.curvature(normalised)
            trace_dir = os.path.join(self.workdir, "trace")
            shutil.rmtree(trace_dir, ignore_errors=True)
            answer = subprocess.run(
                [self.wogan, "simulate", "--oracle", self.oracle,
                 "--oob-tolerance", str(self.tolerance), "--speed-limit", str(self.speed),
                 "--map-size", str(MAP_SIZE_M), "--trace", trace_dir],
                input=self._road(curvature), capture_output=True, text=True)
            if answer.returncode != 0:
                raise RuntimeError("wogan simulate: {}".format(answer.stderr))
            result = json.loads(answer.stdout.splitlines()[0])
            record = {"normalised": [float(v) for v in normalised],
                      "curvature": [float(c) for c in curvature],
                      "validity_valid": self.valid_since_last,
                      "validity_invalid": self.invalid_since_last,
                      "result": result}
            self.invalid_since_last = 0
            self.valid_since_last = 0
            self.executions.append(record)
            test.input_denormalized = curvature
            if result.get("outcome") == "INVALID":
                # As SBSTSUT for an invalid road (never reached: stgem checks validity first).
                record["road_points"] = None
                return SUTOutput(None, None, None, "invalid")
            samples = []
            with open(os.path.join(trace_dir, "trace.1.jsonl")) as f:
                for line in f:
                    r = json.loads(line)
                    if r["type"] == "road":
                        record["road_points"] = r["road_points"]
                    elif r["type"] == "sample":
                        samples.append(r)
            if not samples:
                raise RuntimeError("wogan simulate --trace wrote no samples")
            t = np.array([s["t"] for s in samples])
            signals = np.array([[s["bolp"] for s in samples],
                                [s["dist_left_m"] for s in samples],
                                [s["dist_right_m"] for s in samples],
                                [s["steering_deg"] for s in samples]])
            if result.get("max_bolp") is not None and max(signals[0]) != result["max_bolp"]:
                # MaxOOB must see exactly the simulator's max_bolp.
                self.bolp_mismatches += 1
                signals[0, int(np.argmax(signals[0]))] = result["max_bolp"]
            return SUTOutput(signals, t, {"simulation_time": float(t[-1])}, None)

    return WoganSUT


def run_report_diversity(wogan, path, workdir):
    """Diversity of one run as `wogan report` computes it (3 decimals), or None."""
    out = os.path.join(workdir, "report")
    shutil.rmtree(out, ignore_errors=True)
    r = subprocess.run([wogan, "report", path, "--out", out], capture_output=True, text=True)
    if r.returncode not in (0, 1):
        raise RuntimeError("wogan report: " + r.stderr)
    with open(os.path.join(out, "report.md")) as f:
        for line in f:
            if line.startswith("| diversity"):
                value = line.split("|")[2].strip()
                return None if value == "–" else float(value)
    return None


def one_seed(args, sbst, stgem_mods, seed, workdir):
    torch = stgem_mods["torch"]
    STGEM, Search, Budget = stgem_mods["STGEM"], stgem_mods["Search"], stgem_mods["Budget"]
    Random, WOGAN, WOGAN_Model = stgem_mods["Random"], stgem_mods["WOGAN"], stgem_mods["WOGAN_Model"]
    ObjectiveSelectorAll = stgem_mods["ObjectiveSelectorAll"]
    tolerance, speed = ORACLE_DEFAULTS[args.oracle]
    sut = stgem_mods["WoganSUT"](args.wogan, args.oracle, tolerance, speed, workdir)
    objective = sbst.MaxOOB() if args.objective == "bolp" else sbst.ScaledDistance()
    # Fresh copies per run: stgem writes into its parameter dicts.
    wogan_parameters = copy.deepcopy(sbst.wogan_parameters)
    model_parameters = float_betas(sbst.wogan_model_parameters)
    generator = STGEM(
        description="SBST 2022 set-up against wogan simulate {}".format(args.oracle),
        sut=sut,
        budget=Budget(),
        objectives=[objective],
        objective_selector=ObjectiveSelectorAll(),
        steps=[
            Search(budget_threshold={"executions": RANDOM_TESTS}, mode="exhaust_budget",
                   algorithm=Random(model_factory=lambda: sbst.UniformDependent())),
            Search(budget_threshold={"executions": TOTAL_TESTS}, mode="exhaust_budget",
                   algorithm=WOGAN(model_factory=lambda: WOGAN_Model(copy.deepcopy(model_parameters)),
                                   parameters=wogan_parameters)),
        ])
    generator.logger.silent = True
    error = None
    start = time.perf_counter()
    try:
        # STGEM.run(seed) = setup(seed, use_gpu=True): cuda if available (here: cpu), seeds
        # random, numpy and torch, and makes torch deterministic.
        result = generator.run(seed=seed)
    except BaseException as e:  # noqa: BLE001 - record any crash with the tests it had
        if isinstance(e, KeyboardInterrupt):
            raise
        result = None
        error = "{}: {}".format(type(e).__name__, e)
        traceback.print_exc()
    wall_s = time.perf_counter() - start

    repo = generator.test_repository
    n = repo.tests
    if result is not None and len(result.step_results[0].parameters["executed_tests"]) != RANDOM_TESTS:
        raise RuntimeError("the random step executed {} tests, not {}".format(
            len(result.step_results[0].parameters["executed_tests"]), RANDOM_TESTS))
    perf = repo._performance_records
    executions = sut.executions[:n]
    tests, trains = [], []
    invalid_count_mismatches = 0
    for i in range(n):
        ex = executions[i]
        p = perf[i] if i < len(perf) else {}
        res = dict(ex["result"])
        res.pop("type", None)
        res.pop("line", None)
        phase = "random" if i < RANDOM_TESTS else "wogan"
        objective_value = repo._objectives[i][0] if repo._objectives[i] else None
        invalid = p.get("N_invalid_tests_generated", ex["validity_invalid"])
        if invalid != ex["validity_invalid"]:
            # stgem's count and the SUT's own count of invalid answers before this test.
            invalid_count_mismatches += 1
        generated = p.get("N_tests_generated", ex["validity_invalid"] + ex["validity_valid"])
        fitness = res.get("max_bolp") if args.objective == "bolp" else (
            None if objective_value is None else 1.0 - objective_value)
        test = {"type": "test", "id": i + 1, "phase": phase, "fitness": fitness,
                "predicted_fitness": None,
                "invalid_candidates": invalid,
                "ranked_candidates": (generated - invalid) if phase == "wogan" else 0,
                "generation_ms": 1000.0 * p.get("generation_time", 0.0),
                "stgem_objective": objective_value,
                "normalised": ex["normalised"], "curvature": ex["curvature"],
                "road_points": ex.get("road_points")}
        test.update(res)
        tests.append(test)
        losses = p.get("analyzer_loss")
        if phase == "wogan" and losses and any(len(l) > 0 for l in losses):
            trains.append((i, {"type": "train", "before_test": i + 1,
                               "train_ms": 1000.0 * p.get("training_time", 0.0)}))
    # A crashed generation call (e.g. WOGAN's GenerationException) has no finished record; its
    # invalid candidates are the SUT's count since the last execution.
    crashed_invalid = sut.invalid_since_last if error else 0
    failed = sum(1 for t in tests if t["outcome"] == "FAIL")
    invalid_total = sum(t["invalid_candidates"] for t in tests) + crashed_invalid
    header = {
        "type": "header", "version": "stgem-reference", "seed": seed,
        "algorithm": "stgem-wogan", "oracle": args.oracle,
        "fitness": "bolp" if args.objective == "bolp" else "stgem-scaled-distance",
        "config": {
            "max_tests": TOTAL_TESTS, "curvature_points": CURVATURE_POINTS,
            "road": {"map_size_m": MAP_SIZE_M, "step_m": STEP_M},
            "sim": {"oob_tolerance": tolerance, "speed_limit_kmh": speed},
            "stgem": {
                "checkout": os.path.abspath(args.stgem),
                "steps": [{"algorithm": "Random", "model": "UniformDependent",
                           "budget_threshold": {"executions": RANDOM_TESTS}},
                          {"algorithm": "WOGAN", "model": "WOGAN_Model",
                           "budget_threshold": {"executions": TOTAL_TESTS}}],
                "objective": type(objective).__name__,
                "wogan_parameters": wogan_parameters,
                "wogan_model_parameters": sbst.wogan_model_parameters,
                "device": str(generator.device), "torch": torch.__version__,
                "torch_threads": torch.get_num_threads(),
            },
            "wogan_binary": os.path.abspath(args.wogan),
        },
    }
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "{}.stgem.{}.jsonl".format(args.oracle, seed))
    with open(path, "w") as f:
        f.write(json.dumps(header) + "\n")
        train_at = dict(trains)
        for i, t in enumerate(tests):
            if i in train_at:
                f.write(json.dumps(train_at[i]) + "\n")
            f.write(json.dumps(t) + "\n")
    diversity = run_report_diversity(args.wogan, path, workdir)
    summary = {
        "type": "summary", "executed": n, "failed": failed, "invalid_candidates": invalid_total,
        "wall_s": wall_s,
        "generation_s": sum(p.get("generation_time", 0.0) for p in perf[:n]),
        "training_s": sum(p.get("training_time", 0.0) for p in perf[:n]),
        "simulation_s": sum((t.get("execution_ms") or 0.0) for t in tests) / 1000.0,
        "diversity": diversity, "diversity_pairs": "wogan report (3 decimals)",
        "interrupted": False, "crashed": error is not None,
        "validity_calls": sut.validity_calls, "bolp_mismatches": sut.bolp_mismatches,
        "invalid_count_mismatches": invalid_count_mismatches,
    }
    if error:
        summary["error"] = error
    with open(path, "a") as f:
        f.write(json.dumps(summary) + "\n")
    return {"seed": seed, "executed": n, "failures": failed, "diversity": diversity,
            "invalid": invalid_total, "wall_s": wall_s, "error": error, "path": path,
            "bolp_mismatches": sut.bolp_mismatches,
            "invalid_count_mismatches": invalid_count_mismatches}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    repo_root = os.path.dirname(os.path.dirname(here))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--stgem", default=os.environ.get("STGEM_DIR", "/work/stgem"))
    parser.add_argument("--oracle", choices=sorted(ORACLE_DEFAULTS), default="beamng-ai-proxy")
    parser.add_argument("--seeds", default="1-20", help="e.g. 1-20 or 1,3,5")
    parser.add_argument("--out", default=os.path.join(repo_root, "target", "stgem"))
    parser.add_argument("--wogan", default=os.path.join(repo_root, "target", "release", "wogan"))
    parser.add_argument("--objective", choices=["bolp", "distance"], default="bolp")
    parser.add_argument("--torch-threads", type=int, default=1)
    args = parser.parse_args()
    args.wogan = os.path.abspath(args.wogan)
    if not os.access(args.wogan, os.X_OK):
        sys.exit("no wogan binary at {} (--wogan PATH)".format(args.wogan))

    sbst = import_stgem(os.path.abspath(args.stgem))
    import numpy as np
    import torch
    from stgem.generator import STGEM, Search
    from stgem.budget import Budget
    from stgem.algorithm.random.algorithm import Random
    from stgem.algorithm.wogan.algorithm import WOGAN
    from stgem.algorithm.wogan.model import WOGAN_Model
    from stgem.objective_selector import ObjectiveSelectorAll
    from stgem.sut import SUT, SUTOutput
    torch.set_num_threads(args.torch_threads)
    mods = dict(np=np, torch=torch, STGEM=STGEM, Search=Search, Budget=Budget, Random=Random,
                WOGAN=WOGAN, WOGAN_Model=WOGAN_Model, ObjectiveSelectorAll=ObjectiveSelectorAll,
                WoganSUT=make_sut_class(SUT, SUTOutput, np))

    rows = []
    print("seed  executed  failures  diversity  invalid  wall_s  error", flush=True)
    with tempfile.TemporaryDirectory(prefix="stgem-search-") as workdir:
        for seed in parse_seeds(args.seeds):
            r = one_seed(args, sbst, mods, seed, workdir)
            rows.append(r)
            div = "-" if r["diversity"] is None else "{:.3f}".format(r["diversity"])
            note = r["error"] or ("" if r["executed"] == TOTAL_TESTS else "short run")
            if r["invalid_count_mismatches"]:
                note += " invalid-count mismatches: {}".format(r["invalid_count_mismatches"])
            if r["bolp_mismatches"]:
                note += " bolp mismatches: {}".format(r["bolp_mismatches"])
            print("{:4d}  {:8d}  {:8d}  {:>9}  {:7d}  {:6.1f}  {}".format(
                seed, r["executed"], r["failures"], div, r["invalid"], r["wall_s"], note),
                flush=True)
    med = lambda xs: statistics.median(xs) if xs else float("nan")  # noqa: E731

    def medians(label, runs):
        divs = [r["diversity"] for r in runs if r["diversity"] is not None]
        print("median{}: failures {}  diversity {:.3f}  invalid {}  wall_s {:.1f}  ({} runs)".format(
            label, med([r["failures"] for r in runs]), med(divs), med([r["invalid"] for r in runs]),
            med([r["wall_s"] for r in runs]), len(runs)))

    medians("", rows)
    crashed = [r for r in rows if r["error"]]
    if crashed:
        print("crashed: seeds {} ({})".format(" ".join(str(r["seed"]) for r in crashed),
                                             "; ".join(sorted({r["error"] for r in crashed}))))
        medians(" of the runs that finished", [r for r in rows if not r["error"]])

if __name__ == "__main__":
    main()
