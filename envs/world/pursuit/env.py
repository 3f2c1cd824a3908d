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

Sized for a learner (:mod:`animat.envs.vision.pixels`), the retina's place may go to
``pixels`` (the chosen cameras of both eyes, e.g. ``{"name": "pixels", "levels": [0, 3],
"size": 32}``: ``Box(0, 255, (4, 32, 32), uint8)``, grey, channel-first) or ``evidence`` (each
chosen camera's backprojection of the prey's colour memory, the paper's perception, the same
shapes); with ``frames`` they stack along their first axis.

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
``range_estimate`` (m, triangulated from the gaze), ``time`` (s), ``moved`` (whether the body
moved: False on a look within a frame), and the observer's ``com`` (3,) m and ``forward`` (3,)
(its heading), as the fish envs give them.

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
``sensors`` (a list of sensors that read the observer's view, their entries' names unique,
each a sensor or a registered one's name or ``{"name": ..., **arguments}``: ``retina``,
``pixels``, ``evidence``, ``gaze``, ``proprioception``, ``prey``; default
:func:`~animat.envs.world.pursuit.senses.default_sensors`: the retina, the gaze and
proprioception), ``oracle`` (False; True adds the privileged entry ``prey``, the prey's centre
of mass from the observer's nose in its body frame, BL
(:class:`~animat.envs.world.pursuit.senses.PreyPosition`), for the oracle baseline and
state-based learners), ``eyes`` (True; False leaves the retina out of the default sensors: a
state-based learner's observation is then the gaze, proprioception and, with the oracle, the
prey, and nothing is rendered for it), ``frames`` (1; in [1, 8]: each image entry stacked over
the last ``frames`` observations along its channels, the oldest first, a reset filling the
stack with its first reading, as pixel learners stack frames), ``water`` (the water's fields,
``Water.from_dict``, e.g. ``{"model": "resistive"}``, the paper's; default the reactive
water; the fishes' motor controllers calibrated for its model), ``render_mode``
(``"rgb_array"``: third person, 480x360; ``"retina"``: the two eyes' composites side by side,
512x1024); each checked as it enters (a bad one is a
``ValueError`` of one line naming it). Public attributes: ``dt``, ``body_length``,
``episode_steps``, ``core`` (the bodies' batch), ``view`` (what the sensors read),
``episode_summary()``, ``scene()``, ``retina_images()``.

## Vector env
``gym.make_vec("Animat/FishPursuit-v0", num_envs=N)`` is the native batched form
(:class:`~animat.envs.world.pursuit.vector.FishPursuitVectorEnv`): N worlds in one batch
(:class:`~animat.envs.world.pursuit.worlds.PursuitWorlds`, which this env runs with N = 1), the
N observers' eyes drawn in one call, the cameras over threads; world i reset with ``seed + i``
steps bit for bit as this env reset with that seed.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from .senses import ObserverView
from .shell import (
    DEFAULT_DURATION,
    FrameStack,
    check_render_mode,
    observe,
    pursuit_observer,
    pursuit_params,
    render_world,
    world_info,
    world_infos,
)
from .summary import PursuitSummary
from .worlds import PursuitWorlds


class FishPursuitEnv(gym.Env):
    """Pursuit of a prey fish by vision (see the module docstring)."""

    default_duration = DEFAULT_DURATION  # s
    metadata = {"render_modes": ["rgb_array", "retina"], "render_fps": 20}

    def __init__(self, render_mode: str | None = None, duration: float = DEFAULT_DURATION,
                 start_distance_bl: tuple[float, float] | None = None,
                 bearing_deg: tuple[float, float] = (-60.0, 60.0),
                 flee_distance_bl: float = 2.5, prey_speed: float = 0.5,
                 distractors: int = 1, passers: int = 3, occluders: bool = True,
                 glances: int = 1, sensors: list | None = None, water: dict | None = None,
                 oracle: bool = False, eyes: bool = True, frames: int = 1) -> None:
        self.render_mode = check_render_mode(render_mode)
        params = pursuit_params(duration, start_distance_bl, bearing_deg, flee_distance_bl,
                                prey_speed, distractors, passers, occluders, glances, water)
        self.worlds = PursuitWorlds(1, params)
        self.core, self.fish, self.skins = self.worlds.core, self.worlds.fish, self.worlds.skins
        self.dt, self.body_length = self.worlds.dt, self.worlds.body_length
        self.start_distance_bl, self.bearing_deg = params.start_distance_bl, params.bearing_deg
        self.glances = params.glances
        self.view = ObserverView(self.worlds)
        self.observer, space = pursuit_observer(self.view, sensors, oracle, eyes)
        self.stack = FrameStack(frames, space, self.observer.channels_first)
        self.observation_space = self.stack.space(space)
        self.action_space = gym.spaces.Box(-1.0, 1.0, (7,), np.float32)
        self._started = False

    def episode_summary(self) -> PursuitSummary:
        """A summary for the episode that :meth:`reset` just began."""
        return PursuitSummary(self.body_length, float(self.worlds.distance[0]), self.dt)

    @property
    def episode_steps(self) -> int:
        """Env steps per episode (``duration / dt``, times ``glances``)."""
        return self.core.episode_steps * self.glances

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        kinematics = self.worlds.reset([0], [self.np_random])
        self._started = True
        return self._observe(kinematics, fresh=True), self._info(kinematics, True)

    def step(self, action):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        action = np.asarray(action, dtype=np.float64)
        if action.shape != (7,) or not np.all(np.isfinite(action)):
            raise ValueError(f"action must be 7 finite numbers, got {action.tolist()}")
        action = np.clip(action, -1.0, 1.0)
        closed, moved, kinematics = self.worlds.step(action[None], [self.np_random])
        info = self._info(kinematics, moved)
        if not moved:
            return self._observe(kinematics), 0.0, False, False, info
        reward = closed[0] / self.body_length + 0.05 * info["target_in_fovea"]
        truncated = bool(self.worlds.truncated[0])
        return self._observe(kinematics), float(reward), False, truncated, info

    def scene(self):
        """What there is to see now: the fish in their skins, and the scenery."""
        return self.worlds.scene(0)

    @property
    def _scenery(self) -> list:
        return self.worlds.scenery[0]

    def retina_images(self, kinematics=None) -> np.ndarray:
        """(2, levels, size, size, 3) uint8: what the observer's eyes see now."""
        kinematics = kinematics or self.core.kinematics()
        return self.worlds.eye_images(self.worlds.retina, kinematics)[0]

    def _observe(self, kinematics, fresh: bool = False) -> dict[str, np.ndarray]:
        """The observer's observation: its sensors' reading (entry name -> array; its images
        over the last ``frames``), and with ``glances`` > 1 the looks left before the body
        moves."""
        return self.observer.row(observe(self.observer, self.view, kinematics, self.stack,
                                         fresh), 0)

    def _info(self, kinematics, moved: bool) -> dict:
        return world_info(world_infos(self.worlds, kinematics,
                                      self.worlds.eye_poses(kinematics), moved), 0)

    def render(self):
        return render_world(self.worlds, self.render_mode)
