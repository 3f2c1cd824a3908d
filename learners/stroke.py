"""The exit-stroke learner: the dolphin learns to control the angular momentum of its body as
it leaves the water (the paper's Section 4.2: "... so that it can perform aerial spins and
somersaults"), on top of a macro sequence that carries it there.

In the air nothing the body does changes its angular momentum, so a somersault's spin must be
taken from the water in the last strokes before the exit. A candidate here is a macro
sequence from the repertoire (``prefix``: a learned leap, fixed) followed, from a time ``t0``
in ``start_window``, by a parametric fluke stroke (:class:`StrokeParameters`) that replaces
its actuation: the dorsal and ventral muscles of the middle and back segments beat at
``frequency`` with an ``amplitude`` round a dorsal/ventral ``bias`` per segment (the back
lagging the middle by ``lag`` of a cycle), for ``hold`` s; then the body holds a ``pose``
through the flight. Its 14 numbers, each scaled to [0, 1] between its bounds, are what the
black-box loop of :mod:`animat.learners.blackbox` searches: simulated annealing (``stroke``,
the paper's optimiser) or CMA-ES (``stroke_cmaes``), with its budget, checkpoints, start
states and logging.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from animat.envs.bodies.dolphin import (
    ACTUATOR_NAMES,
    DORSAL_BACK,
    DORSAL_MIDDLE,
    VENTRAL_BACK,
    VENTRAL_MIDDLE,
)
from animat.envs.registration import body_of, timing

from .blackbox import BlackBoxLearner
from .controllers.repertoire import Repertoire, kept_in_run
from .controllers.tent import play
from .macro import MacroSequence, check_sequence
from .optimizers import annealing, cmaes
from .rollout import START_STATES, check_worst_share

NUM_ACTUATORS = 6
# The stroke's numbers, in the order of a candidate's genes, with their bounds.
STROKE_NAMES = ("t0", "hold", "frequency", "phase", "amplitude", "bias_middle", "bias_back",
                "lag")


@dataclass(frozen=True)
class StrokeParameters:
    """One exit stroke. ``t0`` s (episode time it starts), ``hold`` s (how long it beats),
    ``frequency`` Hz, ``phase`` (cycles), ``amplitude`` (0: no beat, 1: a full beat),
    ``bias_middle``/``bias_back`` in [-1, 1] (> 0 dorsal, < 0 ventral: the bend it beats
    round), ``lag`` (cycles the back segment lags the middle), ``pose`` (6,) the activations
    u in [0, 1] held from ``t0 + hold`` on (through the flight)."""

    t0: float
    hold: float
    frequency: float
    phase: float
    amplitude: float
    bias_middle: float
    bias_back: float
    lag: float
    pose: tuple

    def to_dict(self) -> dict:
        return {**{name: float(getattr(self, name)) for name in STROKE_NAMES},
                "pose": [float(u) for u in self.pose]}

    @classmethod
    def from_dict(cls, data: dict) -> StrokeParameters:
        return cls(**{name: float(data[name]) for name in STROKE_NAMES},
                   pose=tuple(float(u) for u in data["pose"]))


def segment_stroke(cycles: np.ndarray, bias: float, amplitude: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(dorsal, ventral) activations u in [0, 1] of one segment at stroke phases ``cycles``
    (T,): the bend s = clip(bias + 2 amplitude sin(2 pi cycles), -1, 1) contracts the dorsal
    muscles where s > 0 and the ventral ones where s < 0, never both."""
    s = np.clip(bias + 2.0 * amplitude * np.sin(2.0 * np.pi * cycles), -1.0, 1.0)
    return np.maximum(s, 0.0), np.maximum(-s, 0.0)


class ExitStroke:
    """The prefix macro sequence, then the stroke from ``stroke.t0``: ``u(t)`` (..., 6)."""

    def __init__(self, prefix: MacroSequence, stroke: StrokeParameters) -> None:
        self.prefix, self.stroke = prefix, stroke

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        shape = np.shape(t)
        t = np.asarray(t, dtype=float).reshape(-1)
        s = self.stroke
        u = np.array(self.prefix(t), dtype=float)
        after, beating = t >= s.t0, (t >= s.t0) & (t < s.t0 + s.hold)
        u[after] = np.asarray(s.pose)
        cycles = s.frequency * (t[beating] - s.t0) + s.phase
        u[beating] = 0.0
        u[beating, DORSAL_MIDDLE], u[beating, VENTRAL_MIDDLE] = segment_stroke(
            cycles, s.bias_middle, s.amplitude)
        u[beating, DORSAL_BACK], u[beating, VENTRAL_BACK] = segment_stroke(
            cycles - s.lag, s.bias_back, s.amplitude)
        return u.reshape(shape + (NUM_ACTUATORS,))

    def actions(self, dt: float, steps: int) -> np.ndarray:
        return play(self, dt, steps)


@dataclass(frozen=True)
class StrokeLearnerParams:
    """repertoire: path of a repertoire JSON (required); prefix: the macro sequence
    [{skill, duration}] played first (required; e.g. a leap learned by the macro learner);
    overlap: its blends' share; start_window: [earliest, latest] t0, s (None: the whole
    episode); max_hold: s (at most the episode's length); max_frequency: Hz (at most half the
    env step's rate); checkpoint_every: rounds; start_states: seeded
    starts each candidate is scored over; worst_share: the share of them its objective
    averages, its worst first (1: all)."""

    repertoire: str | None = None
    prefix: list | None = None
    overlap: float = 0.05
    start_window: list | None = None
    max_hold: float = 1.5
    max_frequency: float = 6.0
    checkpoint_every: int = 10
    start_states: int = START_STATES
    worst_share: float = 1.0

    def __post_init__(self) -> None:
        check_worst_share(self.worst_share)
        if self.repertoire is None or self.prefix is None:
            raise ValueError("needs params.repertoire (a repertoire file) and params.prefix "
                             "(the [{skill, duration}] sequence the stroke follows)")
        if self.start_window is not None and not (
                len(self.start_window) == 2 and all(type(v) in (int, float)
                                                    for v in self.start_window)
                and 0.0 <= self.start_window[0] < self.start_window[1]):
            raise ValueError(f"start_window must be [earliest, latest] s with 0 <= earliest < "
                             f"latest, got {self.start_window!r}")
        if not (np.isfinite(self.max_hold) and self.max_hold > 0.05
                and np.isfinite(self.max_frequency) and self.max_frequency > 1.0):
            raise ValueError(f"need max_hold > 0.05 s and max_frequency > 1 Hz, finite; got "
                             f"{self.max_hold!r}, {self.max_frequency!r}")
        if not 0.0 <= self.overlap < 0.5:
            raise ValueError(f"overlap must be in [0, 0.5), got {self.overlap!r}")
        if self.checkpoint_every < 1 or self.start_states < 1:
            raise ValueError("checkpoint_every and start_states must be >= 1")


def _dolphin_episode(env_id: str, env_kwargs: dict, learner: str) -> tuple[float, float]:
    """(env step, episode duration), s, of a dolphin env, without building it; a ValueError
    naming ``learner`` for a body whose actuators are not the dolphin's (the stroke drives
    its dorsal and ventral muscles by name)."""
    dt, steps = timing(env_id, env_kwargs)  # a bad argument: the env's own error, first
    names = tuple(body_of(env_id, env_kwargs).actuator_names or ())
    if names != ACTUATOR_NAMES:
        raise ValueError(f"learner {learner!r}: the exit stroke drives the dolphin's "
                         f"actuators {ACTUATOR_NAMES}; {env_id} has {names or 'others'}")
    return dt, dt * steps


class StrokeLearner(BlackBoxLearner):
    """Params: ``repertoire``, ``prefix`` (required), ``start_window``, ``max_hold``,
    ``max_frequency``, ``overlap`` (:class:`StrokeLearnerParams`), plus the annealing
    parameters. A candidate is the stroke's 14 numbers scaled to [0, 1]
    (:meth:`bounds`); the search starts at the middle of every range."""

    name = "stroke"
    path_params = ("repertoire",)
    optimizer = annealing
    params_class = annealing.AnnealingParams
    own_params = StrokeLearnerParams

    def _configure(self) -> None:
        own = self.own
        self.repertoire = Repertoire.load(own.repertoire)
        try:
            self.steps = check_sequence(own.prefix, self.repertoire, "prefix")
        except ValueError as error:
            raise ValueError(f"learner {self.name!r}: {error}") from None
        self.overlap = own.overlap
        self.prefix = MacroSequence(self.repertoire, self.steps, self.overlap)
        dt, duration = _dolphin_episode(self.env_id, self.env_kwargs, self.name)
        window = own.start_window if own.start_window is not None else [0.0, duration]
        checks = [(window[1] <= duration, f"start_window {window} ends after the episode "
                                          f"({duration:g} s)"),
                  (own.max_frequency <= 0.5 / dt, f"max_frequency {own.max_frequency:g} Hz is "
                   f"above what the env step ({dt:g} s) can play ({0.5 / dt:g} Hz)")]
        for ok, message in checks:
            if not ok:
                raise ValueError(f"learner {self.name!r}: {message}")
        self.window = (float(window[0]), float(window[1]))
        self.max_hold = min(own.max_hold, duration)  # a longer one beats to the end alike

    def _fit_encoding(self, opt_params: dict) -> dict:
        """The genes are 14 numbers in [0, 1], not blocks of nodal values: their box and
        smoothing along blocks are not the user's to set."""
        fixed = sorted(set(opt_params) & {"lower", "upper", "smoothing", "block"})
        if fixed:
            raise ValueError(f"learner {self.name!r}: {fixed} cannot be set: the stroke's "
                             "genes are its 14 numbers scaled to [0, 1]")
        return opt_params

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(14,) lower and upper bounds of the stroke's numbers, in gene order
        (:data:`STROKE_NAMES`, then the pose)."""
        own = self.own
        low = [self.window[0], 0.05, 1.0, 0.0, 0.0, -1.0, -1.0, 0.0] + [0.0] * NUM_ACTUATORS
        high = [self.window[1], self.max_hold, own.max_frequency, 1.0, 1.0, 1.0, 1.0, 1.0] + [
            1.0] * NUM_ACTUATORS
        return np.array(low), np.array(high)

    def _x0(self, num_actuators: int) -> np.ndarray:
        return np.full(len(STROKE_NAMES) + NUM_ACTUATORS, 0.5)

    def _genes(self, actuators: int) -> tuple[int, str]:
        return len(STROKE_NAMES) + NUM_ACTUATORS, "the stroke's numbers"

    def decode(self, vector: np.ndarray) -> StrokeParameters:
        """The stroke of genes ``vector`` (14,) in [0, 1] (clipped)."""
        low, high = self.bounds()
        values = low + np.clip(np.asarray(vector, dtype=float), 0.0, 1.0) * (high - low)
        named = dict(zip(STROKE_NAMES, values[:len(STROKE_NAMES)]))
        return StrokeParameters(**named, pose=tuple(values[len(STROKE_NAMES):]))

    def controller(self, vector: np.ndarray, duration: float) -> ExitStroke:
        return ExitStroke(self.prefix, self.decode(vector))

    def _artefacts(self, x: np.ndarray, duration: float, evaluator) -> dict:
        return {"prefix": [{"skill": name, "duration": float(d)} for name, d in self.steps],
                "stroke": self.decode(x).to_dict(), "genes": [float(v) for v in x],
                "parameters": int(x.size)}

    def _player(self, artefacts: dict) -> ExitStroke:
        steps = [(step["skill"], float(step["duration"])) for step in artefacts["prefix"]]
        return ExitStroke(MacroSequence(self.repertoire, steps, self.overlap),
                          StrokeParameters.from_dict(artefacts["stroke"]))

    def learn(self, budget_env_steps: int, checkpoint_dir=None):
        """As every black-box learner, composing from the run folder's own copy of the
        repertoire (:func:`animat.learners.controllers.repertoire.kept_in_run`)."""
        self.repertoire = kept_in_run(self.repertoire, checkpoint_dir)
        self.prefix = MacroSequence(self.repertoire, self.steps, self.overlap)
        return super().learn(budget_env_steps, checkpoint_dir)


class StrokeCMAESLearner(StrokeLearner):
    """The exit stroke searched by CMA-ES (the baseline optimiser) instead of annealing."""

    name = "stroke_cmaes"
    optimizer = cmaes
    params_class = cmaes.CMAESParams
