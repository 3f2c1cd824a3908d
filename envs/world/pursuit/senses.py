"""The pursuit's senses: its observation is its sensors' reading of the observer fish.

The sensors are those of the seam of :mod:`animat.envs.core.sensors` (``name``, ``space``,
``read``); what they read in the pursuit is an :class:`ObserverView`, the observer as one body
(B = 1). It offers what a ``BodyBatch`` offers a sensor (the sizes, ``observe``,
``proprioception``, ``task_observation``: a :class:`~animat.envs.core.sensors.Sensed`), so
:class:`~animat.envs.core.sensors.Proprioception` and ``TaskEntries`` read it as it is;
what the eyes read (``scene()``, ``eye_poses()``: a :class:`~animat.envs.vision.retina.Sighted`),
so :class:`~animat.envs.vision.retina.Retina` does; and the ``gaze``, the ``core`` and the
observer's ``row`` for any other sensor. :func:`default_sensors` are the retina (``left_eye``,
``right_eye``), :class:`Gaze` and proprioception; :class:`PursuitObserver` makes their
``Dict``, a sensor whose space is a ``Dict`` (the retina) giving each of its entries. A sensor
more is one class and ``sensors=[*default_sensors(), MySensor()]`` in the env's arguments.
"""

from __future__ import annotations

from collections.abc import Callable

import gymnasium as gym
import numpy as np

from ...core.batch import BodyBatch, Kinematics
from ...core.sensors import Observer, Proprioception, Sensed
from ...render.camera import Scene
from ...vision.retina import Retina, RetinaParams, eye_poses

THETA_RANGE, PHI_RANGE = np.radians(60.0), np.radians(30.0)  # the gaze's units, rad


class ObserverView:
    """The observer as its sensors read it: row ``row`` of ``core``, one body (B = 1).

    ``scene``: () -> :class:`Scene`, what there is to see now; ``gaze``: (4,) the gaze as
    commanded (theta_L, phi_L, theta_R, phi_R in units of ``THETA_RANGE`` and ``PHI_RANGE``;
    the env's array, updated in place); ``retina``: where the eyes sit (``eye_offset``)."""

    def __init__(self, core: BodyBatch, row: int, scene: Callable[[], Scene], gaze: np.ndarray,
                 retina: RetinaParams) -> None:
        self.core, self.row, self.gaze, self.retina = core, row, gaze, retina
        self._scene = scene

    @property
    def obs_size(self) -> int:
        """Entries of the observer's :meth:`observe`: its own state, then the task's."""
        return self.core.obs_size

    @property
    def proprioception_size(self) -> int:
        """Entries of the observer's own state (:meth:`proprioception`)."""
        return self.core.proprioception_size

    def observe(self, kinematics: Kinematics) -> np.ndarray:
        """(1, obs_size) float32: the observer's own state, then the task's entries
        (``BodyBatch.observe``)."""
        return self.core.observe(kinematics)[[self.row]]

    def proprioception(self, kinematics: Kinematics) -> np.ndarray:
        """(1, proprioception_size) float32: the observer's own state
        (``BodyBatch.proprioception``)."""
        return self.core.proprioception(kinematics)[[self.row]]

    def task_observation(self, kinematics: Kinematics) -> np.ndarray:
        """(1, obs_size - proprioception_size) float32: the task's entries for the observer
        (``BodyBatch.task_observation``; none for the pursuit's swim task)."""
        return self.core.task_observation(kinematics)[[self.row]]

    def scene(self) -> Scene:
        """What there is to see now."""
        return self._scene()

    def gaze_angles(self) -> np.ndarray:
        """(2, 2) rad: (theta, phi) of the left and the right eye, relative to the head."""
        return self.gaze.reshape(2, 2) * [THETA_RANGE, PHI_RANGE]

    def eye_poses(self, kinematics: Kinematics) -> tuple[np.ndarray, np.ndarray]:
        """(1, 2, 3) m eye positions and (1, 2, 3, 3) camera rotations (rows right, down,
        forward) of the left and the right eye, in the world
        (:func:`~animat.envs.vision.retina.eye_poses` of the observer's head)."""
        frame = kinematics.frames[self.row]
        positions, rotations = eye_poses(frame, self.core.state.x[self.row, 0],
                                         self.core.body.length, self.gaze_angles(), self.retina)
        return positions[None], rotations[None]


class Gaze:
    """The gaze as commanded (the action's last four entries, in its units):
    ``Box(-1, 1, (4,), float32)``."""

    name = "gaze"

    def space(self, view: ObserverView) -> gym.spaces.Box:
        return gym.spaces.Box(-1.0, 1.0, (4,), np.float32)

    def read(self, view: ObserverView, kinematics: Kinematics) -> np.ndarray:
        """(1, 4) float32."""
        return view.gaze[None].astype(np.float32)


class PreyPosition:
    """Privileged, for baselines only (the oracle, a state-based learner): the centre of mass
    of the fish in row ``target`` of the core (the pursuit's prey) relative to the observer's
    head (its nose), in the observer's body frame (forward, left, up), BL:
    ``Box(-LIMIT, LIMIT, (3,), float32)``, clipped."""

    name = "prey"
    LIMIT = 1000.0  # BL

    def __init__(self, target: int) -> None:
        self.target = int(target)

    def space(self, view: ObserverView) -> gym.spaces.Box:
        return gym.spaces.Box(-self.LIMIT, self.LIMIT, (3,), np.float32)

    def read(self, view: ObserverView, kinematics: Kinematics) -> np.ndarray:
        """(1, 3) float32."""
        offset = kinematics.com[self.target] - view.core.state.x[view.row, 0]
        local = kinematics.frames[view.row] @ offset / view.core.body.length
        return np.clip(local, -self.LIMIT, self.LIMIT)[None].astype(np.float32)


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

    def observe(self, view: Sensed, kinematics: Kinematics) -> dict[str, np.ndarray]:
        """Entry name -> (1, *shape) array: the sensors' readings of the observer (``view``,
        its :class:`ObserverView`)."""
        obs: dict[str, np.ndarray] = {}
        for sensor in self.sensors:
            reading = sensor.read(view, kinematics)
            obs.update(reading if isinstance(reading, dict) else {sensor.name: reading})
        return obs
