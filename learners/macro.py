"""The macro-controller learner (the paper's Section 4.2): simulated annealing over the
selection, ordering and durations of repertoire skills, evaluated by simulation.

A candidate is ``slots`` (skill, duration) pairs, encoded in [0, 1]^(2 slots) so that the
unchanged annealing optimiser of :mod:`animat.learners.optimizers.annealing` can search it: gene
``2k`` picks
slot k's skill (or none: the slot is empty), gene ``2k + 1`` its duration in
[``min_duration``, ``max_duration``] s. The filled slots, in order, are concatenated with 5%
blends (:mod:`animat.learners.controllers.concatenation`); after the sequence the muscles relax.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .blackbox import BlackBoxLearner
from .controllers.concatenation import concatenate
from .controllers.repertoire import Repertoire, check_skill_names, kept_in_run
from .controllers.tent import play
from .optimizers import annealing
from .rollout import START_STATES, check_worst_share


@dataclass(frozen=True)
class MacroParams:
    """repertoire: path of a repertoire JSON (required); skills: the names to use (None: all);
    slots; min_duration, max_duration: s per slot; overlap: the blend's share;
    checkpoint_every: rounds; start_states: seeded starts each candidate is scored over;
    worst_share: the share of them its objective averages, its worst first (1: all);
    start_from: a sequence [{skill, duration}] the chains start from (e.g. a learned leap
    that a stunt builds on; None: a random sequence)."""

    repertoire: str | None = None
    skills: list | None = None
    slots: int = 3
    min_duration: float = 0.5
    max_duration: float = 4.0
    overlap: float = 0.05
    checkpoint_every: int = 10
    start_states: int = START_STATES
    worst_share: float = 1.0
    start_from: list | None = None

    def __post_init__(self) -> None:
        check_worst_share(self.worst_share)
        if self.repertoire is None:
            raise ValueError("needs params.repertoire (a repertoire file)")
        if self.slots < 1 or not 0 < self.min_duration <= self.max_duration:
            raise ValueError("need slots >= 1 and 0 < min_duration <= max_duration")
        check_skill_names(self.skills)
        if self.start_from is not None:
            if not isinstance(self.start_from, list) or len(self.start_from) > self.slots or any(
                    not isinstance(s, dict) or set(s) != {"skill", "duration"}
                    for s in self.start_from):
                raise ValueError(f"start_from must be a list of at most slots ({self.slots}) "
                                 "{skill, duration} entries")


def check_sequence(sequence, repertoire: Repertoire, field: str) -> list[tuple[str, float]]:
    """[(skill, duration s)] of a config's sequence [{skill, duration}]; a ValueError naming
    ``field`` for anything else, a skill the repertoire lacks or a duration that is not > 0."""
    if not isinstance(sequence, list) or not sequence or any(
            not isinstance(s, dict) or set(s) != {"skill", "duration"} for s in sequence):
        raise ValueError(f"{field} must be a non-empty list of {{skill, duration}} entries, "
                         f"got {sequence!r}")
    steps = []
    for step in sequence:
        if not isinstance(step["skill"], str) or step["skill"] not in repertoire.skills:
            raise ValueError(f"{field}: no skill {step['skill']!r} in the repertoire; it has "
                             f"{repertoire.names}")
        duration = step["duration"]
        if type(duration) not in (int, float) or not np.isfinite(duration) or duration <= 0:
            raise ValueError(f"{field}: the duration of {step['skill']!r} must be > 0 s, got "
                             f"{duration!r}")
        steps.append((step["skill"], float(duration)))
    return steps


def decode_slots(vector: np.ndarray, slots: int, skill_names: list[str], min_duration: float,
                 max_duration: float) -> list[tuple[str, float]]:
    """[(skill, duration s)] of the filled slots of genes ``vector`` (2 slots,): gene ``2k``
    picks slot k's skill of ``skill_names`` (or none), gene ``2k + 1`` its duration in
    [``min_duration``, ``max_duration``]."""
    steps = []
    choices = len(skill_names)
    for k in range(slots):
        pick = min(int(vector[2 * k] * (choices + 1)), choices) - 1
        if pick >= 0:
            duration = min_duration + vector[2 * k + 1] * (max_duration - min_duration)
            steps.append((skill_names[pick], float(duration)))
    return steps


class MacroSequence:
    """A decoded candidate: ``steps`` [(skill name, duration s)] and its actuation."""

    def __init__(self, repertoire: Repertoire, steps: list[tuple[str, float]],
                 overlap: float) -> None:
        self.steps = steps
        self.num_actuators = next(iter(repertoire.skills.values())).controller.num_actuators
        if steps:
            self._blended, self.duration = concatenate(
                [repertoire[name].controller for name, _ in steps],
                [duration for _, duration in steps], overlap)
        else:
            self._blended, self.duration = None, 0.0

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self._blended is None:
            return np.zeros(t.shape + (self.num_actuators,))
        return np.where((t < self.duration)[..., None], self._blended(t), 0.0)

    def actions(self, dt: float, steps: int) -> np.ndarray:
        return play(self, dt, steps)


class MacroLearner(BlackBoxLearner):
    """Params: ``repertoire`` (path to a repertoire JSON), ``skills`` (names to use; default
    all), ``slots`` (3), ``min_duration``/``max_duration`` (0.5 / 4 s), ``overlap`` (0.05),
    ``start_from`` (a sequence to start from), plus the annealing parameters."""

    name = "macro"
    path_params = ("repertoire",)
    optimizer = annealing
    params_class = annealing.AnnealingParams
    own_params = MacroParams

    def _configure(self) -> None:
        own = self.own
        self.repertoire = Repertoire.load(own.repertoire)
        self.skill_names = list(own.skills if own.skills is not None else self.repertoire.names)
        for name in self.skill_names:
            self.repertoire[name]  # raises KeyError naming a missing skill
        self.slots, self.overlap = own.slots, own.overlap
        self.min_duration, self.max_duration = own.min_duration, own.max_duration
        if own.start_from is not None:
            self._x0(0)  # a start the encoding cannot hold is refused now, naming it

    def _fit_encoding(self, opt_params: dict) -> dict:
        return opt_params  # slots are not blocks of nodal values

    def _genes(self, actuators: int) -> tuple[int, str]:
        return 2 * self.slots, f"slots {self.slots} x 2"

    def _x0(self, num_actuators: int) -> np.ndarray:
        if self.own.start_from is not None:
            return self.encode([(s["skill"], float(s["duration"])) for s in self.own.start_from])
        return np.random.default_rng(self.seed).uniform(0.0, 1.0, 2 * self.slots)

    def encode(self, steps: list[tuple[str, float]]) -> np.ndarray:
        """The genes (2 slots,) that :meth:`decode` reads as ``steps`` (the slots after them
        empty); a duration outside [min_duration, max_duration] is an error naming it."""
        genes = np.zeros(2 * self.slots)
        choices = len(self.skill_names)
        for k, (name, duration) in enumerate(steps):
            if name not in self.skill_names:
                raise ValueError(f"start_from: skill {name!r} is not among {self.skill_names}")
            if not self.min_duration <= duration <= self.max_duration:
                raise ValueError(f"start_from: duration {duration} of {name!r} is outside "
                                 f"[{self.min_duration}, {self.max_duration}]")
            genes[2 * k] = (self.skill_names.index(name) + 1.5) / (choices + 1)
            genes[2 * k + 1] = (duration - self.min_duration) / (
                self.max_duration - self.min_duration)
        return genes

    def decode(self, vector: np.ndarray) -> list[tuple[str, float]]:
        """[(skill, duration)] of the filled slots, in order."""
        return decode_slots(vector, self.slots, self.skill_names, self.min_duration,
                            self.max_duration)

    def controller(self, vector: np.ndarray, duration: float) -> MacroSequence:
        return MacroSequence(self.repertoire, self.decode(vector), self.overlap)

    def _artefacts(self, x: np.ndarray, duration: float, evaluator) -> dict:
        return {"sequence": [{"skill": name, "duration": float(d)}
                             for name, d in self.decode(x)],
                "parameters": int(x.size)}

    def learn(self, budget_env_steps: int, checkpoint_dir=None):
        """As every black-box learner, composing from the run folder's own copy of the
        repertoire (:func:`animat.learners.controllers.repertoire.kept_in_run`)."""
        self.repertoire = kept_in_run(self.repertoire, checkpoint_dir)
        return super().learn(budget_env_steps, checkpoint_dir)

    def _player(self, artefacts: dict) -> MacroSequence:
        steps = [(step["skill"], float(step["duration"])) for step in artefacts["sequence"]]
        return MacroSequence(self.repertoire, steps, self.overlap)
