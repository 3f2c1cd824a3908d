"""Black-box learners over the nodal values of a tent controller: simulated annealing (the
paper's) and CMA-ES (the baseline), sharing one ``optimize`` loop.

The controller has ``nodes`` nodal values per actuator. With ``period`` set it spans one
period and repeats (its last node equals its first, so the repetition is seamless): the
natural form for locomotion, which the FFT abstraction then compresses; without, it spans the
episode. Candidates are evaluated together on the native vector env (the budget counts every
simulated env step); E = -return.
"""

from __future__ import annotations

import time
from dataclasses import fields
from pathlib import Path
from types import ModuleType

import numpy as np

from learners import annealing, cmaes
from learners.abstraction import abstract, most_compact
from learners.base import Learner, LearnResult, load_checkpoint, save_checkpoint, unknown_params
from learners.controller import TentController, play
from learners.rollout import BatchEvaluator

NUM_ACTUATORS = 6
CONTROLLER_KEYS = {"nodes", "period", "init", "abstraction_threshold", "checkpoint_every"}


def controller_from_vector(vector: np.ndarray, nodes: int, period: float | None,
                           duration: float) -> TentController:
    """The tent controller of a parameter vector (6 * nodes,). Periodic: ``nodes`` free values
    per actuator on [0, period), closed by repeating the first."""
    values = np.asarray(vector, dtype=float).reshape(NUM_ACTUATORS, nodes)
    if period is None:
        return TentController(values, 0.0, duration)
    return TentController(np.concatenate([values, values[:, :1]], axis=1), 0.0, period)


class PeriodicPlayer:
    """Plays a (periodic) controller: u(t mod period)."""

    def __init__(self, controller, period: float | None) -> None:
        self.controller, self.period = controller, period

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.controller(np.mod(t, self.period) if self.period else t)

    def actions(self, dt: float, steps: int) -> np.ndarray:
        return play(self, dt, steps)


class BlackBoxLearner(Learner):
    """Optimises a parameter vector with an ask/tell ``optimizer`` module (``init``, ``ask``,
    ``tell``, ``finished``) configured by ``params_class``. What the vector means is the
    subclass's: ``own_keys`` (its parameters), :meth:`_configure`, :meth:`_x0`,
    :meth:`controller` (vector -> something with ``actions(dt, steps)``), :meth:`_artefacts`.
    This base reads the tent-controller encoding."""

    optimizer: ModuleType
    params_class: type
    population_key: str
    own_keys: set[str] = CONTROLLER_KEYS

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        unknown_params(self.params, self.own_keys | {f.name for f in fields(self.params_class)},
                       self.name)
        self.checkpoint_every = int(self.params.get("checkpoint_every", 10))
        opt_params = {k: v for k, v in self.params.items() if k not in self.own_keys}
        self._configure(opt_params)
        self.opt_params = self.params_class(**opt_params)

    def _configure(self, opt_params: dict) -> None:
        self.nodes = int(self.params.get("nodes", 20))
        period = self.params.get("period", 1.0)
        self.period = None if period is None else float(period)
        self.init_mode = self.params.get("init", "random")
        threshold = self.params.get("abstraction_threshold")
        self.threshold = None if threshold is None else float(threshold)
        if self.nodes < 2 or self.init_mode not in ("random", "relaxed", "half"):
            raise ValueError("nodes must be >= 2 and init one of random, relaxed, half")
        if opt_params.get("smoothing") and "block" not in opt_params:
            opt_params["block"] = self.nodes  # smooth along each actuator's nodes

    @property
    def population(self) -> int:
        return int(getattr(self.opt_params, self.population_key))

    def _x0(self) -> np.ndarray:
        dims = NUM_ACTUATORS * self.nodes
        if self.init_mode == "relaxed":
            return np.zeros(dims)
        if self.init_mode == "half":
            return np.full(dims, 0.5)
        return np.random.default_rng(self.seed).uniform(0.0, 1.0, dims)

    def controller(self, vector: np.ndarray, duration: float) -> PeriodicPlayer:
        tent = controller_from_vector(vector, self.nodes, self.period, duration)
        return PeriodicPlayer(tent, self.period)

    def learn(self, budget_env_steps: int, checkpoint_dir: str | Path | None = None
              ) -> LearnResult:
        evaluator = BatchEvaluator(self.env_id, self.env_kwargs, self.population, self.seed)
        path = Path(checkpoint_dir) / "checkpoint.pkl" if checkpoint_dir else None
        saved = load_checkpoint(path) if path else None
        if saved is None:
            self.log_hparams()
            run = {"state": self.optimizer.init(self.opt_params, self._x0(), self.seed),
                   "env_steps": 0, "wall": 0.0, "best": None, "rounds": 0}
        else:
            run = saved
        start = time.perf_counter() - run["wall"]
        cost = self.population * evaluator.steps
        while (run["env_steps"] + cost <= budget_env_steps
               and not self.optimizer.finished(self.opt_params, run["state"])):
            candidates, state = self.optimizer.ask(self.opt_params, run["state"])
            actions = np.stack([self.controller(c, evaluator.duration).actions(
                evaluator.dt, evaluator.steps) for c in candidates])
            returns, metrics = evaluator.evaluate(actions)
            run["state"] = self.optimizer.tell(self.opt_params, state, candidates, -returns)
            run["env_steps"] += len(candidates) * evaluator.steps
            run["rounds"] += 1
            self._track_best(run, candidates, returns, metrics)
            self._log(run)
            run["wall"] = time.perf_counter() - start
            if path and run["rounds"] % self.checkpoint_every == 0:
                save_checkpoint(path, run)
        if path:
            save_checkpoint(path, run)
        return self._result(run, evaluator)

    def _track_best(self, run: dict, candidates, returns, metrics) -> None:
        k = int(np.argmax(returns))
        if run["best"] is None or returns[k] > run["best"]["return"]:
            run["best"] = {"x": np.array(candidates[k]), "return": float(returns[k]),
                           "metrics": {name: float(v[k]) for name, v in metrics.items()}}

    def _log(self, run: dict) -> None:
        best, step = run["best"], run["env_steps"]
        self.logger.scalar("eval/return", best["return"], step)
        for name, value in best["metrics"].items():
            self.logger.scalar(f"eval/{name}", value, step)
        temperature = getattr(run["state"], "temperature", None)
        if temperature is not None:
            self.logger.scalar("train/temperature", temperature, step)

    def _result(self, run: dict, evaluator: BatchEvaluator) -> LearnResult:
        best = run["best"]
        if best is None:
            raise ValueError(f"budget too small: one round of {self.name} needs "
                             f"{self.population * evaluator.steps} env steps")
        artefacts = self._artefacts(best["x"], evaluator.duration, evaluator)
        metrics = {"eval/return": best["return"],
                   **{f"eval/{k}": v for k, v in best["metrics"].items()}}
        return LearnResult(env_steps=run["env_steps"], wall_seconds=run["wall"],
                           metrics=metrics, artefacts=artefacts)


    def _artefacts(self, x: np.ndarray, duration: float, evaluator: BatchEvaluator) -> dict:
        """The best controller and its FFT abstraction (over the period, or over the whole
        window for a non-periodic controller, sampled 4x finer than its nodes): at the fixed
        ``abstraction_threshold`` if one is given, else the most compact one within 10% of the
        learned objective; with what the abstraction scores (each simulation here is not
        charged to the budget)."""
        tent = controller_from_vector(x, self.nodes, self.period, duration)
        artefacts = {"controller": {"nodes": tent.nodes.tolist(), "t0": tent.t0, "t1": tent.t1,
                                    "periodic": self.period is not None},
                     "parameters": int(x.size),
                     "episode": {"task": evaluator.task, "duration": evaluator.duration}}
        samples = None if self.period is not None else 4 * (tent.num_nodes - 1)

        def score(controllers):
            actions = np.stack([PeriodicPlayer(c, self.period).actions(
                evaluator.dt, evaluator.steps) for c in controllers])
            return evaluator.evaluate(actions)

        if self.threshold is not None:
            chosen = abstract(tent, self.threshold, samples)
        else:
            chosen, artefacts["abstraction_report"] = most_compact(
                tent, lambda cs: -score(cs)[0], samples=samples)
        returns, metrics = score([chosen])
        artefacts["abstraction"] = chosen.to_dict()
        artefacts["abstraction_metrics"] = {
            "eval/return": float(returns[0]), **{f"eval/{k}": float(v[0]) for k, v in
                                                metrics.items()},
            "parameters": chosen.num_parameters, "coefficients": chosen.num_coefficients}
        return artefacts


class AnnealingLearner(BlackBoxLearner):
    """The paper's low-level learner: simulated annealing over the nodal values."""

    name = "annealing"
    optimizer = annealing
    params_class = annealing.AnnealingParams
    population_key = "chains"


class CMAESLearner(BlackBoxLearner):
    """CMA-ES over the same nodal values (baseline)."""

    name = "cmaes"
    optimizer = cmaes
    params_class = cmaes.CMAESParams
    population_key = "popsize"
