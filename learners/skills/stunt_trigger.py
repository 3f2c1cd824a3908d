"""The triggered macro controller: the paper's macro sequence of repertoire skills, in two
parts, the second launched by what the dolphin senses.

The open-loop macro controller (:mod:`animat.learners.macro`) plays one sequence on one clock
from every start; where a start brings the dolphin to the surface a tenth of a second later,
the move that must begin as it breaks the surface begins at the wrong moment. Here the
**approach** (``slots`` skills) plays from the start, as the macro's sequence does, until the
dolphin's height above the surface (its centre of mass, BL: the stunt task's first entry of its
observation) first reaches the **trigger** height; from that env step the **flight** sequence
(``flight_slots`` skills, on its own clock from 0) plays instead, and after it the muscles
relax. A dolphin that never reaches the trigger plays its approach to the end, then relaxes.

A candidate is the macro's genes for each sequence (skill and duration per slot,
:func:`animat.learners.macro.decode_slots`) and one gene for the trigger height in
[``trigger_low``, ``trigger_high``] BL, searched by simulated annealing (the paper's optimiser, as
the macro learner's) and scored closed loop on the stunt's native vector env from the same
seeded starts. Nothing in a skill or the trigger is told the stunt's answer.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from animat.envs.registration import task_of
from animat.envs.tasks.stunts import StuntTask

from ..agents import BatchPolicyAgent
from ..base import episode_timing
from ..macro import MacroLearner, MacroParams, MacroSequence, decode_slots
from ..rollout import BatchEvaluator


@dataclass(frozen=True)
class TriggeredMacroParams(MacroParams):
    """The macro's params (``slots``: the approach's; ``start_from``: an approach to start
    from, e.g. a learned leap), and flight_slots: the flight sequence's slots;
    trigger_low, trigger_high: BL, the range the trigger height is searched in."""

    flight_slots: int = 3
    trigger_low: float = -1.0
    trigger_high: float = 0.5

    def __post_init__(self) -> None:
        super().__post_init__()
        if type(self.flight_slots) is not int or self.flight_slots < 1:
            raise ValueError(f"flight_slots must be an integer >= 1, got {self.flight_slots!r}")
        if not -10.0 <= self.trigger_low < self.trigger_high <= 10.0:
            raise ValueError("need -10 <= trigger_low < trigger_high <= 10 BL, got "
                             f"{self.trigger_low!r} and {self.trigger_high!r}")


@dataclass(frozen=True)
class TriggeredSequence:
    """A decoded candidate: the ``approach`` and ``flight`` sequences and the trigger height
    ``trigger_bl`` (BL above the surface)."""

    approach: MacroSequence
    flight: MacroSequence
    trigger_bl: float

    def tracks(self, dt: float, steps: int) -> tuple[np.ndarray, np.ndarray]:
        """The env actions (steps, A) of the approach from the start and of the flight from
        its launch: each is played from its own clock's 0."""
        return self.approach.actions(dt, steps), self.flight.actions(dt, steps)


class TriggeredPolicy:
    """B dolphins, row b playing candidate ``rows[b]`` of ``sequences``: ``reset()``, then
    ``act(obs)`` once an env step; ``height_at`` is where the observation holds the height
    above the surface (BL)."""

    def __init__(self, sequences: list[TriggeredSequence], rows: np.ndarray, dt: float,
                 steps: int, height_at: int) -> None:
        tracks = [s.tracks(dt, steps) for s in sequences]
        self.approach = np.stack([a for a, _ in tracks])[rows]  # (B, steps, A)
        self.flight = np.stack([f for _, f in tracks])[rows]
        self.trigger = np.array([s.trigger_bl for s in sequences])[rows]
        self.height_at, self.steps = int(height_at), int(steps)
        self.reset()

    def reset(self, batch: int | None = None) -> None:
        """Begin B episodes (``batch``, if given, must be B): no step played, no flight
        launched."""
        if batch is not None and batch != len(self.trigger):
            raise ValueError(f"{len(self.trigger)} triggered sequences for {batch} dolphins")
        self.step = 0
        self.launched = np.full(len(self.trigger), -1)  # the env step each flight began

    def act(self, obs: np.ndarray) -> np.ndarray:
        """(B, A) env actions for the observations (B, O)."""
        k = min(self.step, self.steps - 1)
        height = np.atleast_2d(obs)[:, self.height_at]
        self.launched[(self.launched < 0) & (height >= self.trigger)] = k
        rows = np.arange(len(self.trigger))
        flying = self.launched >= 0
        actions = self.approach[:, k].copy()
        actions[flying] = self.flight[rows[flying], k - self.launched[flying]]
        self.step += 1
        return actions


class TriggeredEvaluator(BatchEvaluator):
    """Scores :class:`TriggeredSequence` candidates closed loop: each row of the vector env is
    a dolphin playing its candidate from one of the start states."""

    def __init__(self, env_id: str, env_kwargs: dict | None = None, *args, **kwargs) -> None:
        super().__init__(env_id, env_kwargs, *args, **kwargs)
        observed = int(self.env.single_observation_space.shape[0])
        self.height_at = observed - int(self.task.obs_size)  # the stunt task's first entry
        self._sequences: list[TriggeredSequence] = []

    def evaluate_players(self, players) -> tuple[np.ndarray, dict[str, np.ndarray]]:
        """:meth:`evaluate_rows` of the candidates ``players`` over the start states."""
        self._sequences = list(players)
        return self.evaluate_rows(np.repeat(np.arange(len(players)), self.num_starts))

    def _player(self, rows: np.ndarray):
        """``act(k, obs)``: each row's dolphin played by its candidate (padding rows play the
        first; their scores are dropped)."""
        policy = TriggeredPolicy(self._sequences, rows.astype(int), self.dt, self.steps,
                                 self.height_at)
        return lambda k, obs: policy.act(obs)


class TriggeredMacroLearner(MacroLearner):
    """Params: the macro learner's (``slots`` the approach's), ``flight_slots`` (3),
    ``trigger_low``/``trigger_high`` (-1 / 0.5 BL), plus the annealing parameters. Drives
    the dolphin's stunt envs."""

    name = "macro_triggered"
    own_params = TriggeredMacroParams

    def _configure(self) -> None:
        if not isinstance(task_of(self.env_id, self.env_kwargs), StuntTask):
            raise ValueError(f"learner {self.name!r} plays a dolphin stunt: it needs a stunt "
                             f"env (e.g. Animat/DolphinSomersault-v0), not {self.env_id}")
        self.flight_slots = self.own.flight_slots  # read by _x0, which a start_from checks
        super()._configure()

    def _genes(self, actuators: int) -> tuple[int, str]:
        return (2 * (self.slots + self.flight_slots) + 1,
                f"slots {self.slots} + {self.flight_slots} x 2 + the trigger")

    def _x0(self, num_actuators: int) -> np.ndarray:
        rng = np.random.default_rng(self.seed)
        x = rng.uniform(0.0, 1.0, 2 * (self.slots + self.flight_slots) + 1)
        if self.own.start_from is not None:
            x[:2 * self.slots] = super()._x0(num_actuators)
        return x

    def _parts(self, vector: np.ndarray) -> tuple[list, list, float]:
        """The approach's and the flight's [(skill, duration s)] and the trigger (BL)."""
        vector = np.asarray(vector, dtype=float)
        cut = 2 * self.slots
        approach = self.decode(vector[:cut])
        flight = decode_slots(vector[cut:-1], self.flight_slots, self.skill_names,
                              self.min_duration, self.max_duration)
        low, high = self.own.trigger_low, self.own.trigger_high
        return approach, flight, float(low + np.clip(vector[-1], 0.0, 1.0) * (high - low))

    def controller(self, vector: np.ndarray, duration: float) -> TriggeredSequence:
        approach, flight, trigger = self._parts(vector)
        return TriggeredSequence(MacroSequence(self.repertoire, approach, self.overlap),
                                 MacroSequence(self.repertoire, flight, self.overlap), trigger)

    def _evaluator(self) -> TriggeredEvaluator:
        return TriggeredEvaluator(self.env_id, self.env_kwargs, self.population, self.seed,
                                  self.own.start_states, self.own.worst_share)

    def _artefacts(self, x: np.ndarray, duration: float, evaluator) -> dict:
        approach, flight, trigger = self._parts(x)
        return {"approach": _listed(approach), "flight": _listed(flight),
                "trigger_height_bl": trigger, "height_at": int(evaluator.height_at),
                "parameters": int(x.size)}

    def agent(self, artefacts: dict, folder) -> BatchPolicyAgent:
        """The learned sequences and trigger, playing one dolphin in the run's env."""
        dt, steps = episode_timing(self.env_id, self.env_kwargs)
        sequence = TriggeredSequence(
            MacroSequence(self.repertoire, _steps(artefacts["approach"]), self.overlap),
            MacroSequence(self.repertoire, _steps(artefacts["flight"]), self.overlap),
            float(artefacts["trigger_height_bl"]))
        policy = TriggeredPolicy([sequence], np.zeros(1, int), dt, steps,
                                 int(artefacts["height_at"]))
        return BatchPolicyAgent(policy, self.env_id, self.env_kwargs)


def _listed(steps: list[tuple[str, float]]) -> list[dict]:
    return [{"skill": name, "duration": float(d)} for name, d in steps]


def _steps(listed: list[dict]) -> list[tuple[str, float]]:
    return [(step["skill"], float(step["duration"])) for step in listed]
