"""The state of a fish batch: :class:`BodyState`, everything that changes while B fish move,
with its copy and its checked restore (what
:meth:`animat.envs.core.batch.BodyBatch.get_state` and ``set_state`` hand over).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..bodies.spec import BodySpec
from ..tasks.base import Task


@dataclass
class BodyState:
    """Everything that changes while B fish move (arrays changed in place by
    :meth:`~animat.envs.core.batch.BodyBatch.step` and
    :meth:`~animat.envs.core.batch.BodyBatch.reset_rows`).

    Attributes:
        x, v: (B, N, 3) node positions (m) and velocities (m/s), world frame.
        u_prev, u_prev2: (B, A) the actuations of the last two env steps, in [0, 1].
        fins: (B, P) fin angles held over the current env step, rad.
        steps: (B,) env steps since each episode began.
        origin: (B, 3) centre of mass at each episode's start, m.
        targets: (B, T) each episode's task parameters (:meth:`animat.envs.tasks.base.Task.sample`).
        splash: (B,) the splash of the last env step: the impact momentum of the faces that
            went under the surface, kg m/s (:func:`animat.envs.physics.forces.add_face_forces`).
        memory: (B, M) what the task keeps over an episode (``Task.memory_size``).
        ball: (B, 6) the beach ball's position (m) and velocity (m/s), if the task has one.
        touch: (B, 3) the ball's contact impulse with each body part this episode, N s.
        start_yaw: (B,) the yaw of each episode's start heading, rad
            (:func:`animat.envs.tasks.start.spread_start`).
    """

    x: np.ndarray
    v: np.ndarray
    u_prev: np.ndarray
    u_prev2: np.ndarray
    fins: np.ndarray
    steps: np.ndarray
    origin: np.ndarray
    targets: np.ndarray
    splash: np.ndarray
    memory: np.ndarray
    ball: np.ndarray
    touch: np.ndarray
    start_yaw: np.ndarray

    @classmethod
    def zeros(cls, num_envs: int, body: BodySpec, task: Task) -> BodyState:
        n, a, p = body.num_nodes, body.num_actuators, body.num_fins
        return cls(np.zeros((num_envs, n, 3)), np.zeros((num_envs, n, 3)),
                   np.zeros((num_envs, a)), np.zeros((num_envs, a)), np.zeros((num_envs, p)),
                   np.zeros(num_envs, dtype=np.int64), np.zeros((num_envs, 3)),
                   np.zeros((num_envs, task.target_size)), np.zeros(num_envs),
                   np.zeros((num_envs, task.memory_size)), np.zeros((num_envs, 6)),
                   np.zeros((num_envs, 3)), np.zeros(num_envs))

    def copy_arrays(self) -> dict[str, np.ndarray]:
        """A copy of every array, by name."""
        return {f.name: getattr(self, f.name).copy() for f in fields(BodyState)}

    def restore(self, saved: dict[str, np.ndarray]) -> None:
        """Continue from ``saved`` (:meth:`copy_arrays`'s dict); ValueError naming the first
        entry that does not fit this state (wrong name, dtype or shape; bodies not finite),
        before anything is changed. A state saved before start headings existed has no
        ``start_yaw``: its episodes started heading +x (0)."""
        names = [f.name for f in fields(BodyState)]
        if "start_yaw" not in saved:
            saved = {**saved, "start_yaw": np.zeros_like(self.start_yaw)}
        if sorted(saved) != sorted(names):
            raise ValueError(f"a fish state has the entries {names}, got {sorted(saved)}")
        arrays = {}
        for name in names:
            current, value = getattr(self, name), np.asarray(saved[name])
            if value.shape != current.shape or value.dtype != current.dtype:
                raise ValueError(f"fish state {name!r} must be {current.dtype} of shape "
                                 f"{current.shape}, got {value.dtype} of shape {value.shape}")
            if name in ("x", "v") and not np.isfinite(value).all():  # (task memory may be)
                raise ValueError(f"fish state {name!r} is not finite")
            arrays[name] = value.copy()
        for name, value in arrays.items():
            setattr(self, name, value)
