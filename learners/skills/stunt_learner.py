"""The closed-loop stunt controller's learner: simulated annealing (the paper's optimiser, as
its macro learner's) over a table of moves (:class:`~animat.learners.skills.stunt_table.StuntTable`)
that chooses the dolphin's next skill from its height, pitch and speed.

A candidate is one gene in [0, 1] per cell of the table, read as a move code (0 rests; k plays
the k-th of ``skills``). Candidates are scored together, closed loop, on the native vector env
of the stunt (:class:`StuntTableEvaluator`), each from the same seeded start states, by the
stunt's own objective: where the open-loop macro learner fixes one sequence for every start,
this learns what to do from what the dolphin senses as it goes. ``stunt_table_coordinate``
searches the same table a cell at a time (:mod:`animat.learners.optimizers.coordinate`), as the
fish's ``switching_coordinate`` does.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from animat.envs.registration import task_of
from animat.envs.tasks.stunts import StuntTask

from ..agents import BatchPolicyAgent
from ..base import episode_timing
from ..blackbox import BlackBoxLearner
from ..controllers.repertoire import Repertoire, check_skill_names, kept_in_run
from ..controllers.table import CellTableEncoding
from ..optimizers import annealing, coordinate
from ..rollout import START_STATES, BatchEvaluator, check_worst_share
from .stunt_table import StuntTable, table_shape


@dataclass(frozen=True)
class StuntTableParams:
    """repertoire: path of a repertoire JSON (required); skills: the names a table may play
    (None: all of the repertoire's); interval_s: s between decisions; start_states: seeded
    starts each candidate is scored over; worst_share: the share of them its objective
    averages, its worst first (1: all); checkpoint_every: rounds."""

    repertoire: str | None = None
    skills: list | None = None
    interval_s: float = 0.25
    start_states: int = START_STATES
    worst_share: float = 1.0
    checkpoint_every: int = 10

    def __post_init__(self) -> None:
        if self.repertoire is None:
            raise ValueError("needs params.repertoire (a repertoire file)")
        check_worst_share(self.worst_share)
        if not 0 < self.interval_s < np.inf:
            raise ValueError(f"interval_s must be > 0 s, got {self.interval_s!r}")
        if self.start_states < 1 or self.checkpoint_every < 1:
            raise ValueError("start_states and checkpoint_every must be >= 1")
        check_skill_names(self.skills)


class StuntTableEvaluator(BatchEvaluator):
    """Scores tables (P, *shape) closed loop: every row of the vector env is a dolphin played
    by its table (``policy(tables, layout) -> StuntTable``)."""

    def __init__(self, policy, env_id: str, env_kwargs: dict | None = None, *args,
                 **kwargs) -> None:
        super().__init__(env_id, env_kwargs, *args, **kwargs)
        observed = int(self.env.single_observation_space.shape[0])
        self.layout = (observed - int(self.task.obs_size), self.action_size)
        self.policy = policy

    def evaluate_players(self, players) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """:meth:`evaluate_rows` of the tables ``players`` (P, *shape)."""
        return self.evaluate_rows(np.repeat(np.asarray(players), self.num_starts, axis=0))

    def _player(self, rows: np.ndarray):
        """``act(k, obs)``: each row's dolphin played by its table (padding rows rest)."""
        policy = self.policy(rows.astype(int), self.layout)
        policy.reset(len(rows))
        return lambda k, obs: policy.act(obs)


class StuntTableLearner(CellTableEncoding, BlackBoxLearner):
    """Params: ``repertoire``, ``skills``, ``interval_s`` (0.25 s), ``start_states``, plus the
    annealing parameters (``mutation_rate`` is per cell: a small one, e.g. 0.1, changes a few
    moves at a time). Drives the dolphin's stunt envs."""

    name = "stunt_table"
    path_params = ("repertoire",)
    optimizer = annealing
    params_class = annealing.AnnealingParams
    own_params = StuntTableParams

    def _configure(self) -> None:
        if not isinstance(task_of(self.env_id, self.env_kwargs), StuntTask):
            raise ValueError(f"learner {self.name!r} plays a dolphin stunt: it needs a stunt "
                             f"env (e.g. Animat/DolphinLeap-v0), not {self.env_id}")
        self.repertoire = Repertoire.load(self.own.repertoire)
        self.skill_names = list(self.own.skills if self.own.skills is not None
                                else self.repertoire.names)
        for name in self.skill_names:
            self.repertoire[name]  # raises KeyError naming a missing skill
        self.shape = table_shape()
        self.moves = len(self.skill_names) + 1

    def _policy(self, tables: np.ndarray, layout: tuple[int, int]) -> StuntTable:
        dt = float(episode_timing(self.env_id, self.env_kwargs).dt)
        return StuntTable(self.repertoire, self.skill_names, tables, dt, self.own.interval_s,
                          layout)

    def _evaluator(self) -> StuntTableEvaluator:
        return StuntTableEvaluator(self._policy, self.env_id, self.env_kwargs, self.population,
                                   self.seed, self.own.start_states, self.own.worst_share)

    def _artefacts(self, x: np.ndarray, duration: float, evaluator) -> dict:
        return {"table": self.controller(x, duration).tolist(),
                "moves": ["rest", *self.skill_names], "parameters": int(x.size),
                "layout": list(evaluator.layout)}

    def learn(self, budget_env_steps: int, checkpoint_dir=None):
        """As every black-box learner, playing the run folder's own copy of the repertoire
        (:func:`animat.learners.controllers.repertoire.kept_in_run`)."""
        self.repertoire = kept_in_run(self.repertoire, checkpoint_dir)
        return super().learn(budget_env_steps, checkpoint_dir)

    def agent(self, artefacts: dict, folder) -> BatchPolicyAgent:
        """The learned table, playing one dolphin in the run's env."""
        policy = self._policy(np.asarray(artefacts["table"]), tuple(artefacts["layout"]))
        return BatchPolicyAgent(policy, self.env_id, self.env_kwargs)


class CoordinateStuntTableLearner(StuntTableLearner):
    """The same table, searched a cell at a time (every other move of one cell per round, on
    the same ``start_states``; the best kept if it beats the table so far) until a sweep
    changes no cell or the budget ends. ``candidates`` (moves tried a round) follows the
    budget."""

    name = "stunt_table_coordinate"
    optimizer = coordinate
    params_class = coordinate.CoordinateParams

    def _fit_encoding(self, opt_params: dict) -> dict:
        return coordinate.with_levels(opt_params, self.moves, f"learner {self.name!r}",
                                      "the table's moves")
