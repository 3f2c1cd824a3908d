"""A learned closed-loop maneuver: simulated annealing over a table of moves that the steering
(:mod:`animat.learners.skills.steering`) plays, choosing a repertoire skill every
``interval_s`` from the goal's |bearing| and range as the fish goes.

A candidate is one gene in [0, 1] per cell of the table (6 bearing bins of 30 deg by the
range bins that ``range_edges_bl`` splits; by default 4, split at 1, 2 and 4 BL), read as a
move code (rest, a swim, or a turn toward the goal;
:func:`~animat.learners.skills.steering.table_moves`). Candidates are scored together, closed
loop, on the native vector env (:class:`ClosedLoopEvaluator`), each from the same seeded
start states, the goal drawn by the reach task: what the open-loop macro learner does for one
goal, this does for every goal at once.

Two searches over the same table: ``switching``, the paper's simulated annealing; and
``switching_coordinate``, a coordinate search (:mod:`animat.learners.optimizers.coordinate`):
one cell at a time, every other move tried on the same starts and the best kept, until a
sweep over all cells changes none.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from animat.envs.tasks import ReachTask

from .base import episode_timing
from .blackbox import BlackBoxLearner
from .controllers.repertoire import Repertoire, kept_in_run
from .controllers.table import CellTableEncoding
from .optimizers import annealing, coordinate
from .rollout import START_STATES, BatchEvaluator, check_worst_share
from .skills.steering import (
    RANGE_EDGES_BL,
    SkillSteering,
    SteeringAgent,
    SteeringParams,
    check_reach,
    repertoire_moves,
    table_moves,
    table_shape,
)


@dataclass(frozen=True)
class SwitchingParams:
    """repertoire: path of a repertoire JSON (required); interval_s: s between decisions;
    range_edges_bl: BL, where the table splits the goal's range; start_states: seeded starts
    each candidate is scored over; worst_share: the share of them its objective averages, its
    worst first (1: all); checkpoint_every: rounds."""

    repertoire: str | None = None
    interval_s: float = 0.25
    range_edges_bl: tuple[float, ...] = RANGE_EDGES_BL
    start_states: int = START_STATES
    worst_share: float = 1.0
    checkpoint_every: int = 10

    def __post_init__(self) -> None:
        if self.repertoire is None:
            raise ValueError("needs params.repertoire (a repertoire file)")
        check_worst_share(self.worst_share)
        self.steering()  # a bad interval or bad edges, in one line
        if self.start_states < 1 or self.checkpoint_every < 1:
            raise ValueError("start_states and checkpoint_every must be >= 1")

    def steering(self) -> SteeringParams:
        """The steering's settings these params give."""
        return SteeringParams(interval_s=self.interval_s, range_edges_bl=self.range_edges_bl)


class ClosedLoopEvaluator(BatchEvaluator):
    """Scores tables of moves (P, bearing bins, range bins) closed loop: every row of the
    vector env is a fish steered by its table (``steering(tables) -> SkillSteering``) toward
    its goal, the reach task's observation entries."""

    def __init__(self, steering, env_id: str, env_kwargs: dict | None = None, *args,
                 **kwargs) -> None:
        check_reach(env_id, env_kwargs, "a table of moves")
        super().__init__(env_id, env_kwargs, *args, **kwargs)
        self.steering = steering

    def evaluate_players(self, players) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """:meth:`evaluate_rows` of the tables ``players`` (P, bearing bins, range bins)."""
        return self.evaluate_rows(np.repeat(np.asarray(players), self.num_starts, axis=0))

    def _player(self, rows: np.ndarray):
        """``act(k, obs)``: each row's fish steered by its table (``rows`` (num_envs,
        bearing bins, range bins), padding rows all rest) toward its goal, the observation's task
        entries."""
        steering = self.steering(rows.astype(int))
        steering.reset(len(rows))
        return lambda k, obs: steering.act(obs[:, -ReachTask.obs_size:])


class SwitchingLearner(CellTableEncoding, BlackBoxLearner):
    """Params: ``repertoire``, ``interval_s`` (0.25 s), ``start_states``, plus the annealing
    parameters (``mutation_rate`` is per cell: a small one, e.g. 0.1, changes a few moves at
    a time)."""

    name = "switching"
    path_params = ("repertoire",)
    optimizer = annealing
    params_class = annealing.AnnealingParams
    own_params = SwitchingParams

    def _configure(self) -> None:
        check_reach(self.env_id, self.env_kwargs, f"learner {self.name!r}")
        self.repertoire = Repertoire.load(self.own.repertoire)
        self.rules = self.own.steering()
        self.shape = table_shape(self.rules)
        self.move_skills = table_moves(*repertoire_moves(self.repertoire))
        self.moves = len(self.move_skills)

    def _evaluator(self) -> ClosedLoopEvaluator:
        dt = self._dt()
        return ClosedLoopEvaluator(
            lambda tables: SkillSteering(self.repertoire, self.rules, dt, tables),
            self.env_id, self.env_kwargs, self.population, self.seed, self.own.start_states,
            self.own.worst_share)

    def _dt(self) -> float:
        return float(episode_timing(self.env_id, self.env_kwargs).dt)

    def _artefacts(self, x: np.ndarray, duration: float, evaluator) -> dict:
        names = [("rest" if left < 0 else self.repertoire.names[left]).replace("_left", "")
                 for left, _ in self.move_skills]
        return {"table": self.controller(x, duration).tolist(), "moves": names,
                "parameters": int(x.size)}

    def learn(self, budget_env_steps: int, checkpoint_dir=None):
        """As every black-box learner, steering with the run folder's own copy of the
        repertoire (:func:`animat.learners.controllers.repertoire.kept_in_run`)."""
        self.repertoire = kept_in_run(self.repertoire, checkpoint_dir)
        return super().learn(budget_env_steps, checkpoint_dir)

    def agent(self, artefacts: dict, folder) -> SteeringAgent:
        """The learned table, steering one fish in the run's env."""
        steering = SkillSteering(self.repertoire, self.rules, self._dt(),
                                 np.asarray(artefacts["table"]))
        return SteeringAgent(steering, self.env_id, self.env_kwargs)


class CoordinateSwitchingLearner(SwitchingLearner):
    """The same table, searched a cell at a time (:mod:`~animat.learners.optimizers.coordinate`:
    every other move of one cell per round, on the same ``start_states``; the best kept if it
    beats the table so far) until a sweep changes no cell or the budget ends. Params:
    ``repertoire``, ``interval_s``, ``start_states``; ``candidates`` (moves tried a round)
    follows the budget."""

    name = "switching_coordinate"
    optimizer = coordinate
    params_class = coordinate.CoordinateParams

    def _fit_encoding(self, opt_params: dict) -> dict:
        return coordinate.with_levels(opt_params, self.moves, f"learner {self.name!r}",
                                      "the repertoire's moves")
