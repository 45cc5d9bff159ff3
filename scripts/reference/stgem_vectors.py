#!/usr/bin/env python3
"""Reference vectors for wogan-core, made by the WOGAN authors' own code (stgem).

Development-time only: CI reads the committed JSON files and needs neither torch nor stgem.

    git -C <mirror of mshaheryarmalik/stgem> archive HEAD stgem problems/sbst/sbst.py | tar -x -C /tmp/stgem
    pip install torch numpy
    python3 scripts/reference/stgem_vectors.py --stgem /tmp/stgem --out tests/reference/wogan

Every number written here comes out of stgem's classes (WOGAN_NN networks, WOGAN_Model's
WGAN-GP step, Analyzer_NN's step, the WOGAN algorithm's batch and acceptance code), driven with
the SBST 2022 parameters read from stgem's `problems/sbst/sbst.py`. Random draws made inside
stgem (torch.rand noise and interpolation weights, numpy's bin and test choices) are recorded as
they happen so that the Rust tests can replay them.

Files (one JSON object each):
  networks.json   forward passes of generator (training mode, and inference mode after several
                  training-mode passes), critic and analyzer at the SBST sizes
  wgan_steps.json two WGAN epochs (5 critic steps with gradient penalty, 1 generator step each):
                  the torch.rand draws, every loss, and all weights and batch statistics after
  analyzer_steps.json  analyzer steps (logit MSE + L2, Adam): losses and weights after
  algorithm.json  bin weights and the shift (alpha) schedule, batches built by do_train with the
                  draws it made, the acceptance loop of do_generate_next_test on scripted
                  candidates, and UniformDependent's random walk from its uniform draws
"""

import argparse
import ast
import copy
import json
import os
import sys

import numpy as np
import torch


def sbst_parameters(stgem_dir):
    """The parameter dictionaries of problems/sbst/sbst.py, evaluated without importing the
    module (it imports BeamNG's Python stack at top level)."""
    path = os.path.join(stgem_dir, "problems", "sbst", "sbst.py")
    tree = ast.parse(open(path).read())
    wanted = {"wogan_parameters", "analyzer_mlm_parameters", "wogan_model_parameters", "sut_parameters"}
    namespace = {}
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id in wanted for t in node.targets
        ):
            exec(compile(ast.Module(body=[node], type_ignores=[]), path, "exec"), namespace)
    params = {k: namespace[k] for k in wanted}
    # Current torch wants Adam's betas as a tuple of floats.
    m = params["wogan_model_parameters"]
    for key in ("critic_betas", "generator_betas"):
        m[key] = tuple(float(b) for b in m[key])
    m["analyzer_parameters"]["betas"] = tuple(float(b) for b in m["analyzer_parameters"]["betas"])
    return params


def short(value):
    """Nested lists of numbers with float32 values written in 9 significant digits (exact)."""
    if isinstance(value, torch.Tensor):
        value = value.detach().cpu().numpy()
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return [short(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float("%.9g" % value)
    if isinstance(value, (np.integer,)):
        return int(value)
    return value


def state(module):
    """A module's state_dict as plain lists (PyTorch layout: Linear weight [out, in])."""
    return {k: short(v) for k, v in module.state_dict().items() if not k.endswith("num_batches_tracked")}


class RecordTorchRand:
    """Records every torch.rand result made while active (noise and interpolation weights)."""

    def __init__(self):
        self.draws = []
        self.original = torch.rand

    def __enter__(self):
        def rand(*args, **kwargs):
            t = self.original(*args, **kwargs)
            self.draws.append(t.clone())
            return t

        torch.rand = rand
        return self

    def __exit__(self, *exc):
        torch.rand = self.original


class RecordNumpyChoice:
    """Records numpy.random.choice calls: the population, the probabilities and the result."""

    def __init__(self):
        self.calls = []
        self.original = np.random.choice

    def __enter__(self):
        def choice(a, size=None, replace=True, p=None):
            result = self.original(a, size, replace, p)
            population = list(range(a)) if isinstance(a, (int, np.integer)) else list(a)
            self.calls.append({"population": population, "p": None if p is None else list(p), "result": result})
            return result

        np.random.choice = choice
        return self

    def __exit__(self, *exc):
        np.random.choice = self.original


class Space:
    """The part of stgem's SearchSpace the algorithm and models touch."""

    def __init__(self, dim, valid=None):
        self.input_dimension = dim
        self.objectives = 1
        self.valid = valid

    def is_valid(self, test):
        return 1 if self.valid is None else self.valid(test)


def networks(params, dim):
    from stgem.algorithm.wogan.mlm import AnalyzerNetwork, CriticNetwork, GeneratorNetwork

    m = params["wogan_model_parameters"]
    torch.manual_seed(1)
    g = GeneratorNetwork(output_shape=dim, **m["generator_mlm_parameters"])
    noise_dim = m["generator_mlm_parameters"]["noise_dim"]
    # Non-trivial batch-norm affine parameters, so that gamma and beta are exercised too.
    with torch.no_grad():
        for norm in g.norm:
            norm.weight.uniform_(0.5, 1.5)
            norm.bias.uniform_(-0.3, 0.3)
    initial = state(g)
    noise = 2 * torch.rand(8, noise_dim) - 1
    g.train(True)
    train_out = g(noise)
    # More training-mode passes on batches of several sizes move the running statistics; the
    # small batches make the unbiased variance's n/(n-1) visible.
    passes = [2 * torch.rand(n, noise_dim) - 1 for n in (2, 3, 32, 5)]
    for p in passes:
        g(p)
    g.train(False)
    probe = 2 * torch.rand(6, noise_dim) - 1
    eval_out = g(probe)
    generator = {
        "state": initial,
        "noise": short(noise),
        "train_output": short(train_out),
        "passes": [short(p) for p in passes],
        "state_after_passes": state(g),
        "probe": short(probe),
        "eval_output": short(eval_out),
    }

    torch.manual_seed(2)
    c = CriticNetwork(input_shape=dim, **m["critic_mlm_parameters"])
    x = 2 * torch.rand(7, dim) - 1
    critic = {"state": state(c), "input": short(x), "output": short(c(x))}

    torch.manual_seed(3)
    a_params = m["analyzer_parameters"]["analyzer_mlm_parameters"]
    a = AnalyzerNetwork(input_shape=dim, **a_params)
    x = 2 * torch.rand(7, dim) - 1
    analyzer = {"state": state(a), "input": short(x), "output": short(a(x))}
    return {"dim": dim, "generator": generator, "critic": critic, "analyzer": analyzer}


def wogan_model(params, dim, seed):
    from stgem.algorithm.wogan.model import WOGAN_Model

    torch.manual_seed(seed)
    model = WOGAN_Model(copy.deepcopy(params["wogan_model_parameters"]))
    model.setup(Space(dim), torch.device("cpu"), None)
    return model


def wgan_steps(params, dim):
    model = wogan_model(params, dim, 4)
    g, c = model.modelG, model.modelC
    initial = {"generator": state(g), "critic": state(c)}
    rng = np.random.default_rng(5)
    real = rng.uniform(-1, 1, size=(32, dim)).astype(np.float32)
    settings = dict(params["wogan_model_parameters"]["train_settings"])
    epochs = []
    with RecordTorchRand() as rec:
        for _ in range(2):
            start = len(rec.draws)
            c_losses, g_losses, gps = model.train_with_batch(real, train_settings=settings)
            epochs.append({
                "draws": [short(d) for d in rec.draws[start:]],
                "critic_losses": short(c_losses),
                "generator_losses": short(g_losses),
                "gradient_penalties": short(gps),
            })
    return {
        "dim": dim,
        "critic_steps": settings["critic_steps"],
        "generator_steps": settings["generator_steps"],
        "noise_batch": params["wogan_model_parameters"]["noise_batch_size"],
        "lr": params["wogan_model_parameters"]["generator_lr"],
        "real": short(real),
        "initial": initial,
        "epochs": epochs,
        "after": {"generator": state(g), "critic": state(c)},
        "draw_order": "per epoch: per critic step noise [m, noise_dim] then eps [m, 1]; "
        "per generator step noise [noise_batch, noise_dim]; then the Wasserstein report's noise",
    }


def analyzer_steps(params, dim):
    model = wogan_model(params, dim, 6)
    a = model.modelA
    initial = state(a.modelA)
    rng = np.random.default_rng(7)
    x = rng.uniform(-1, 1, size=(20, dim)).astype(np.float32)
    # Objectives as stgem sees them (1 - max BOLP), including both ends of [0, 1].
    y = rng.uniform(0, 1, size=(20, 1)).astype(np.float32)
    y[0, 0], y[1, 0] = 0.0, 1.0
    losses = [a.train_with_batch(x, y, {}) for _ in range(5)]
    return {
        "dim": dim,
        "lr": params["wogan_model_parameters"]["analyzer_parameters"]["lr"],
        "l2": params["wogan_model_parameters"]["analyzer_parameters"]["l2_regularization_coef"],
        "x": short(x),
        "y": short(y),
        "initial": initial,
        "losses": short(losses),
        "after": state(a.modelA),
    }


class StubModel:
    """Stands in for WOGAN_Model inside the WOGAN algorithm: records the batches it is given,
    and proposes scripted candidates with scripted predictions."""

    def __init__(self, params, candidates=None, predictions=None):
        self.train_settings_init = params["train_settings_init"]
        self.train_settings = params["train_settings"]
        self.batches = []
        self.candidates = list(candidates or [])
        self.predictions = dict(predictions or {})

    def setup(self, *args, **kwargs):
        pass

    def train_analyzer_with_batch(self, *args, **kwargs):
        return [0.0]

    def train_with_batch(self, x, train_settings=None):
        self.batches.append(np.array(x))
        return [0.0], [0.0], [0.0]

    def generate_test(self, n=1):
        return np.array([self.candidates.pop(0) for _ in range(n)])

    def predict_objective(self, tests):
        return np.array([[self.predictions[float(t[0])]] for t in tests])


def repository_with(tests):
    from stgem.sut import SUTInput, SUTOutput
    from stgem.test_repository import TestRepository

    repo = TestRepository()
    for inputs, objective in tests:
        repo.new_record()
        repo.record_input(SUTInput(np.array(inputs), None, None))
        repo.record_output(SUTOutput(None, None, None, None))
        repo.record_objectives([objective])
        repo.finalize_record()
    return repo


def algorithm_vectors(params, dim):
    from stgem.algorithm.wogan.algorithm import WOGAN
    from stgem.sut import SUTInput, SUTOutput

    out = {"dim": dim}
    wp = params["wogan_parameters"]
    bins = wp["bins"]

    def algorithm(model):
        alg = WOGAN(models=[model], parameters=copy.deepcopy(wp))
        alg.setup(Space(dim))
        alg.initialize()
        return alg

    # Bin weights (stgem's bins are of the objective 1 - fitness: bin 0 holds the best tests).
    alg = algorithm(StubModel(params["wogan_model_parameters"]))
    weights = []
    for shift in (0.0, 0.5, 1.5, 3.0):
        with RecordNumpyChoice() as rec:
            alg.bin_sample(1, shift)
        weights.append({"shift": shift, "weights": rec.calls[0]["p"]})
    out["bins"] = bins
    out["bin_weights"] = weights
    # stgem bins the objective 1 - max BOLP; given as [fitness, stgem's bin].
    out["get_bin"] = [[f, alg.get_bin(1 - f)] for f in (0.0, 0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.95, 0.99, 1.0)]

    # do_train over a search: 60 random tests, then WOGAN tests arriving one at a time, with the
    # budget remaining as stgem's executions budget gives it ([60, 300]). Test inputs carry their
    # index in the first component so batches can be read back as indices.
    rng = np.random.default_rng(8)
    fitness = list(rng.uniform(0, 1, size=80))
    fitness[3] = 0.0
    fitness[5] = 1.0
    # Leave the best bins nearly empty so that draws wrap round.
    fitness = [f if f <= 0.8 or i in (5, 17) else f - 0.2 for i, f in enumerate(fitness)]
    objectives = [1 - f for f in fitness]

    def inputs(i):
        return [float(i)] + [0.0] * (dim - 1)

    model = StubModel(params["wogan_model_parameters"])
    alg = algorithm(model)
    shifts = []
    original_bin_sample = alg.bin_sample

    def bin_sample(n, shift):
        shifts.append(shift)
        return original_bin_sample(n, shift)

    alg.bin_sample = bin_sample
    repo = repository_with([(inputs(i), objectives[i]) for i in range(60)])
    rounds = []
    np.random.seed(9)
    with RecordNumpyChoice() as rec:
        for executed in range(60, 72):
            if executed > 60:
                repo.new_record()
                repo.record_input(SUTInput(np.array(inputs(executed - 1)), None, None))
                repo.record_output(SUTOutput(None, None, None, None))
                repo.record_objectives([objectives[executed - 1]])
                repo.finalize_record()
            remaining = 1.0 - (executed - 60) / 240.0
            first_call = len(rec.calls)
            first_batch = len(model.batches)
            first_shift = len(shifts)
            alg.do_train([0], repo, remaining)
            batches = [[int(row[0]) for row in b] for b in model.batches[first_batch:]]
            if not batches:
                continue
            calls = rec.calls[first_call:]
            draws = {"bins": [], "picks": []}
            for call in calls:
                if call["p"] is not None:
                    draws["bins"].extend(int(r) for r in np.atleast_1d(call["result"]))
                else:
                    draws["picks"].append(call["population"].index(call["result"]))
            rounds.append({
                "executed": executed,
                "budget_remaining": remaining,
                "shift": shifts[first_shift],
                "batches": batches,
                "draws": draws,
            })
    out["fitness"] = [float(f) for f in fitness[:72]]
    out["training_rounds"] = rounds
    out["batch_size"] = wp["wgan_batch_size"]
    out["train_delay"] = wp["train_delay"]

    # The acceptance loop on scripted candidates: candidate k has first component k; validity
    # and the predicted objective are given per candidate.
    scenarios = []
    rng = np.random.default_rng(10)
    for name, n, invalid_share, low in (
        ("confident", 40, 0.0, 0.02),
        ("pessimistic", 300, 0.3, 0.6),
        ("mixed", 200, 0.5, 0.2),
        ("too many invalid", 150, 0.9, 0.9),
    ):
        valid = [bool(v) for v in rng.uniform(size=n) >= invalid_share]
        predicted = [float(np.float32(v)) for v in rng.uniform(low, 1.0, size=n)]
        candidates = [[float(k)] + [0.0] * (dim - 1) for k in range(n)]
        model = StubModel(params["wogan_model_parameters"], candidates, {float(k): predicted[k] for k in range(n)})
        alg = WOGAN(models=[model], parameters=copy.deepcopy(wp))
        alg.setup(Space(dim, valid=lambda t: 1 if valid[int(t[0])] else 0))
        alg.initialize()
        repo = repository_with([])
        repo.new_record()
        result = {"name": name, "valid": valid, "predicted_objective": predicted}
        try:
            chosen = alg.do_generate_next_test([0], repo, 1.0)
            perf = repo._performance_records[-1]
            result.update({
                "chosen": int(chosen[0]),
                "generated": int(perf["N_tests_generated"]),
                "invalid": int(perf["N_invalid_tests_generated"]),
            })
        except Exception as e:  # stgem's give-up path raises an undefined name
            result.update({"error": type(e).__name__ + ": " + str(e), "generated": n - len(model.candidates)})
        scenarios.append(result)
    out["fitness_coef"] = wp["fitness_coef"]
    out["invalid_threshold"] = alg.invalid_threshold
    out["acceptance"] = scenarios

    # UniformDependent's random walk, from the uniforms it drew.
    sampler = sbst_uniform_dependent()
    walks = []
    for seed in range(5):
        np.random.seed(100 + seed)
        test = sampler(dim)
        np.random.seed(100 + seed)
        uniforms = [np.random.uniform(-1, 1) for _ in range(dim)]
        walks.append({"uniforms": uniforms, "test": [float(v) for v in test]})
    out["uniform_dependent"] = walks
    return out


def sbst_uniform_dependent():
    """UniformDependent.generate_test from sbst.py, bound to a minimal search space."""
    path = os.path.join(STGEM_DIR, "problems", "sbst", "sbst.py")
    tree = ast.parse(open(path).read())
    node = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "UniformDependent")
    from stgem.algorithm import Model

    namespace = {"Model": Model, "np": np}
    exec(compile(ast.Module(body=[node], type_ignores=[]), path, "exec"), namespace)
    cls = namespace["UniformDependent"]

    def sample(dim):
        model = cls()
        model.search_space = Space(dim)
        return model.generate_test()

    return sample


def main():
    global STGEM_DIR
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--stgem", default=os.environ.get("STGEM_DIR", "/work/stgem"), help="stgem checkout")
    parser.add_argument("--out", default="tests/reference/wogan", help="output directory")
    args = parser.parse_args()
    STGEM_DIR = args.stgem
    sys.path.insert(0, args.stgem)
    torch.set_default_dtype(torch.float32)
    params = sbst_parameters(args.stgem)
    dim = params["sut_parameters"]["curvature_points"]
    os.makedirs(args.out, exist_ok=True)
    files = {
        "networks.json": networks(params, dim),
        "wgan_steps.json": wgan_steps(params, dim),
        "analyzer_steps.json": analyzer_steps(params, dim),
        "algorithm.json": algorithm_vectors(params, dim),
    }
    files["algorithm.json"]["parameters"] = {
        "wogan_parameters": params["wogan_parameters"],
        "wogan_model_parameters": params["wogan_model_parameters"],
    }
    for name, content in files.items():
        path = os.path.join(args.out, name)
        with open(path, "w") as f:
            json.dump(content, f, separators=(",", ":"))
            f.write("\n")
        print(f"{path}: {os.path.getsize(path)} bytes")


STGEM_DIR = None

if __name__ == "__main__":
    main()
