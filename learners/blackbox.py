"""Black-box learners over the nodal values of a tent controller: simulated annealing (the
paper's) and CMA-ES (the baseline), sharing one ``optimize`` loop.

The controller has ``nodes`` nodal values per actuator. With ``period`` set it spans one
period and repeats (its last node equals its first, so the repetition is seamless): the
natural form for locomotion, which the FFT abstraction then compresses; without, it spans the
episode. Candidates are evaluated together on the native vector env (the budget counts every
simulated env step); E = -return.

With ``refine`` set, the learner goes on as the paper's abstraction suggests: the learned
controller's FFT abstraction at ``refine.threshold`` (a handful of harmonics) becomes the
starting point of a second search over its frequency parameters (the kept harmonics' means
and complex coefficients; :meth:`AbstractController.frequency_parameters`), with
``refine.share`` of the budget. The result is a compact controller (tens of parameters,
not actuators x nodes) that the repertoire keeps; what plain truncation kept is reported beside it.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, fields, replace
from enum import StrEnum
from pathlib import Path
from types import ModuleType
from typing import Any

import gymnasium as gym
import numpy as np

from . import checkpoint_data
from .agents import OpenLoopAgent
from .base import (
    BudgetError,
    Learner,
    LearnResult,
    UntrustedPickle,
    check_memory,
    episode_timing,
    load_checkpoint,
    save_checkpoint,
    typed_params,
    unknown_params,
)
from .controllers.abstraction import AbstractController, abstract, most_compact
from .controllers.tent import TentController, play
from .optimizers import annealing, cmaes
from .rollout import START_STATES, BatchEvaluator

REFINE_KEYS = {"share", "threshold"}


class ResultFrom(StrEnum):
    """Which controller a run reports: ``result_from`` of its artefacts (written as the value,
    so result.json holds the same words as before the enum): the learning phase's best, or
    the refined FFT abstraction of it."""

    LEARNED = "learned"
    REFINED_ABSTRACTION = "refined abstraction"


@dataclass(frozen=True)
class ControllerParams:
    """The tent-controller encoding and the loop's own settings (the rest of a black-box
    learner's params go to its optimiser's params class).

    Attributes:
        nodes: nodal values per actuator.
        period: s, the controller's period (None: it spans the episode).
        init: starting values: ``"random"``, ``"relaxed"`` (0) or ``"half"`` (0.5).
        abstraction_threshold: the FFT threshold of the abstraction kept (None: the most
            compact one within 10% of the learned objective).
        checkpoint_every: rounds between checkpoints.
        refine: the refinement phase's settings (see :meth:`BlackBoxLearner._configure_refine`).
        start_states: seeded start states every candidate is scored over.
    """

    nodes: int = 20
    period: float | None = 1.0
    init: str = "random"
    abstraction_threshold: float | None = None
    checkpoint_every: int = 10
    refine: dict | None = None
    start_states: int = START_STATES

    def __post_init__(self) -> None:
        if self.nodes < 2 or self.init not in ("random", "relaxed", "half"):
            raise ValueError("nodes must be >= 2 and init one of random, relaxed, half")
        if self.checkpoint_every < 1 or self.start_states < 1:
            raise ValueError("checkpoint_every and start_states must be >= 1")
        if self.period is not None and not 0 < self.period < math.inf:
            raise ValueError(f"period must be a finite number of seconds > 0 (or null: the "
                             f"episode), got {self.period!r}")


def controller_from_vector(vector: np.ndarray, nodes: int, period: float | None,
                           duration: float) -> TentController:
    """The tent controller of a parameter vector (A * nodes,), A actuators (the env's action
    size). Periodic: ``nodes`` free values per actuator on [0, period), closed by repeating
    the first."""
    values = np.asarray(vector, dtype=float).reshape(-1, nodes)
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


@dataclass
class Phase:
    """One optimisation: its optimiser params and state, the best candidate so far
    ({``x``, ``return``, ``metrics``}), the abstraction whose frequency parameters it searches
    (refining; None for the nodal search) and, refining, the metrics it started from."""

    params: Any
    state: Any
    best: dict | None = None
    support: Any = None
    start: dict | None = None


@dataclass
class Run:
    """A learner's progress (what a checkpoint holds): its phases and the counters."""

    phases: list[Phase] = field(default_factory=list)
    env_steps: int = 0
    wall: float = 0.0
    rounds: int = 0

    @classmethod
    def from_checkpoint(cls, saved) -> Run:
        """A saved run; checkpoints from before these dataclasses were dicts."""
        if isinstance(saved, Run):
            return saved
        phases = saved.get("phases") or [{"params": saved["params"], "state": saved["state"],
                                           "best": saved.get("best")}]
        return cls([Phase(p["params"], p["state"], p.get("best"), p.get("support"),
                          p.get("start")) for p in phases],
                   saved["env_steps"], saved["wall"], saved["rounds"])


class BlackBoxLearner(Learner):
    """Optimises a parameter vector with an ask/tell ``optimizer`` module (``init``, ``ask``,
    ``tell``, ``finished``, ``population``, ``metrics``, ``fit_encoding``,
    ``refine_options``; see :mod:`animat.learners.optimizers.annealing`) configured by
    ``params_class``. What
    the vector means is the subclass's: ``own_keys`` (its parameters), :meth:`_configure`,
    :meth:`_x0`, :meth:`controller` (vector -> something with ``actions(dt, steps)``),
    :meth:`_artefacts`. This base reads the tent-controller encoding; nothing here is
    specific to one optimiser."""

    optimizer: ModuleType
    params_class: type
    own_params: type = ControllerParams

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        owner = f"learner {self.name!r}"
        own_names = {f.name for f in fields(self.own_params)}
        unknown_params(self.params, own_names | {f.name for f in fields(self.params_class)},
                       owner)
        self.own = typed_params(self.own_params,
                                {k: v for k, v in self.params.items() if k in own_names}, owner)
        self.checkpoint_every = self.own.checkpoint_every
        self._configure()
        opt_params = {k: v for k, v in self.params.items() if k not in own_names}
        self.opt_params = typed_params(self.params_class, self._fit_encoding(opt_params), owner)
        self.refine = self._configure_refine(getattr(self.own, "refine", None))

    def _configure(self) -> None:
        """Read the encoding's settings off ``self.own``."""
        self.nodes = self.own.nodes
        self.period = None if self.own.period is None else float(self.own.period)
        self.init_mode = self.own.init
        threshold = self.own.abstraction_threshold
        self.threshold = None if threshold is None else float(threshold)

    def _fit_encoding(self, opt_params: dict) -> dict:
        """The optimiser's options for this encoding (blocks of ``nodes`` values per
        actuator)."""
        return self.optimizer.fit_encoding(opt_params, self.nodes)

    def _configure_refine(self, refine: dict | None) -> dict | None:
        """``refine``: {``share`` (the fraction of the run's budget it gets, in (0, 1)),
        ``threshold`` (the FFT threshold of the abstraction refined, default 0.5), and
        optimiser parameters that differ in the frequency space (e.g. ``step_size``)};
        smoothing is off there."""
        if refine is None:
            return None
        if not isinstance(refine, dict):
            raise ValueError(f"learner {self.name!r}: refine must be a mapping, got {refine!r}")
        if "env_steps" in refine:
            raise ValueError(f"learner {self.name!r}: refine.env_steps is gone: give "
                             "refine.share, the fraction of budget.env_steps it gets (e.g. 0.25)")
        option_names = {f.name for f in fields(self.params_class)}
        unknown_params(refine, REFINE_KEYS | option_names, f"{self.name}.refine")
        share, threshold = refine.get("share"), refine.get("threshold", 0.5)
        if not (type(share) in (float, int) and 0.0 < share < 1.0
                and type(threshold) in (float, int) and 0.0 <= threshold < 1.0):
            raise ValueError(f"learner {self.name!r}: refine needs share in (0, 1) and "
                             f"threshold in [0, 1); got {share!r}, {threshold!r}")
        options = self.optimizer.refine_options(
            {k: v for k, v in refine.items() if k not in REFINE_KEYS})
        params = replace(self.opt_params, **options)
        # the population stays: one batch width for both phases, every row a candidate
        if self.optimizer.population(params) != self.population:
            raise ValueError(f"learner {self.name!r}: refine cannot change the population "
                             f"({self.population})")
        return {"share": float(share), "threshold": threshold, "params": params}

    def _env_sizes(self) -> tuple[int, int]:
        """(env steps in an episode, the env's actuators), from the env built once."""
        if getattr(self, "_sizes", None) is None:
            env = gym.make(self.env_id, **self.env_kwargs)
            try:
                self._sizes = (int(env.unwrapped.episode_steps), int(env.action_space.shape[0]))
            finally:
                env.close()
        return self._sizes

    def _episode_cost(self) -> int:
        """Env steps to score one candidate: an episode from every start state."""
        return self._env_sizes()[0] * int(self.own.start_states)

    def _genes(self, actuators: int) -> tuple[int, str]:
        """The size of a candidate of the encoding (``actuators``: the env's), and what makes
        it, for a message: ``nodes`` values per actuator here."""
        return actuators * self.nodes, f"nodes {self.nodes} x {actuators} actuators"

    def _check_memory(self, population: int) -> None:
        """ValueError in one line (:func:`~animat.learners.base.check_memory`) when a round
        of ``population`` candidates would not fit in this machine's memory: the optimiser's
        state over their genes, and their action sequences (float32) over every start
        state, stacked, then repeated for the batch."""
        steps, actuators = self._env_sizes()
        dims, made_of = self._genes(actuators)
        params = self.optimizer.with_population(self.opt_params, population)
        need = (self.optimizer.state_bytes(params, dims)
                + 4 * population * (1 + int(self.own.start_states)) * steps * actuators)
        check_memory(need, f"learner {self.name!r}: {made_of} ({dims:,} genes) for "
                           f"{population} candidates")

    def plan(self, budget_env_steps: int) -> dict:
        """How this run spends ``budget_env_steps``: the learning phase gets the budget less
        the refinement's share; a population that one round of the learning phase cannot
        afford shrinks to what it can (never below the optimiser's minimum). Raises
        :class:`BudgetError` when even that does not fit."""
        cost = self._episode_cost()
        refine = int(round(budget_env_steps * self.refine["share"])) if self.refine else 0
        learn = budget_env_steps - refine
        smallest = int(self.optimizer.MIN_POPULATION)
        if learn < smallest * cost:
            phase = f" (its budget less refine.share {self.refine['share']:g})" if refine else ""
            raise BudgetError(
                f"{budget_env_steps} is less than one round of {self.name}: "
                f"the learning phase{phase} needs at least {smallest * cost} env steps "
                f"({smallest} candidates x {cost} env steps each)")
        population = min(self.population, learn // cost)
        self._check_memory(population)
        return {"episode_cost": cost, "learn_env_steps": learn, "refine_env_steps": refine,
                "population": population, "configured_population": self.population}

    def scored_episodes(self) -> int:
        return int(self.own.start_states)

    def check_budget(self, budget_env_steps: int) -> None:
        self.plan(budget_env_steps)

    def agent(self, artefacts: dict, folder: Path) -> OpenLoopAgent:
        """The controller the run reported (``result_from``: the learned one, or its refined
        abstraction), played open loop."""
        dt, steps = episode_timing(self.env_id, self.env_kwargs)
        return OpenLoopAgent(self._player(artefacts), dt, steps, self.env_id, self.env_kwargs)

    def _player(self, artefacts: dict):
        """The reported controller of ``artefacts`` (:class:`ResultFrom`; a run without
        ``result_from`` reports the learned one), as a player."""
        result_from = ResultFrom(artefacts.get("result_from", ResultFrom.LEARNED))
        if result_from is ResultFrom.REFINED_ABSTRACTION:
            return PeriodicPlayer(AbstractController.from_dict(artefacts["abstraction"]),
                                  self.period)
        nodes = artefacts["controller"]
        return PeriodicPlayer(TentController(np.array(nodes["nodes"]), nodes["t0"],
                                             nodes["t1"]), self.period)

    def _fit_population(self, size: int) -> None:
        """Use ``size`` candidates per round in both phases."""
        if size == self.population:
            return
        self.opt_params = self.optimizer.with_population(self.opt_params, size)
        if self.refine:
            self.refine["params"] = self.optimizer.with_population(self.refine["params"], size)

    @property
    def population(self) -> int:
        return int(self.optimizer.population(self.opt_params))

    def _x0(self, num_actuators: int) -> np.ndarray:
        dims = num_actuators * self.nodes
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
        """Phase "learn" searches the encoding of :meth:`controller` with the budget less
        the refinement's share; phase "refine" (when configured) then searches the frequency
        parameters of the learned controller's FFT abstraction with the rest (see
        :meth:`plan`)."""
        plan = self.plan(budget_env_steps)
        self._fit_population(plan["population"])
        evaluator = BatchEvaluator(self.env_id, self.env_kwargs, self.population, self.seed,
                                   self.own.start_states)
        path, saved = self._saved(checkpoint_dir)
        if saved is not None:
            if isinstance(saved, dict) and "phases" not in saved:  # before phases existed
                saved["params"] = self.opt_params
            run = Run.from_checkpoint(saved)
        else:
            self.log_hparams()
            run = Run([self._phase(self.opt_params, self._x0(evaluator.action_size),
                                   self.seed)])
        start = time.perf_counter() - run.wall
        self._run_phase(run, 0, evaluator, plan["learn_env_steps"], path, start)
        learned = run.phases[0].best
        if (self.refine and learned is not None and len(run.phases) == 1
                and run.env_steps + evaluator.episode_cost <= budget_env_steps):
            self._start_refining(run, learned["x"], evaluator)
        if len(run.phases) > 1:
            self._run_phase(run, 1, evaluator, budget_env_steps, path, start)
        if path:
            self._save(path, run)
        result = self._result(run, evaluator)
        result.artefacts["budget"] = {**plan, "population": self.population,
                                      "phases_run": len(run.phases)}
        return result

    def _saved(self, checkpoint_dir: str | Path | None) -> tuple[Path | None, object]:
        """Where the run's checkpoint goes, and what is saved there (None: nothing yet).
        ``checkpoint.json`` is data (:mod:`animat.learners.checkpoint_data`); an older
        version's ``checkpoint.pkl`` is read (and the run goes on pickling) only when the
        caller trusts the folder: unpickling runs whatever its writer put in it."""
        if not checkpoint_dir:
            return None, None
        folder = Path(checkpoint_dir)
        legacy, path = folder / "checkpoint.pkl", folder / "checkpoint.json"
        if path.exists() or not legacy.exists():
            return path, checkpoint_data.load(path)
        if not self.trust_pickles:
            raise UntrustedPickle(legacy)
        return legacy, load_checkpoint(legacy)

    @staticmethod
    def _save(path: Path, run: Run) -> None:
        if path.suffix == ".pkl":  # a trusted older run goes on as it was saved
            save_checkpoint(path, run)
        else:
            checkpoint_data.save(path, run)

    def _start_refining(self, run: Run, x: np.ndarray, evaluator: BatchEvaluator) -> None:
        """Phase 2 starts at the truncated abstraction, which is scored first (one episode,
        charged), so that the refined controller is never worse than the one it came from."""
        support = self._abstract(x, evaluator.duration, self.refine["threshold"])
        x0 = support.frequency_parameters()
        phase = self._phase(self.refine["params"], x0, self.seed + 1, support)
        player = self._decode(phase, x0, evaluator.duration)
        returns, metrics = evaluator.evaluate_players([player])
        run.env_steps += evaluator.episode_cost
        self._track_best(phase, [x0], returns, metrics)
        phase.start = _eval_metrics(phase.best)
        run.phases.append(phase)

    def _phase(self, params, x0: np.ndarray, seed: int, support=None) -> Phase:
        return Phase(params, self.optimizer.init(params, x0, seed), support=support)

    def _decode(self, phase: Phase, vector: np.ndarray, duration: float):
        if phase.support is None:
            return self.controller(vector, duration)
        return PeriodicPlayer(phase.support.with_frequency_parameters(vector), self.period)

    def _run_phase(self, run: Run, index: int, evaluator: BatchEvaluator, limit: int,
                   path: Path | None, start: float) -> None:
        """ask -> simulate -> tell until ``limit`` env steps or the optimiser's stopping rule."""
        phase = run.phases[index]
        params = phase.params
        cost = int(self.optimizer.population(params)) * evaluator.episode_cost
        while (run.env_steps + cost <= limit
               and not self.optimizer.finished(params, phase.state)):
            candidates, state = self.optimizer.ask(params, phase.state)
            returns, metrics = evaluator.evaluate_players(
                [self._decode(phase, c, evaluator.duration) for c in candidates])
            phase.state = self.optimizer.tell(params, state, candidates, -returns)
            run.env_steps += len(candidates) * evaluator.episode_cost
            run.rounds += 1
            self._track_best(phase, candidates, returns, metrics)
            self._log(run, phase, returns, metrics)
            run.wall = time.perf_counter() - start
            if path and run.rounds % self.checkpoint_every == 0:
                self._save(path, run)

    @staticmethod
    def _track_best(phase: Phase, candidates, returns, metrics) -> None:
        """The one place the best candidate is kept: its vector, return and metrics."""
        k = int(np.argmax(returns))
        if phase.best is None or returns[k] > phase.best["return"]:
            phase.best = {"x": np.array(candidates[k]), "return": float(returns[k]),
                          "metrics": {name: float(v[k]) for name, v in metrics.items()}}

    @staticmethod
    def _overall_best(run: Run) -> dict | None:
        bests = [p.best for p in run.phases if p.best is not None]
        return max(bests, key=lambda b: b["return"]) if bests else None

    def _log(self, run: Run, phase: Phase, returns: np.ndarray, metrics: dict) -> None:
        """Like every learner, ``eval/*``: the current incumbent (the best candidate of this
        round, scored over the evaluation start states), as PPO logs its current policy;
        ``best/*``: the best so far (of either phase), which is what the run returns; and the
        optimiser's own ``train/*`` scalars."""
        k, best, step = int(np.argmax(returns)), self._overall_best(run), run.env_steps
        self.logger.scalar("eval/return", float(returns[k]), step)
        for name, values in metrics.items():
            self.logger.scalar(f"eval/{name}", float(values[k]), step)
        self.logger.scalar("best/return", best["return"], step)
        for name, value in best["metrics"].items():
            self.logger.scalar(f"best/{name}", value, step)
        for name, value in self.optimizer.metrics(phase.params, phase.state).items():
            self.logger.scalar(f"train/{name}", value, step)

    def _result(self, run: Run, evaluator: BatchEvaluator) -> LearnResult:
        learned, best = run.phases[0].best, self._overall_best(run)
        if learned is None:
            raise ValueError(f"budget too small: one round of {self.name} needs "
                             f"{self.population * evaluator.episode_cost} env steps")
        artefacts = self._artefacts(learned["x"], evaluator.duration, evaluator)
        artefacts["learned_metrics"] = _eval_metrics(learned)
        if len(run.phases) > 1:
            artefacts.update(self._refined_artefacts(run.phases[1], artefacts))
        result_from = ResultFrom.LEARNED if best is learned else ResultFrom.REFINED_ABSTRACTION
        artefacts["result_from"] = result_from.value
        return LearnResult(env_steps=run.env_steps, wall_seconds=run.wall,
                           metrics=_eval_metrics(best), artefacts=artefacts)

    def _abstract(self, x: np.ndarray, duration: float, threshold: float):
        """The FFT abstraction of the tent controller ``x`` at ``threshold`` (over the period,
        or over the whole window for a non-periodic controller, sampled 4x finer than its
        nodes)."""
        tent = controller_from_vector(x, self.nodes, self.period, duration)
        return abstract(tent, threshold, self._samples(tent))

    def _samples(self, tent: TentController) -> int | None:
        return None if self.period is not None else 4 * (tent.num_nodes - 1)

    def _score(self, controllers, evaluator: BatchEvaluator) -> list[dict]:
        """``eval/*`` metrics of each controller, played periodically (not charged)."""
        returns, metrics = evaluator.evaluate_players(
            [PeriodicPlayer(c, self.period) for c in controllers])
        return [{"eval/return": float(r), **{f"eval/{k}": float(v[j]) for k, v in
                                              metrics.items()}} for j, r in enumerate(returns)]

    def _artefacts(self, x: np.ndarray, duration: float, evaluator: BatchEvaluator) -> dict:
        """The best learned controller and its FFT abstraction: at the fixed
        ``abstraction_threshold`` if one is given, else the most compact one within 10% of the
        learned objective; with what the abstraction scores (each simulation here is not
        charged to the budget)."""
        tent = controller_from_vector(x, self.nodes, self.period, duration)
        artefacts = {"controller": {"nodes": tent.nodes.tolist(), "t0": tent.t0, "t1": tent.t1,
                                    "periodic": self.period is not None},
                     "parameters": int(x.size),
                     "episode": {"task": evaluator.task.name,
                                 "duration": evaluator.duration}}
        if self.threshold is not None:
            chosen = abstract(tent, self.threshold, self._samples(tent))
        else:
            chosen, artefacts["abstraction_report"] = most_compact(
                tent, lambda cs: [-m["eval/return"] for m in self._score(cs, evaluator)],
                samples=self._samples(tent))
        artefacts["abstraction"] = chosen.to_dict()
        artefacts["abstraction_metrics"] = {
            **self._score([chosen], evaluator)[0], "parameters": chosen.num_parameters,
            "coefficients": chosen.num_coefficients, "refined": False}
        return artefacts

    def _refined_artefacts(self, phase: Phase, artefacts: dict) -> dict:
        """The refined abstraction becomes the learner's ``abstraction``; the truncation the
        "learn" phase chose moves to ``truncated_abstraction``; ``abstraction_metrics`` also
        report the abstraction refinement started from, before refining."""
        support = phase.support
        refined = support.with_frequency_parameters(phase.best["x"])
        return {
            "truncated_abstraction": artefacts["abstraction"],
            "truncated_abstraction_metrics": artefacts["abstraction_metrics"],
            "abstraction": refined.to_dict(),
            "abstraction_metrics": {
                **_eval_metrics(phase.best), "parameters": refined.num_parameters,
                "coefficients": refined.num_coefficients, "refined": True,
                "threshold": self.refine["threshold"],
                "before_refining": phase.start}}


def _eval_metrics(best: dict) -> dict[str, float]:
    """A phase's best as ``eval/*`` metrics."""
    return {"eval/return": best["return"], **{f"eval/{k}": v for k, v in best["metrics"].items()}}


class AnnealingLearner(BlackBoxLearner):
    """The paper's low-level learner: simulated annealing over the nodal values."""

    name = "annealing"
    optimizer = annealing
    params_class = annealing.AnnealingParams


class CMAESLearner(BlackBoxLearner):
    """CMA-ES over the same nodal values (baseline)."""

    name = "cmaes"
    optimizer = cmaes
    params_class = cmaes.CMAESParams
