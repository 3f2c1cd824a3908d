"""A closed-loop stunt controller: the dolphin's next repertoire skill chosen, every
``interval_s``, from what it senses, as the fish's switching table chooses its moves from the
goal's bearing and range (:mod:`animat.learners.skills.steering`); the open-loop macro
controller (:mod:`animat.learners.macro`) fixes one sequence for every start.

What the dolphin senses is read off its own observation (a dolphin stunt env's:
:meth:`animat.envs.core.batch.BodyBatch.proprioception`, then the stunt task's entries):

* ``height_bl``: its centre of mass above the surface, BL (the stunt task's first entry);
* ``pitch_deg``: its nose above the horizontal, deg (from the world's up in its body frame);
* ``speed_bl``: its centre of mass's speed along its body axis, BL/s.

Each is split into bins at its edges (:data:`SENSE_EDGES`); a table names a move for every
cell: rest (the muscles relaxed) or one of the stunt's skills. A skill chosen again goes on from
where it is; a new one starts from its beginning. A skill whose abstraction repeats within the
episode it was learned over (a beat: the swim, the arcs, the spins) plays as long as it is
chosen; one that spans its episode (a turn) plays at most that long, then the dolphin rests
until the table chooses afresh (a turn chosen again then starts again). Nothing in a skill or
the table is told the stunt's answer: the table is learned (:class:`StuntTableLearner`).
"""

from __future__ import annotations

import numpy as np

from ..controllers.repertoire import REST, Repertoire, play_skills, switch_skills

SENSES = ("height_bl", "pitch_deg", "speed_bl")
# Where each sense is split into bins: deep under, near the surface, breaking it, in the air;
# pitched down steeply, down, level-ish up, up, steeply up; slow, cruising, fast.
SENSE_EDGES = {"height_bl": (-1.0, -0.25, 0.0), "pitch_deg": (-30.0, 0.0, 30.0, 60.0),
               "speed_bl": (1.0, 2.0)}
OBS_FRAME = 6  # the centre of mass's velocity (3) and the world's up (3), in the body frame


def table_shape(edges: dict[str, tuple[float, ...]] = SENSE_EDGES) -> tuple[int, ...]:
    """The table's shape: one axis per sense, one bin more than its edges."""
    return tuple(len(edges[name]) + 1 for name in SENSES)


def senses(obs: np.ndarray, proprioception_size: int, actions: int) -> np.ndarray:
    """(B, 3) the senses (:data:`SENSES`) of observations ``obs`` (B, O) of a stunt env whose
    proprioception is ``proprioception_size`` long over ``actions`` actuators."""
    frame = proprioception_size - actions - OBS_FRAME  # after the nodes' positions and speeds
    velocity, up = obs[:, frame:frame + 3], obs[:, frame + 3:frame + 6]
    pitch = np.degrees(np.arcsin(np.clip(up[:, 0], -1.0, 1.0)))  # the nose's share of up
    return np.stack([obs[:, proprioception_size], pitch, velocity[:, 0]], axis=1)


class StuntTable:
    """The policy of B dolphins at once: ``reset(B)``, then ``act(obs)`` once an env step.

    Args:
        repertoire: the skills; ``skills`` the names a table's codes 1, 2, ... play (0 rests).
        tables: (*shape) codes for every dolphin, or (B, *shape) one per dolphin.
        dt: s, the env step; interval_s: s between decisions (at least one env step).
        layout: (proprioception size, actuators) of the env's observation.
        edges: the senses' bin edges (:data:`SENSE_EDGES`).
    """

    def __init__(self, repertoire: Repertoire, skills: list[str], tables: np.ndarray,
                 dt: float, interval_s: float, layout: tuple[int, int],
                 edges: dict[str, tuple[float, ...]] = SENSE_EDGES) -> None:
        self.controllers = [repertoire[name].controller for name in skills]
        self.durations = np.array([repertoire[name].duration for name in skills] + [np.inf])
        # a beat repeats within its episode; a turn's abstraction spans it (mirrored)
        self.periodic = np.array([c.period < d - 1e-9 for c, d in
                                  zip(self.controllers, self.durations)] + [True])
        self.shape, self.edges = table_shape(edges), [np.asarray(edges[n]) for n in SENSES]
        self.tables = self._checked(np.asarray(tables), len(skills))
        self.dt, self.layout = float(dt), layout
        self.every = max(1, int(round(interval_s / self.dt)))
        self.reset(len(self.tables) if self.tables.ndim == len(self.shape) + 1 else 1)

    def _checked(self, tables: np.ndarray, skills: int) -> np.ndarray:
        if (tables.shape[-len(self.shape):] != self.shape
                or tables.ndim not in (len(self.shape), len(self.shape) + 1)
                or not np.issubdtype(tables.dtype, np.integer)
                or tables.min() < 0 or tables.max() > skills):
            raise ValueError(f"a stunt table must be integers in [0, {skills}] of shape "
                             f"{self.shape} (one axis per sense: {', '.join(SENSES)}), got "
                             f"shape {tables.shape}")
        return tables

    def reset(self, batch: int) -> None:
        """Begin B episodes: every dolphin resting, no step played."""
        if self.tables.ndim == len(self.shape) + 1 and len(self.tables) != batch:
            raise ValueError(f"{len(self.tables)} stunt tables for {batch} dolphins")
        self.skill = np.full(batch, REST)
        self.clock = np.zeros(batch, dtype=int)  # env steps played of the current skill
        self.step = 0

    def choose(self, sensed: np.ndarray) -> np.ndarray:
        """(B,) the skill index (or :data:`REST`) each dolphin's table names for its senses
        (B, 3); a dolphin whose senses are not finite rests."""
        cells = tuple(np.searchsorted(edges, np.nan_to_num(sensed[:, k]))
                      for k, edges in enumerate(self.edges))
        tables = self.tables if self.tables.ndim > len(self.shape) else self.tables[None]
        codes = tables[(np.arange(len(sensed)) % len(tables),) + cells]
        return np.where(np.isfinite(sensed).all(axis=1), codes - 1, REST)

    def act(self, obs: np.ndarray) -> np.ndarray:
        """(B, A) env actions in [-1, 1] for the observations (B, O)."""
        if self.step % self.every == 0:
            switch_skills(self.skill, self.clock,
                          self.choose(senses(np.atleast_2d(obs), *self.layout)),
                          self.durations, self.periodic, self.dt)
        u = play_skills(self.controllers, self.durations, self.periodic, self.skill,
                        self.clock, self.dt, self.layout[1])
        self.step += 1
        return (2.0 * np.clip(u, 0.0, 1.0) - 1.0).astype(np.float32)
