#!/usr/bin/env python3
"""Times one WOGAN iteration of the authors' own implementation (stgem) on this machine.

Dev-time only: CI never runs this. It is the stgem side of the comparison with our
`RAYON_NUM_THREADS=1 cargo bench -p wogan-core --bench iteration`, and needs torch and numpy
(`pip install torch==2.15.0 numpy`, the torch of scripts/reference/stgem_search.py) and a checkout
of stgem (the public `mshaheryarmalik/stgem`, unpacked with `git archive`), given by --stgem:

    nice python3 scripts/reference/stgem_iteration.py --stgem /tmp/stgem --json out.json

Nothing of stgem is copied here. The script imports stgem's WOGAN algorithm, WOGAN_Model,
TestRepository and SearchSpace, and reads the SBST 2022 parameter dictionaries
(`wogan_parameters`, `wogan_model_parameters`) from the checkout's problems/sbst/sbst.py (parsed,
not imported: it imports BeamNG's stack).

Set-up per (threads, N), as our bench: a 5-dim synthetic SUT, valid when sum(t) <= 2.0, whose
objective (stgem minimises it; our model's fitness is the same quantity) is
exp(-sum((t - 0.4)^2)); N tests drawn as sbst.py's UniformDependent draws them (random walk, step
0.05/0.07, clipped to [-1, 1]) and recorded in a stgem TestRepository as executed tests. The
WOGAN algorithm (SBST parameters, one model, CPU, seeded as STGEM.setup_seed seeds: random,
numpy, torch, and torch.use_deterministic_algorithms(True)) then runs stgem's own per-test loop
(the body of Search.run in stgem/generator.py: new_record, Algorithm.train,
Algorithm.generate_next_test, execute, record, finalize_record). The first call trains the
first round (train_settings_init: 3 epochs x 20 analyzer epochs) and is not timed; then
3 x ROUNDS + 2 more tests are generated, and the times are stgem's own per-test records
"training_time" and "generation_time" (perf_counter timers in Algorithm.train and
Algorithm.generate_next_test). budget_remaining is 1.0 at the first training and BUDGET (0.5)
after, so the bin shift is 1.5 (shift function "linear", 0 -> 3).

What one iteration contains in stgem (stgem/algorithm/wogan/algorithm.py, model.py, analyzer.py):
- WOGAN.do_train puts the newest test in its bin, and trains only when train_delay (3) tests have
  been generated since the last training: two of three calls only bin one test. A training round
  (later rounds: WOGAN_Model's train_settings from sbst.py, epochs 2, analyzer_epochs 10,
  critic_steps 5, generator_steps 1) fetches all tests from the repository (TestRepository.get,
  a Python loop over all N) and, per epoch:
  - WOGAN_Model.train_analyzer_with_batch: analyzer_epochs Analyzer_NN.train_with_batch steps, each
    ONE full-batch Adam step on ALL N tests (logit MSE + L2 over the weights); no sub-sampling;
  - the WGAN batch (wgan_batch_size 32): each of the train_delay newest tests (found through
    TestRepository.indices, a fresh list of all N indices each time) joins when its bin is >= a
    bin drawn by bin_sample; the rest by WOGAN.training_sample, which copies every bin's index
    list and rebuilds an (N, 5) array of all tests from TestRepository.get (O(N) per epoch);
  - WOGAN_Model.train_with_batch: 5 WGAN-GP critic steps, 1 generator step (noise_batch_size 32),
    and, as report_wd is True, one more forward pass of both networks for the W. distance.
- WOGAN.do_generate_next_test: N_candidate_tests is 1, so each candidate is one generator call
  (inference mode), one validity call and one analyzer call; the best prediction is kept in a heap
  and accepted once it is <= the target (1 - 0.95 (1 - target), rising from 0) + 1e-4.

Printed per (threads, N): the median training round (over the iterations that trained), the
median generation, the median iteration with training (training round + generation of the same
test: what our bench times) in wall time and in this process's CPU time (time.process_time: less
moved by other processes on a shared machine; with 2 threads it adds both threads' time), and
the mean wall cost per test over all iterations (training every third test). The training round
is split into analyzer steps, WGAN steps (timers around the model's two training methods) and
the rest (data handling in WOGAN.do_train). `--json PATH` writes all figures (with every
per-test time) and the load averages.

On a busy machine, 2 threads can be many times slower than 1: torch's OpenMP threads spin while
waiting for each other, and a descheduled partner makes every parallel region wait. Setting
OMP_WAIT_POLICY=PASSIVE in the environment (read when torch loads) shows how much of a
2-thread figure is that waiting.
"""

import argparse
import ast
import copy
import json
import os
import platform
import random
import statistics
import sys
import time

DIM = 5


def sbst_parameters(stgem_dir):
    """wogan_parameters and wogan_model_parameters of problems/sbst/sbst.py, evaluated without
    importing the module; Adam betas as float tuples (current torch rejects [0, 0.9])."""
    path = os.path.join(stgem_dir, "problems", "sbst", "sbst.py")
    with open(path) as f:
        tree = ast.parse(f.read(), path)
    wanted = {"wogan_parameters", "analyzer_mlm_parameters", "wogan_model_parameters"}
    namespace = {}
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id in wanted for t in node.targets):
            exec(compile(ast.Module(body=[node], type_ignores=[]), path, "exec"), namespace)
    missing = wanted - set(namespace)
    if missing:
        sys.exit("{}: no {}".format(path, ", ".join(sorted(missing))))
    model = copy.deepcopy(namespace["wogan_model_parameters"])
    for key in ("critic_betas", "generator_betas"):
        model[key] = tuple(float(b) for b in model[key])
    model["analyzer_parameters"]["betas"] = tuple(
        float(b) for b in model["analyzer_parameters"]["betas"])
    return copy.deepcopy(namespace["wogan_parameters"]), model


def objective(np, t):
    """The bench's synthetic fitness: a smooth bump at 0.4 (stgem minimises it)."""
    return float(np.exp(-np.sum((np.asarray(t, dtype=np.float64) - 0.4) ** 2)))


def uniform_dependent(np):
    """A random walk as sbst.py's UniformDependent draws it (numpy's global generator)."""
    t = np.zeros(DIM)
    t[0] = np.random.uniform(-1, 1)
    for i in range(1, DIM):
        t[i] = max(-1, min(1, t[i - 1] + (0.05 / 0.07) * np.random.uniform(-1, 1)))
    return t


class Timed:
    """Wraps a bound method and adds its wall time to a total."""

    def __init__(self, method):
        self.method = method
        self.total = 0.0

    def __call__(self, *args, **kwargs):
        start = time.perf_counter()
        try:
            return self.method(*args, **kwargs)
        finally:
            self.total += time.perf_counter() - start


def measure(mods, params, n, threads, rounds, seed, budget, deterministic):
    np, torch = mods["np"], mods["torch"]
    SUT, SUTInput, SUTOutput = mods["SUT"], mods["SUTInput"], mods["SUTOutput"]
    torch.set_num_threads(threads)
    # As STGEM.setup_seed with a seed.
    torch.use_deterministic_algorithms(mode=deterministic)
    random.seed(seed)
    np.random.seed(seed)
    torch.manual_seed(seed)

    class Synthetic(SUT):
        """The bench's SUT: validity is a half-space."""

        def __init__(self):
            super().__init__({})
            self.idim = DIM
            self.odim = 1

        def validity(self, test):
            return 1 if float(np.sum(test)) <= 2.0 else 0

    sut = Synthetic()
    space = mods["SearchSpace"]()
    space.setup(sut=sut, objectives=[objective], rng=np.random.RandomState(seed=seed))
    repo = mods["TestRepository"]()

    def execute(test):
        f = objective(np, test)
        repo.record_input(SUTInput(test, None, None))
        repo.record_output(SUTOutput(np.array([[f]]), None, None, None))
        repo.record_objectives([f])
        repo.finalize_record()

    for _ in range(n):
        repo.new_record()
        execute(uniform_dependent(np))

    wogan_parameters, model_parameters = params
    algorithm = mods["WOGAN"](
        model_factory=lambda: mods["WOGAN_Model"](copy.deepcopy(model_parameters)),
        parameters=copy.deepcopy(wogan_parameters))
    algorithm.setup(search_space=space, device=torch.device("cpu"), logger=None)
    algorithm.initialize()
    model = algorithm.models[0]
    analyzer_t = Timed(model.train_analyzer_with_batch)
    wgan_t = Timed(model.train_with_batch)
    model.train_analyzer_with_batch = analyzer_t
    model.train_with_batch = wgan_t

    per_test = []
    remaining = 1.0
    # The first training round (all tests binned, 3 x 20) and 3 * rounds + 2 later tests.
    for i in range(1 + 3 * rounds + 2):
        performance = repo.new_record()
        a0, w0 = analyzer_t.total, wgan_t.total
        cpu0 = time.process_time()
        algorithm.train([0], repo, remaining)
        cpu1 = time.process_time()
        trained = model.train_with_batch.total > w0
        remaining = budget
        try:
            test = algorithm.generate_next_test([0], repo, remaining)
        except NameError as e:
            # stgem raises GenerationException after 100 invalid candidates without importing it.
            raise SystemExit("N={}: stgem's generation failed ({}): the generator's candidates "
                             "were invalid".format(n, e))
        cpu2 = time.process_time()
        execute(np.asarray(test))
        if i == 0:
            continue
        per_test.append({
            "training_s": performance.obtain("training_time"),
            "generation_s": performance.obtain("generation_time"),
            "trained": trained,
            "training_cpu_s": cpu1 - cpu0,
            "generation_cpu_s": cpu2 - cpu1,
            "analyzer_s": analyzer_t.total - a0,
            "wgan_s": wgan_t.total - w0,
            "candidates": performance.obtain("N_tests_generated"),
            "invalid": performance.obtain("N_invalid_tests_generated"),
        })

    trained = [r for r in per_test if r["trained"]]
    med = statistics.median
    ms = lambda s: round(1000.0 * s, 3)  # noqa: E731
    train = [r["training_s"] for r in trained]
    return {
        "n_start": n, "n_end": repo.tests, "threads": threads, "rounds": len(trained),
        "tests": len(per_test),
        "train_round_ms": ms(med(train)),
        "train_round_min_ms": ms(min(train)),
        "analyzer_ms": ms(med([r["analyzer_s"] for r in trained])),
        "wgan_ms": ms(med([r["wgan_s"] for r in trained])),
        "data_ms": ms(med([r["training_s"] - r["analyzer_s"] - r["wgan_s"] for r in trained])),
        "generation_ms": ms(med([r["generation_s"] for r in per_test])),
        "candidates": med([r["candidates"] for r in per_test]),
        "iteration_ms": ms(med([r["training_s"] + r["generation_s"] for r in trained])),
        "iteration_cpu_ms": ms(med([r["training_cpu_s"] + r["generation_cpu_s"]
                                    for r in trained])),
        "per_test_mean_ms": ms(statistics.mean(
            [r["training_s"] + r["generation_s"] for r in per_test])),
        "per_test": per_test,
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--stgem", required=True, help="an unpacked stgem checkout")
    parser.add_argument("--sizes", default="300,3000,30000", help="tests in the model (N)")
    parser.add_argument("--threads", default="1,2", help="torch.set_num_threads values")
    parser.add_argument("--rounds", type=int, default=10,
                        help="timed training rounds per size (3 tests each)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--budget", type=float, default=0.5,
                        help="budget_remaining after the first training (bin shift 3 (1 - B))")
    parser.add_argument("--nondeterministic", action="store_true",
                        help="leave torch.use_deterministic_algorithms off (stgem turns it on "
                             "whenever a seed is given)")
    parser.add_argument("--json", help="write the figures to this file")
    args = parser.parse_args()
    try:
        sizes = [int(s) for s in args.sizes.split(",") if s]
        threads = [int(s) for s in args.threads.split(",") if s]
    except ValueError:
        sys.exit("--sizes and --threads take comma-separated integers")
    if not sizes or min(sizes) < 1 or not threads or min(threads) < 1 or args.rounds < 1:
        sys.exit("--sizes, --threads and --rounds must be positive")
    if not 0.0 < args.budget <= 1.0:
        sys.exit("--budget must be in (0, 1]")
    stgem_dir = os.path.abspath(args.stgem)
    if not os.path.isfile(os.path.join(stgem_dir, "stgem", "algorithm", "wogan", "algorithm.py")):
        sys.exit("--stgem {}: no stgem/algorithm/wogan/algorithm.py".format(stgem_dir))
    params = sbst_parameters(stgem_dir)

    sys.path.insert(0, stgem_dir)
    import numpy as np
    import torch
    from stgem.algorithm.wogan.algorithm import WOGAN
    from stgem.algorithm.wogan.model import WOGAN_Model
    from stgem.sut import SUT, SUTInput, SUTOutput, SearchSpace
    from stgem.test_repository import TestRepository
    mods = dict(np=np, torch=torch, WOGAN=WOGAN, WOGAN_Model=WOGAN_Model, SUT=SUT,
                SUTInput=SUTInput, SUTOutput=SUTOutput, SearchSpace=SearchSpace,
                TestRepository=TestRepository)

    load_before = os.getloadavg()
    started = time.time()
    results = []
    print("threads       N  rounds  train_round  (analyzer  wgan  data)  generation  cands  "
          "iteration  (cpu)  per_test_mean   (ms)", flush=True)
    for t in threads:
        for n in sizes:
            r = measure(mods, params, n, t, args.rounds, args.seed, args.budget,
                        not args.nondeterministic)
            results.append(r)
            print("{:7d}  {:6d}  {:6d}  {:11.1f}  ({:8.1f}  {:4.1f}  {:4.1f})  {:10.2f}  {:5.0f}  "
                  "{:9.1f}  {:5.0f}  {:13.1f}".format(
                      t, n, r["rounds"], r["train_round_ms"], r["analyzer_ms"], r["wgan_ms"],
                      r["data_ms"], r["generation_ms"], r["candidates"], r["iteration_ms"],
                      r["iteration_cpu_ms"],
                      r["per_test_mean_ms"]), flush=True)
    load_after = os.getloadavg()
    print("load average before {:.2f} {:.2f} {:.2f}, after {:.2f} {:.2f} {:.2f}".format(
        *load_before, *load_after))
    if args.json:
        summary = {
            "stgem": stgem_dir, "torch": torch.__version__, "numpy": np.__version__,
            "python": platform.python_version(), "seed": args.seed, "budget": args.budget,
            "deterministic": not args.nondeterministic, "rounds": args.rounds,
            "load_before": load_before, "load_after": load_after,
            "wall_s": round(time.time() - started, 1), "results": results,
        }
        with open(args.json, "w") as f:
            json.dump(summary, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
