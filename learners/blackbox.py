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

import time
from dataclasses import fields
from pathlib import Path

import numpy as np

from animat.envs.registration import action_size_of

from .agents import OpenLoopAgent
from .base import Learner, LearnResult, episode_steps, episode_timing
from .blackbox_run import Phase, Run, log_round, refine_settings, save_run, saved_run
from .controllers.periodic import ControllerParams, PeriodicPlayer, controller_from_vector
from .controllers.report import (
    ResultFrom,
    abstraction_of,
    eval_metrics,
    learned_artefacts,
    refined_artefacts,
    reported_player,
    result_from,
)
from .optimizers import Optimizer, annealing, cmaes
from .rollout import BatchEvaluator
from .storage import migration
from .validation import BudgetError, check_memory, typed_params, unknown_params


class BlackBoxLearner(Learner):
    """Optimises a parameter vector with an ask/tell ``optimizer`` module (an
    :class:`~animat.learners.optimizers.Optimizer`, e.g.
    :mod:`animat.learners.optimizers.annealing`) configured by ``params_class``. What the vector
    means is the subclass's: ``own_params`` (its parameters), :meth:`_configure`, :meth:`_x0`,
    :meth:`controller` (vector -> something with ``actions(dt, steps)``), :meth:`_artefacts`,
    :meth:`_player`. This base reads the tent-controller encoding
    (:mod:`animat.learners.controllers.periodic`); nothing here is specific to one optimiser."""

    optimizer: Optimizer
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
        self.refine = refine_settings(getattr(self.own, "refine", None), self.name,
                                      self.optimizer, self.opt_params)

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

    def _env_sizes(self) -> tuple[int, int]:
        """(env steps in an episode, the env's actuators), read from the id and its kwargs
        without building the env (:func:`~animat.envs.registration.action_size_of`)."""
        if getattr(self, "_sizes", None) is None:
            self._sizes = (episode_steps(self.env_id, self.env_kwargs),
                           action_size_of(self.env_id, self.env_kwargs))
        return self._sizes

    def _episode_cost(self) -> int:
        """Env steps to score one candidate: an episode from every start state."""
        return self._env_sizes()[0] * int(self.own.start_states)

    def _genes(self, actuators: int) -> tuple[int, str]:
        """The size of a candidate of the encoding (``actuators``: the env's), and what makes
        it, for a message: ``nodes`` values per actuator here."""
        return actuators * self.nodes, f"nodes {self.nodes} x {actuators} actuators"

    def _check_memory(self, population: int) -> None:
        """ValueError in one line (:func:`~animat.learners.validation.check_memory`) when a
        round of ``population`` candidates would not fit in this machine's memory: the
        optimiser's state over their genes, and their action sequences (float32) over every
        start state, stacked, then repeated for the batch."""
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
        abstraction), played open loop; a :class:`~animat.learners.storage.files.CorruptFile` naming
        the folder's artefacts.json for a ``result_from`` it does not know."""
        dt, steps = episode_timing(self.env_id, self.env_kwargs)
        result_from(artefacts, Path(folder or "") / "artefacts.json")
        return OpenLoopAgent(self._player(artefacts), dt, steps, self.env_id, self.env_kwargs)

    def _player(self, artefacts: dict):
        """The reported controller of ``artefacts`` (:class:`ResultFrom`; a run without
        ``result_from`` reports the learned one), as a player."""
        return reported_player(artefacts, self.period)

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
        evaluator = self._evaluator()
        path, saved = self._saved(checkpoint_dir)
        if saved is not None:
            if isinstance(saved, dict) and "phases" not in saved:  # before phases existed
                saved["params"] = migration.as_before_schedules(self.opt_params)
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
            save_run(path, run)
        result = self._result(run, evaluator)
        result.artefacts["budget"] = {**plan, "population": self.population,
                                      "phases_run": len(run.phases)}
        return result

    def _evaluator(self) -> BatchEvaluator:
        """What scores a round's candidates (:meth:`controller` of each): the open-loop
        batch of the env, ``population`` candidates at a time over the start states."""
        return BatchEvaluator(self.env_id, self.env_kwargs, self.population, self.seed,
                              self.own.start_states, self.own.worst_share)

    def _saved(self, checkpoint_dir: str | Path | None) -> tuple[Path | None, object]:
        """Where the run's checkpoint goes, and what is saved there
        (:func:`~animat.learners.blackbox_run.saved_run`)."""
        return saved_run(checkpoint_dir, self.trust_pickles)

    def _start_refining(self, run: Run, x: np.ndarray, evaluator: BatchEvaluator) -> None:
        """Phase 2 starts at the truncated abstraction, which is scored first (one episode,
        charged), so that the refined controller is never worse than the one it came from."""
        support = abstraction_of(x, self.nodes, self.period, evaluator.duration,
                                 self.refine["threshold"], self.refine["max_parameters"],
                                 evaluator.steps)
        x0 = support.frequency_parameters()
        params = self.optimizer.same_schedule(self.refine["params"], run.phases[0].params)
        phase = self._phase(params, x0, self.seed + 1, support)
        player = self._decode(phase, x0, evaluator.duration)
        returns, metrics = evaluator.evaluate_players([player])
        run.env_steps += evaluator.episode_cost
        phase.track([x0], returns, metrics)
        phase.start = eval_metrics(phase.best)
        run.phases.append(phase)

    def _phase(self, params, x0: np.ndarray, seed: int, support=None) -> Phase:
        return Phase(params, self.optimizer.init(params, x0, seed), support=support)

    def _decode(self, phase: Phase, vector: np.ndarray, duration: float):
        if phase.support is None:
            return self.controller(vector, duration)
        return PeriodicPlayer(phase.support.with_frequency_parameters(vector), self.period)

    def _run_phase(self, run: Run, index: int, evaluator: BatchEvaluator, limit: int,
                   path: Path | None, start: float) -> None:
        """ask -> simulate -> tell until ``limit`` env steps or the optimiser's stopping rule,
        the optimiser's schedule planned over the rounds that ``limit`` affords
        (``with_budget``)."""
        phase = run.phases[index]
        cost = int(self.optimizer.population(phase.params)) * evaluator.episode_cost
        phase.params = self.optimizer.with_budget(phase.params, phase.state,
                                                  max(limit - run.env_steps, 0) // cost)
        params = phase.params
        while (run.env_steps + cost <= limit
               and not self.optimizer.finished(params, phase.state)):
            candidates, state = self.optimizer.ask(params, phase.state)
            returns, metrics = evaluator.evaluate_players(
                [self._decode(phase, c, evaluator.duration) for c in candidates])
            phase.state = self.optimizer.tell(params, state, candidates, -returns)
            run.env_steps += len(candidates) * evaluator.episode_cost
            run.rounds += 1
            phase.track(candidates, returns, metrics)
            run.wall = time.perf_counter() - start
            log_round(self.logger, run, returns, metrics,
                      self.optimizer.metrics(params, phase.state))
            if path and run.rounds % self.checkpoint_every == 0:
                save_run(path, run)

    def _result(self, run: Run, evaluator: BatchEvaluator) -> LearnResult:
        learned, best = run.phases[0].best, run.overall_best()
        if learned is None:
            raise ValueError(f"budget too small: one round of {self.name} needs "
                             f"{self.population * evaluator.episode_cost} env steps")
        artefacts = self._artefacts(learned["x"], evaluator.duration, evaluator)
        artefacts["learned_metrics"] = eval_metrics(learned)
        if len(run.phases) > 1:
            refined = run.phases[1]
            artefacts.update(refined_artefacts(refined.support, refined.best, refined.start,
                                               self.refine["threshold"], artefacts))
        result_from = ResultFrom.LEARNED if best is learned else ResultFrom.REFINED_ABSTRACTION
        artefacts["result_from"] = result_from.value
        return LearnResult(env_steps=run.env_steps, wall_seconds=run.wall,
                           metrics=eval_metrics(best), artefacts=artefacts)

    def _artefacts(self, x: np.ndarray, duration: float, evaluator: BatchEvaluator) -> dict:
        """The best learned controller and its FFT abstraction, scored
        (:func:`~animat.learners.controllers.report.learned_artefacts`)."""
        return learned_artefacts(x, self.nodes, self.period, self.threshold, evaluator)


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
