"""What a user's module registers, and the registries put back afterwards: a task of the
user's own (:class:`DiveTask`, go down), and :func:`restored_registries`, which leaves every
registry (bodies, tasks, env ids, learners) as it found it, so that nothing a test registers
reaches another test (``tests/conftest.py`` offers it as the fixture ``registries_restored``)."""

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass

import gymnasium as gym
import numpy as np

from animat.envs.registration import ENVS
from animat.envs.tasks import TASKS
from animat.envs.tasks.base import Task, World


@contextmanager
def restored_registries() -> Iterator[None]:
    """Every registry as it was on entry, again on exit: bodies, tasks, the env table and
    Gymnasium's ids, the learners and what each drives (the tables are cleared and refilled,
    not replaced: the package's modules hold them)."""
    from animat.envs.bodies import BODIES
    from animat.learners.registry import LEARNERS
    from animat.learners.validation import DRIVES

    tables: list[dict] = [BODIES, TASKS, ENVS, LEARNERS, DRIVES]
    saved = [dict(table) for table in tables]
    ids = set(gym.registry)
    try:
        yield
    finally:
        for table, before in zip(tables, saved):
            table.clear()
            table.update(before)
        for env_id in set(gym.registry) - ids:
            del gym.registry[env_id]


@dataclass
class DiveTask(Task):
    """Go down: E_v = z (BL, the centre of mass's height over its start, weighted by
    ``weight``); observation: that height; metric ``depth_bl``, its mean over the episode."""

    weight: float = 1.0
    obs_size = 1
    default_duration = 1.0
    mean_metrics = ("depth_bl",)

    def __post_init__(self) -> None:
        super().__post_init__()
        if not 0.0 <= self.weight <= 10.0:
            raise ValueError(f"weight must be in [0, 10], got {self.weight!r}")

    def observe(self, world: World) -> np.ndarray:
        return world.com[:, 2:3] / world.length

    def terms(self, world: World, last: np.ndarray):
        height = world.com[:, 2] / world.length
        return self.weight * height, {"depth_bl": -height}, world.memory


def user_id_known() -> bool:
    """Whether this process's Gymnasium registry holds the env id of
    :mod:`tests.support.user_animals` (what a spawned worker knows)."""
    import animat  # noqa: F401

    return "UserAnimals/EelDive-v0" in gym.registry
