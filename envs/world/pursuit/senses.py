"""The pursuit's senses: its observation is its sensors' reading of the observer fish.

The sensors are those of the seam of :mod:`animat.envs.core.sensors` (``name``, ``space``,
``read``); what they read in the pursuit is an :class:`ObserverView`, the observers of a batch
of worlds (B of them; B = 1 for the single env), one body each. It offers what a
``BodyBatch`` offers a sensor (the sizes, ``observe``, ``proprioception``,
``task_observation``: a :class:`~animat.envs.core.sensors.Sensed`), so
:class:`~animat.envs.core.sensors.Proprioception` and ``TaskEntries`` read it as it is; what
the eyes read (``scene()``, ``eye_poses()``: a :class:`~animat.envs.vision.retina.Sighted`,
and ``eye_images()``, every world's eyes drawn in one call), so
:class:`~animat.envs.vision.retina.Retina` does; and the ``gaze`` (B, 4), the ``core`` and the
observers' ``rows`` (B,) for any other sensor (a reading is (B, ...)).
:func:`default_sensors` are the retina (``left_eye``, ``right_eye``), :class:`Gaze` and
proprioception; :class:`PursuitObserver` makes their ``Dict``, a sensor whose space is a
``Dict`` (the retina) giving each of its entries. A sensor more is one class and
``sensors=[*default_sensors(), MySensor()]`` in the env's arguments.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from ...core.batch import Kinematics
from ...core.sensors import Observer, Proprioception, Sensed, register_sensor
from ...render.camera import Scene
from ...vision.pixels import TargetEvidence
from ...vision.retina import Retina, RetinaParams
from .memory import prey_model_histogram
from .start import PREY

THETA_RANGE, PHI_RANGE = np.radians(60.0), np.radians(30.0)  # the gaze's units, rad


class ObserverView:
    """The observers of a batch of pursuit worlds as their sensors read them: ``rows`` (B,),
    each world's observer's row of ``core`` (B = 1 for the single env).

    ``worlds``: the :class:`~animat.envs.world.pursuit.worlds.PursuitWorlds` they live in: its
    ``gaze`` (B, 4) as commanded (theta_L, phi_L, theta_R, phi_R in units of ``THETA_RANGE``
    and ``PHI_RANGE``), its scenes, and its eyes drawn in one call (:meth:`eye_images`);
    ``retina``: where the eyes sit (``eye_offset``)."""

    def __init__(self, worlds) -> None:
        self.worlds, self.core, self.rows = worlds, worlds.core, worlds.observers
        self.retina = worlds.retina

    @property
    def gaze(self) -> np.ndarray:
        """(B, 4) the gaze as commanded."""
        return self.worlds.gaze

    @property
    def obs_size(self) -> int:
        """Entries of the observer's :meth:`observe`: its own state, then the task's."""
        return self.core.obs_size

    @property
    def proprioception_size(self) -> int:
        """Entries of the observer's own state (:meth:`proprioception`)."""
        return self.core.proprioception_size

    def observe(self, kinematics: Kinematics) -> np.ndarray:
        """(B, obs_size) float32: the observers' own state, then the task's entries
        (``BodyBatch.observe``)."""
        return self.core.observe(kinematics)[self.rows]

    def proprioception(self, kinematics: Kinematics) -> np.ndarray:
        """(B, proprioception_size) float32: the observers' own state
        (``BodyBatch.proprioception``)."""
        return self.core.proprioception(kinematics)[self.rows]

    def task_observation(self, kinematics: Kinematics) -> np.ndarray:
        """(B, obs_size - proprioception_size) float32: the task's entries for the observers
        (``BodyBatch.task_observation``; none for the pursuit's swim task)."""
        return self.core.task_observation(kinematics)[self.rows]

    def scene(self, world: int = 0) -> Scene:
        """What there is to see now in world ``world``."""
        return self.worlds.scene(world)

    def gaze_angles(self) -> np.ndarray:
        """(B, 2, 2) rad: (theta, phi) of each observer's left and right eye, from the head."""
        return self.worlds.gaze_angles()

    def eye_poses(self, kinematics: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        """(B, 2, 3) m eye positions and (B, 2, 3, 3) camera rotations (rows right, down,
        forward) of each observer's left and right eye, in the world
        (:func:`~animat.envs.vision.retina.eye_poses` of its head)."""
        return self.worlds.eye_poses(kinematics)

    def eye_images(self, params: RetinaParams, kinematics: Kinematics) -> np.ndarray:
        """(B, 2, levels, size, size, 3) uint8: every observer's eyes through ``params``'
        cameras, each in its own world (one call for the batch)."""
        return self.worlds.eye_images(params, kinematics)


class Gaze:
    """The gaze as commanded (the action's last four entries, in its units):
    ``Box(-1, 1, (4,), float32)``."""

    name = "gaze"

    def space(self, view: ObserverView) -> gym.spaces.Box:
        return gym.spaces.Box(-1.0, 1.0, (4,), np.float32)

    def read(self, view: ObserverView, kinematics: Kinematics) -> np.ndarray:
        """(B, 4) float32."""
        return view.gaze.astype(np.float32)


class PreyPosition:
    """Privileged, for baselines only (the oracle, a state-based learner): the centre of mass
    of the fish in row ``target`` of the core (the pursuit's prey) relative to the observer's
    head (its nose), in the observer's body frame (forward, left, up), BL:
    ``Box(-LIMIT, LIMIT, (3,), float32)``, clipped."""

    name = "prey"
    LIMIT = 1000.0  # BL

    def __init__(self, target: int) -> None:
        self.target = int(target)  # the prey's row within its world

    def space(self, view: ObserverView) -> gym.spaces.Box:
        return gym.spaces.Box(-self.LIMIT, self.LIMIT, (3,), np.float32)

    def read(self, view: ObserverView, kinematics: Kinematics) -> np.ndarray:
        """(B, 3) float32."""
        offsets = kinematics.com[view.rows + self.target] - view.core.state.x[view.rows, 0]
        local = np.stack([kinematics.frames[row] @ offset
                          for row, offset in zip(view.rows, offsets)]) / view.core.body.length
        return np.clip(local, -self.LIMIT, self.LIMIT).astype(np.float32)


def prey_evidence(levels: list[int] | tuple[int, ...] = (0, 3), size: int = 32,
                  radius: int = 2) -> TargetEvidence:
    """The ``evidence`` sensor of the pursuit: each chosen camera's backprojection of the
    pursuer's colour memory of its prey (:func:`~.memory.prey_model_histogram`, made from
    model images before any episode), the paper's perception without its controller."""
    return TargetEvidence(prey_model_histogram(), levels, size, radius)


register_sensor("gaze", Gaze)
register_sensor("prey", lambda target=PREY: PreyPosition(target))
register_sensor("evidence", prey_evidence)


def default_sensors(retina: RetinaParams = RetinaParams()) -> list:
    """The pursuit's sensors: the eyes (``left_eye``, ``right_eye``), the gaze and
    proprioception."""
    return [Retina(retina), Gaze(), Proprioception()]


class PursuitObserver(Observer):
    """The pursuit's observation, always a ``Dict``: each sensor's reading under its name, or,
    for a sensor whose space is a ``Dict`` (the retina), each of its entries under theirs."""

    def __init__(self, view: ObserverView, sensors: list) -> None:
        super().__init__(view, sensors)  # checks the list, the sensors and their names
        spaces: dict[str, gym.spaces.Space] = {}
        for sensor in self.sensors:
            space = sensor.space(view)
            entries = space.spaces if isinstance(space, gym.spaces.Dict) else {sensor.name: space}
            twice = sorted(set(entries) & set(spaces))
            if twice:
                raise ValueError(f"sensors: entry names must be unique, got {twice} twice")
            spaces.update(entries)
        self.single_space = gym.spaces.Dict(spaces)
        self.channels_first = frozenset(  # image entries whose channels come first
            s.name for s in self.sensors if getattr(s, "channels_first", False))

    def observe(self, view: Sensed, kinematics: Kinematics) -> dict[str, np.ndarray]:
        """Entry name -> (1, *shape) array: the sensors' readings of the observer (``view``,
        its :class:`ObserverView`)."""
        obs: dict[str, np.ndarray] = {}
        for sensor in self.sensors:
            reading = sensor.read(view, kinematics)
            obs.update(reading if isinstance(reading, dict) else {sensor.name: reading})
        return obs
