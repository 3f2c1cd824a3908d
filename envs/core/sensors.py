"""The sensor seam: an env's observation is assembled from a list of sensors.

A sensor has a ``name``, the observation ``space`` it gives for one body, and ``read``: its
reading of every body in the batch, (B, *shape), from the env's core and the current
:class:`~envs.core.batch.Kinematics`. With one sensor (the default, :class:`Proprioception`)
the observation is that sensor's array, a ``Box``; with several it is a ``Dict`` keyed by
their names. A new sensor is one class and ``sensors=[Proprioception(), MySensor()]`` in the
env's arguments; to keep the body's own state and the task's entries apart,
``sensors=[Proprioception(task_entries=False), TaskEntries(), MySensor()]``. The retina (the
eyes, :class:`animat.envs.vision.retina.Retina`) is a sensor like any other, for a core that
has eyes (the pursuit's observer); a body env refuses it when made.

``core`` is what the sensors read (:class:`Sensed`): the env's ``BodyBatch`` here; in the
pursuit (:mod:`animat.envs.world.pursuit.senses`) a one-body view of its observer that offers
what a ``BodyBatch`` offers :class:`Proprioception` and :class:`TaskEntries` (the sizes,
``observe``, ``proprioception``, ``task_observation``) and what the eyes read besides, the
scene and the eye poses.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol, overload

import gymnasium as gym
import numpy as np

from ..checks import check_entry_name, is_new_entry, shown
from ..vision.pixels import RetinaPixels
from ..vision.retina import Retina, RetinaParams
from .batch import OBS_LIMIT, Kinematics


class Sensed(Protocol):
    """What every sensor may read of the bodies (``core``): a :class:`BodyBatch`, or the
    pursuit's one-body view of its observer. ``obs_size - proprioception_size`` is the
    task's ``obs_size``, the length of :meth:`task_observation`'s rows."""

    @property
    def obs_size(self) -> int:
        """The length of :meth:`observe`'s rows."""
        ...

    @property
    def proprioception_size(self) -> int:
        """The length of :meth:`proprioception`'s rows."""
        ...

    def observe(self, kinematics: Kinematics) -> np.ndarray:
        """(B, ``obs_size``) float32: :meth:`proprioception`, then :meth:`task_observation`."""
        ...

    def proprioception(self, kinematics: Kinematics) -> np.ndarray:
        """(B, ``proprioception_size``) float32: the bodies' own state."""
        ...

    def task_observation(self, kinematics: Kinematics) -> np.ndarray:
        """(B, ``obs_size - proprioception_size``) float32: the task's entries."""
        ...


class Sensor(Protocol):
    """What the envs need of a sensor."""

    name: str

    def space(self, core: Sensed) -> gym.spaces.Space:
        """The observation space of one body's reading."""
        ...

    def read(self, core: Sensed, kinematics: Kinematics) -> np.ndarray:
        """(B, *shape) the reading of every body in the batch."""
        ...


class Proprioception:
    """The default sensor, float32 clipped to +-``OBS_LIMIT``: the body's own state
    (:meth:`~animat.envs.core.batch.BodyBatch.proprioception`: node positions and velocities in
    the body frame, centre-of-mass velocity, up direction, activations), then, by default, the
    task's entries (:meth:`~animat.envs.core.batch.BodyBatch.task_observation`, from
    :meth:`animat.envs.tasks.base.Task.observe`): (B, ``core.obs_size``), as
    :meth:`~animat.envs.core.batch.BodyBatch.observe`. With ``task_entries=False`` the body's
    state alone, (B, ``core.proprioception_size``); give :class:`TaskEntries` beside it for the
    rest."""

    name = "proprioception"

    def __init__(self, task_entries: bool = True) -> None:
        self.task_entries = bool(task_entries)

    def space(self, core: Sensed) -> gym.spaces.Box:
        """``Box(-OBS_LIMIT, OBS_LIMIT, (size,), float32)``, size ``core.obs_size`` (or
        ``core.proprioception_size`` without the task's entries)."""
        size = core.obs_size if self.task_entries else core.proprioception_size
        return gym.spaces.Box(-OBS_LIMIT, OBS_LIMIT, (size,), np.float32)

    def read(self, core: Sensed, kinematics: Kinematics) -> np.ndarray:
        """(B, size) float32."""
        if self.task_entries:
            return core.observe(kinematics)
        return core.proprioception(kinematics)


class TaskEntries:
    """The task's entries alone (:meth:`~animat.envs.core.batch.BodyBatch.task_observation`,
    from :meth:`animat.envs.tasks.base.Task.observe`, e.g. the goal of a reach in the body frame):
    (B, the task's ``obs_size``) float32 clipped to +-``OBS_LIMIT``; (B, 0) for a task without
    entries. Beside ``Proprioception(task_entries=False)`` it splits the default observation in
    its two parts."""

    name = "task"

    def space(self, core: Sensed) -> gym.spaces.Box:
        """``Box(-OBS_LIMIT, OBS_LIMIT, (size,), float32)``, size the task's ``obs_size``
        (``core.obs_size - core.proprioception_size``; 0 for a task without entries)."""
        size = core.obs_size - core.proprioception_size
        return gym.spaces.Box(-OBS_LIMIT, OBS_LIMIT, (size,), np.float32)

    def read(self, core: Sensed, kinematics: Kinematics) -> np.ndarray:
        """(B, size) float32."""
        return core.task_observation(kinematics)


SensorFactory = Callable[..., Any]
SENSORS: dict[str, SensorFactory] = {
    "proprioception": Proprioception, "task": TaskEntries,
    "retina": lambda **fields: Retina(RetinaParams(**fields)), "pixels": RetinaPixels,
}


@overload
def register_sensor(name: str, factory: None = None) -> Callable[[SensorFactory],
                                                                   SensorFactory]: ...
@overload
def register_sensor(name: str, factory: SensorFactory) -> SensorFactory: ...
def register_sensor(name: str, factory=None):
    """Register ``factory`` (a sensor class, or a function of keyword arguments returning a
    sensor) under ``name``, so that an env's ``sensors`` list, and so a config, may name it:
    ``"name"`` or ``{"name": "name", **its keyword arguments}``. A plain call or a decorator;
    either returns the factory. Refused with a ValueError of one line: a name that is not a
    non-empty string, or one taken by another factory."""
    check_entry_name("register_sensor", name)
    if factory is None:
        return lambda given: register_sensor(name, given)
    if not callable(factory):
        raise ValueError(f"register_sensor({name!r}, ...): not callable: {shown(factory)}")
    if is_new_entry("register_sensor", "sensor", SENSORS, name, factory):
        SENSORS[name] = factory
    return factory


def make_sensor(spec: Any) -> Any:
    """A sensor from ``spec``: a sensor (returned as it is), a registered name, or a mapping
    ``{"name": ..., **keyword arguments}``; a ValueError of one line for an unknown name or
    bad arguments."""
    if isinstance(spec, str):
        spec = {"name": spec}
    if not isinstance(spec, dict):
        return spec
    fields = dict(spec)
    name = fields.pop("name", None)
    if not (isinstance(name, str) and name in SENSORS):
        raise ValueError(f"unknown sensor {shown(name)}; registered: {sorted(SENSORS)}")
    try:
        return SENSORS[name](**fields)
    except TypeError as error:
        raise ValueError(f"sensor {name!r}: {error}") from None


class Observer:
    """Assembles the observation of a batch from ``sensors`` (default: proprioception): each a
    sensor, or a registered sensor's name or ``{"name": ..., **arguments}``
    (:func:`make_sensor`)."""

    def __init__(self, core: Sensed, sensors: list | None = None) -> None:
        if sensors is not None and not isinstance(sensors, (list, tuple)):
            raise ValueError(f"sensors must be a list of sensors, got {shown(sensors)}")
        self.sensors = [make_sensor(s) for s in sensors] if sensors else [Proprioception()]
        for sensor in self.sensors:
            if not all(hasattr(sensor, a) for a in ("name", "space", "read")):
                raise ValueError(f"sensors: each must have a name, space() and read() "
                                 f"(animat.envs.core.sensors.Sensor), got {shown(sensor)}")
        names = [s.name for s in self.sensors]
        if len(set(names)) != len(names):
            raise ValueError(f"sensor names must be unique, got {names}")
        if len(self.sensors) == 1:
            self.single_space = self.sensors[0].space(core)
        else:
            self.single_space = gym.spaces.Dict({s.name: s.space(core) for s in self.sensors})

    def observe(self, core: Sensed, kinematics: Kinematics):
        """(B, ...) array, or a dict of them by sensor name."""
        if len(self.sensors) == 1:
            return self.sensors[0].read(core, kinematics)
        return {s.name: s.read(core, kinematics) for s in self.sensors}

    def row(self, obs, index: int):
        """Body ``index``'s observation out of a batch's."""
        if isinstance(obs, dict):
            return {k: v[index] for k, v in obs.items()}
        return obs[index]

    @staticmethod
    def copy(obs):
        return {k: v.copy() for k, v in obs.items()} if isinstance(obs, dict) else obs.copy()
