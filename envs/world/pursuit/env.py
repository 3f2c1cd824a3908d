"""``Animat/FishPursuit-v0``: an observer fish with eyes pursues a reddish prey fish.

## Description
Fish of :mod:`animat.envs.bodies.fish` share the water (one batched simulation): the observer
(orange), whose two eyes (:mod:`animat.envs.vision.retina`) are the only way it sees; a red prey;
``distractors`` salmon fish of the prey's size and colour family (a colour histogram of their
own); and ``passers`` fish of other colours (yellow, blue, silver). All but the observer live by
the living world's mind and behaviours (:mod:`animat.envs.world`): the prey swims on at
``prey_speed`` and flees the observer, which it fears as a predator (its fear is 0.5, the
threshold of flight, with the observer ``flee_distance_bl`` away, and decays once it is far); a
distractor swims on at the prey's speed; the passers swim across the line of sight at full
speed. Every fish moves only through its motor controllers
(:mod:`animat.envs.motor.navigation`). The benchmark is the default: the prey anywhere in the
eyes' 120 deg field, 1-4 m away; ``bearing_deg=(60, 300)`` is its search variant (the prey
outside the field, behind or to a side).

## Action Space
``Box(-1, 1, (7,), float32)``: swim speed (mapped to [0, 1]), turn (positive: left; above
0.15 it starts a turn of up to 90 deg that runs to its end), pitch (the fin-MC); then the gaze
of the left and the right eye, theta (left, units of 60 deg) and phi (up, units of 30 deg),
relative to the head.

## Observation Space
``Dict``, the reading of the observer by its sensors (:mod:`animat.envs.world.pursuit.senses`;
the seam of :mod:`animat.envs.core.sensors`): the retina
(:class:`animat.envs.vision.retina.Retina`) gives ``left_eye`` and ``right_eye``
``Box(0, 255, (64, 64, 12), uint8)`` (the 4 levels' RGB stacked, level 0 = 120 deg first,
level 3 = the fovea last), ``gaze`` ``Box(-1, 1, (4,))`` (the gaze as commanded, in the
action's units) and ``proprioception`` (the fish envs' 150 entries); with ``glances`` > 1,
``glance`` ``Box(0, glances - 1, (1,))``, the looks left before the body moves. It takes
stable-baselines3's ``MultiInputPolicy`` as it is.

## Glances
With ``glances`` = G > 1 each frame (``dt``) is G env steps: the first G - 1 move the eyes
alone (the action's gaze; its swim, turn and pitch are ignored), with the scene still and the
eyes rendered again at the new gaze (reward 0, info's ``moved`` False); the last moves the
body and the world as a step does with G = 1. So the paper's foveation (a saccade from the
periphery, then a second pass in the fovea) and vergence can finish within a frame.

## Rewards
``r = (d_prev - d) / L + 0.05 * target_in_fovea`` per step: the distance closed on the prey
(body lengths L) plus a small bonus for holding it in both foveas.

## Info (ground truth, for evaluation only)
``target_in_fovea`` (the prey's centre within both foveas' 7.5 deg half-angle),
``target_distance`` (m, head to the prey's centre of mass), ``distractor_in_fovea`` and
``passer_in_fovea`` (any of them within both foveas), ``gaze``
(rad: theta_L, phi_L, theta_R, phi_R), ``vergence`` (theta_R - theta_L, rad),
``range_estimate`` (m, triangulated from the gaze), ``time`` (s).

## Scene
A sand-tiled seabed 0.5 m below, water with depth haze, and a seeded scenery per episode
(:mod:`animat.envs.world.pursuit.start`, :mod:`animat.envs.render.scenery`): 5 rocks and 12
plants on the seabed and 15 food particles floating, over 8 m x 10 m round the start; with
``occluders``, 3 boulders up to 0.9 m and 8 kelp fronds up to 1.1 m tall that rise through the
swimming layer and hide what is behind them (they do not stop a fish: there are no collisions
here). The fish wear textured skins (:func:`animat.envs.render.camera.fish_skin`):
countershading, bands and a checker.

## Starting State
The observer at the origin heading +x; the prey ``start_distance_bl`` away (default 1-4 m)
at a bearing drawn from ``bearing_deg`` (default +-60 deg: anywhere in the eyes' 120 deg
field), heading away from the observer within +-60 deg; each distractor at its own distance
and bearing from the same ranges, heading anywhere; the first passer 3 BL to the side of the
line of sight, 2 BL beyond the prey, heading across it, the others 2-4 BL to a side at
0.3-1.5 of the prey's distance (:func:`animat.envs.world.pursuit.start.place`).

## Episode End
No termination; truncation after ``duration`` s (default 20).

## Arguments
``duration`` (s, 20; in (0, 86400]), ``start_distance_bl`` (default 1-4 m: (1 / L, 4 / L)
with L = 0.3 m; within [1, 100]), ``bearing_deg`` (the prey's start bearing, deg, positive
left: (-60, 60); within [-360, 360], spanning at most 360), ``flee_distance_bl`` (2.5; in
(0, 100]), ``prey_speed`` (0.5; the swim-MC's speed, in [0, 1]), ``distractors`` (1) and
``passers`` (3) (integers in [0, 8]), ``occluders`` (True), ``glances`` (1; in [1, 4]: looks
per frame, see Glances),
``sensors`` (a list of sensors that read the observer's view, their entries' names unique;
default :func:`~animat.envs.world.pursuit.senses.default_sensors`: the retina, the gaze and
proprioception), ``oracle`` (False; True adds the privileged entry ``prey``, the prey's centre
of mass from the observer's nose in its body frame, BL
(:class:`~animat.envs.world.pursuit.senses.PreyPosition`), for the oracle baseline and
state-based learners), ``water`` (the water's fields, ``Water.from_dict``, e.g. ``{"model":
"resistive"}``, the paper's; default the reactive water; the fishes' motor controllers
calibrated for its model), ``render_mode``
(``"rgb_array"``: third person, 480x360; ``"retina"``: the two eyes' composites side by side,
512x1024); each checked as it enters (a bad one is a
``ValueError`` of one line naming it). Public attributes: ``dt``, ``body_length``,
``episode_steps``, ``view`` (what the sensors read), ``episode_summary()``, ``scene()``,
``retina_images()``.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from ...checks import check_flag, check_integer, check_number, check_range, shown
from ...core.batch import BodyBatch
from ...motor.navigation import Navigator, forward_speeds, navigation_for
from ...render.camera import Camera, Scene, fish_skin, look_at, yaw_matrix
from ...render.scenery import furnish
from ...tasks.locomotion import SwimTask
from ...vision.perception import triangulate
from ...vision.retina import Retina, RetinaParams, composite
from .others import OtherFish
from .senses import ObserverView, PreyPosition, PursuitObserver, default_sensors
from .start import DISTRACTOR, OBSERVER, PREY, SEABED_Z, colours, place, scenery
from .summary import PursuitSummary

FOVEA_HALF_ANGLE = np.radians(7.5)
MAX_DISTANCE_BL = 100.0  # the farthest start and flight distance, BL
MAX_OTHERS = 8  # distractors and passers at most, each
MAX_GLANCES = 4  # looks per frame at most


class FishPursuitEnv(gym.Env):
    """Pursuit of a prey fish by vision (see the module docstring)."""

    metadata = {"render_modes": ["rgb_array", "retina"], "render_fps": 20}

    def __init__(self, render_mode: str | None = None, duration: float = 20.0,
                 start_distance_bl: tuple[float, float] | None = None,
                 bearing_deg: tuple[float, float] = (-60.0, 60.0),
                 flee_distance_bl: float = 2.5, prey_speed: float = 0.5,
                 distractors: int = 1, passers: int = 3, occluders: bool = True,
                 glances: int = 1, sensors: list | None = None, water: dict | None = None,
                 oracle: bool = False) -> None:
        if render_mode not in (None, "rgb_array", "retina"):
            raise ValueError(f"render_mode must be None, 'rgb_array' or 'retina', got "
                             f"{render_mode!r}")
        self.render_mode = render_mode
        self.distractors = check_integer("distractors", distractors, 0, MAX_OTHERS)
        self.passers = check_integer("passers", passers, 0, MAX_OTHERS)
        self.occluders = check_flag("occluders", occluders)
        self.glances = check_integer("glances", glances, 1, MAX_GLANCES)
        self.fish = 2 + self.distractors + self.passers
        self.core = BodyBatch(self.fish, SwimTask(), duration=duration, fins=True, water=water,
                              start_spread="point")  # placed by the pursuit
        self.dt, self.body_length = self.core.dt, self.core.body.length
        metres = (1.0 / self.body_length, 4.0 / self.body_length)  # 1-4 m, BL
        self.start_distance_bl = check_range(
            "start_distance_bl", metres if start_distance_bl is None else start_distance_bl,
            1.0, MAX_DISTANCE_BL, "BL")
        self.bearing_deg = check_range("bearing_deg", bearing_deg, -360.0, 360.0, "deg")
        if self.bearing_deg[1] - self.bearing_deg[0] > 360.0:
            raise ValueError(f"bearing_deg must span at most 360 deg, got {shown(bearing_deg)}")
        self.flee_distance_bl = check_number("flee_distance_bl", flee_distance_bl, 0.0,
                                             MAX_DISTANCE_BL, "BL", low_open=True)
        self.prey_speed = check_number("prey_speed", prey_speed, 0.0, 1.0)
        self.retina = RetinaParams()
        self.navigator = Navigator(self.fish, navigation_for(self.core.system.water))
        self.others = OtherFish(self.distractors, self.passers, self.prey_speed,
                                0.5 * self.flee_distance_bl * self.body_length)
        self.gaze = np.zeros(4)
        self.view = ObserverView(self.core, OBSERVER, self.scene, self.gaze, self.retina)
        self.eyes = Retina(self.retina)  # what render() and retina_images() show
        sensors = default_sensors(self.retina) if sensors is None else sensors
        if check_flag("oracle", oracle):
            sensors = [*sensors, PreyPosition(PREY)]
        self.observer = PursuitObserver(self.view, sensors)
        self.observation_space = self.observer.single_space
        if self.glances > 1:  # how many looks are left before the body moves
            self.observation_space = gym.spaces.Dict({
                **self.observation_space.spaces,
                "glance": gym.spaces.Box(0.0, float(self.glances - 1), (1,), np.float32)})
        self.action_space = gym.spaces.Box(-1.0, 1.0, (7,), np.float32)
        self.skins = [fish_skin(self.core.body, colour)
                      for colour in colours(self.distractors, self.passers)]
        self._scenery: list = []
        self._started = False

    def episode_summary(self) -> PursuitSummary:
        """A summary for the episode that :meth:`reset` just began."""
        return PursuitSummary(self.body_length, self._distance, self.dt)

    @property
    def episode_steps(self) -> int:
        """Env steps per episode (``duration / dt``, times ``glances``)."""
        return self.core.episode_steps * self.glances

    # --- the world -----------------------------------------------------------------------
    def _place(self, row: int, position: np.ndarray, yaw: float) -> None:
        body, state = self.core.body, self.core.state
        state.x[row] = (state.x[row] - body.rest_positions[0]) @ yaw_matrix(yaw).T + position
        state.v[row] = 0.0

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        rng, rows = self.np_random, np.arange(self.fish)
        self.core.reset_rows(rows, [rng] * self.fish)
        starts = place(rng, self.body_length, self.start_distance_bl, self.bearing_deg,
                       self.distractors, self.passers)
        for row, start in enumerate(starts, start=PREY):
            self._place(row, start.position, start.yaw)
        kinematics = self.core.kinematics()  # of the placed fish
        self.core.state.origin[:] = kinematics.com
        self._scenery = scenery(rng, self.occluders)
        self.navigator.reset(rows)
        self.others.reset(kinematics.frames[:, 0])
        self.gaze[:] = 0.0
        self._time, self._glance = 0.0, 0
        self._distance = self._target_distance(kinematics)
        self._started = True
        return self._observe(kinematics), self._info(kinematics)

    def step(self, action):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        action = np.asarray(action, dtype=np.float64)
        if action.shape != (7,) or not np.all(np.isfinite(action)):
            raise ValueError(f"action must be 7 finite numbers, got {action.tolist()}")
        action = np.clip(action, -1.0, 1.0)
        kinematics = self.core.kinematics()
        if self._glance < self.glances - 1:  # a look within the frame: the eyes move alone
            self._glance += 1
            self.gaze[:] = action[3:]
            info = {**self._info(kinematics), "moved": False}
            return self._observe(kinematics), 0.0, False, False, info
        self._glance = 0
        observer = [[0.5 * (action[0] + 1.0), action[1], action[2]]]
        others = self.others.commands(self.core.state.x[:, 0], kinematics, self._time, self.dt,
                                      self.np_random)
        commands = np.concatenate([observer, others])
        moves = self.navigator.actions(commands, self._time,
                                       forward=forward_speeds(kinematics, self.body_length))
        self.gaze[:] = action[3:]
        _, _, kinematics = self.core.step(moves.astype(np.float64))
        self._time += self.dt
        distance = self._target_distance(kinematics)
        info = self._info(kinematics)
        reward = (self._distance - distance) / self.body_length + 0.05 * info["target_in_fovea"]
        self._distance = distance
        truncated = bool(self.core.truncated[OBSERVER])
        return self._observe(kinematics), float(reward), False, truncated, info

    # --- the eyes and the other senses --------------------------------------------------
    def scene(self) -> Scene:
        """What there is to see now: the three fish in their skins, and the scenery."""
        scene = furnish(Scene(seabed_z=SEABED_Z), self._scenery)
        for row in range(self.fish):
            scene.add(self.core.body, self.core.state.x[row], self.skins[row])
        return scene

    def retina_images(self, kinematics=None) -> np.ndarray:
        """(2, levels, size, size, 3) uint8: what the observer's eyes see now."""
        return self.eyes.images(self.view, kinematics or self.core.kinematics())[0]

    def _observe(self, kinematics=None) -> dict[str, np.ndarray]:
        """The observer's observation: its sensors' reading (entry name -> array), and with
        ``glances`` > 1 the looks left before the body moves."""
        kinematics = kinematics or self.core.kinematics()
        obs = self.observer.row(self.observer.observe(self.view, kinematics), 0)
        if self.glances > 1:
            obs["glance"] = np.array([self.glances - 1 - self._glance], np.float32)
        return obs

    def _target_distance(self, kinematics) -> float:
        return float(np.linalg.norm(kinematics.com[PREY] - self.core.state.x[OBSERVER, 0]))

    def _in_foveas(self, point: np.ndarray, positions, rotations) -> bool:
        for position, rotation in zip(positions, rotations):
            direction = point - position
            cosine = direction @ rotation[2] / np.linalg.norm(direction)
            if cosine < np.cos(FOVEA_HALF_ANGLE):
                return False
        return True

    def _info(self, kinematics) -> dict:
        positions, rotations = (poses[0] for poses in self.view.eye_poses(kinematics))
        angles = self.view.gaze_angles()
        baseline = float(np.linalg.norm(positions[0] - positions[1]))
        def seen(rows) -> bool:
            return any(self._in_foveas(kinematics.com[row], positions, rotations) for row in rows)

        others = DISTRACTOR + self.distractors
        return {"target_in_fovea": seen([PREY]),
                "distractor_in_fovea": seen(range(DISTRACTOR, others)),
                "passer_in_fovea": seen(range(others, self.fish)),
                "target_distance": self._target_distance(kinematics),
                "gaze": angles.reshape(-1).copy(),
                "vergence": float(angles[1, 0] - angles[0, 0]),
                "range_estimate": triangulate(angles[0, 0], angles[1, 0], baseline),
                "time": self._time, "moved": True}

    def render(self):
        if self.render_mode == "retina":
            images = self.retina_images()
            return np.concatenate([composite(images[0]), composite(images[1])], axis=1)
        if self.render_mode == "rgb_array":
            centre = self.core.kinematics().com.mean(axis=0)
            eye = centre + np.array([-1.0, -2.0, 1.2]) * self.body_length * 1.5
            camera = Camera(480, 360, 432.0, eye, look_at(eye, centre))
            return camera.render(self.scene())
        return None
