"""Gymnasium environments of the artificial fish: a single env and a native batched vector env,
both thin shells over :class:`animat.envs.core.batch.BodyBatch` (the same step code).

## Description
A 0.30 m, 0.52 kg mass-spring fish (23 nodes, 91 Voigt elements, 12 muscles in 6 actuators;
:mod:`animat.envs.bodies.fish`) in still water. It moves only by pushing water with its body faces
(the
reaction force on faces moving into the water, in its cross-flow form by default, plus skin
friction; :mod:`animat.envs.physics.forces`). Tasks: ``swim`` (forward, optionally at a target
speed), ``turn`` (by an angle, left or right), ``reach`` (a goal point). World frame: right
handed, z up, gravity -z; the fish starts at the origin heading +x, its left is +y.

## Action Space
``Box(-1, 1, (6,), float32)``; activation ``u = (a + 1) / 2`` in [0, 1] of the actuators
left-front, left-middle, left-back, right-front, right-middle, right-back. Within an env step
the activation ramps linearly from the previous action to this one (actions are piecewise
linear in time). Out-of-range values are clipped; a wrong shape, NaN or infinity raises
``ValueError`` and leaves the state unchanged. With ``fins=True``: ``(8,)``, the last two
the left and right pectoral fin angles, ``30 deg`` times the entry (held over the env step).

## Observation Space
With the default sensor (:class:`animat.envs.core.sensors.Proprioception`):
``Box(-1e4, 1e4, (150 + task entries,), float32)`` (clipped): the 23 node positions and velocities
relative to the centre of mass, in the body frame (BL and BL/s, 69 + 69), the centre-of-mass
velocity in the body frame (BL/s, 3), the world's up direction in the body frame (3), the six
current activations (6), then the task's entries (swim with a target speed: the target, 1;
turn: sin and cos of the heading error, 2; reach: the goal in the body frame, BL, 3).
With ``sensors=[...]`` of more than one, a ``Dict`` keyed by the sensors' names.

## Rewards
``r = -(mu1 E_u + mu2 E_v) dt`` (the paper's Eq. 1), ``E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2)
/ 2``. E_v: swim ``-u`` (u: velocity along the start heading, BL/s) or
``(u - target)^2``; turn: squared heading error (rad^2, the heading followed through the
episode from the start heading), plus with ``final_weight`` the squared error and settling on
the last step (:class:`~animat.envs.tasks.locomotion.TurnTask`); reach: distance to the goal
(BL), plus ``final_weight`` times it on the last step. ``info`` holds ``E_u``, ``E_v``,
``reward_ctrl``, ``reward_task`` (the two summands of the reward), ``com`` (3,) m, ``forward``
(3,), ``linear_momentum`` (3,) kg m/s and
``angular_momentum`` (3,) kg m^2/s (world frame, about the centre of mass), ``time`` s,
and the task's metrics (swim:
``speed_bl_per_s``, ``heading_deg``, ``distance_bl``; turn: ``heading_deg``,
``heading_error_deg``; reach: ``distance_bl``).

## Starting State
The rest shape at the origin heading +x, spread by the task's start distribution
(:mod:`animat.envs.tasks.start`; the fish's tasks: any heading, bent sideways by up to 20 deg,
gliding forward at up to 0.5 BL/s, drifting up to 0.2 BL/s sideways and yawing up to 30 deg/s,
moved up to 1 BL), then each node coordinate moved by uniform noise of ``reset_noise_scale``
body lengths; muscles relaxed. The tasks measure from the start heading. Reach goals are drawn
per episode. ``start_spread="point"`` starts every episode from the rest shape at rest (as
before the spread existed).

## Episode End
No termination; truncation after ``duration`` simulated seconds.

## Arguments
| argument | type | default | meaning |
|---|---|---|---|
| ``task`` | str | by id | ``"swim"``, ``"turn"``, ``"reach"`` (:data:`animat.envs.tasks.TASKS`) |
| ``body`` | str, BodySpec | ``"fish"`` | a name in :data:`animat.envs.bodies.BODIES`, or a spec |
| ``duration`` | float, s | the task's | truncation time (swim 10, turn 5, reach 20) |
| ``physics_dt`` | float, s | 1/800 | step; refused above 75% of the body's bound |
| ``frame_skip`` | int | 40 | steps per env step (``dt = physics_dt * frame_skip``) |
| ``integrator`` | str | ``"explicit"`` | or ``"implicit"`` (:class:`~envs.physics.system.System`) |
| ``water`` | dict | reactive | ``Water`` fields (:mod:`~envs.physics.system`) over the base |
| ``base_water`` | dict | none | a registered world's water (the dolphin's pool), field by field |
| ``fins`` | bool | False | the pectoral fin angles in the action space |
| ``sensors`` | list | proprioception | :mod:`animat.envs.core.sensors`; several give a Dict space |
| ``reset_noise_scale`` | float, BL | 0.005 | uniform noise on each start node coordinate |
| ``start_spread`` | dict, str | the task's | the start distribution's fields, or ``"point"`` |
| ``reward_weights`` | dict | see text | ``mu1`` 1e-4, ``mu2`` 1, ``nu1`` 1, ``nu2`` 0.01 |
| ``render_mode`` | str, None | None | ``"rgb_array"`` |
| task arguments | | | see below |

Task arguments: swim ``target_speed`` (BL/s, None); turn ``angle_deg`` (90), ``direction``
(``"left"``), ``path_weight`` (1), ``final_weight`` (0), ``settle_s`` (0.5 s); reach
``distance_bl`` ((2, 4)), ``bearing_deg`` ((-180, 180)), ``final_weight``
(20).

Every argument is checked as it enters, and a bad one is a ``ValueError`` of one line naming
it and its value: ``duration`` in (0, 86400] s (and at most 1e9 integration steps of
``physics_dt``), ``physics_dt`` in [1e-6, 1] s, ``frame_skip`` an integer in [1, 10000],
``num_envs`` in [1, 65536], ``reset_noise_scale`` in [0, 0.01] BL, each reward weight in
[0, 1e6] (:func:`animat.envs.core.arguments.check_arguments`), the water's fields
(:class:`~envs.physics.system.Water`) and the task's arguments in their ranges (each task's
docstring): so that no argument gives NaN, and a step and an episode have a bounded cost.

Public attributes (single env through ``env.unwrapped``; the vector env directly): ``dt`` (s),
``body_length`` (m), ``body`` (the ``BodySpec``), ``task`` (the :class:`~envs.tasks.base.Task`),
``episode_steps`` (env steps per episode) and ``node_positions`` (world frame, m: (N, 3), or
(B, N, 3) for the vector env; a copy). ``get_state()`` and ``set_state(state)``: everything
that changes (the bodies, the random generators), as arrays and plain values, to continue
exactly from a saved moment (:meth:`BodyVectorEnv.get_state`).
"""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from ..checks import check_integer
from ..render.camera import BodyRenderer
from ..render.seaworld import SeaWorldRenderer
from ..tasks.base import SingleEpisodeSummary
from .arguments import MAX_NUM_ENVS, validate_actions
from .env_args import BodyArgs, make_core
from .sensors import Observer
from .shell import (
    PublicSurface,
    action_space_of,
    check_render_mode,
    generator_from_state,
    make_renderer,
    parse_autoreset_mode,
    render_row,
    sub_env_seeds,
)

RENDER_FPS = 20


class BodyEnv(PublicSurface, gym.Env):
    """One fish doing one task (see the module docstring for the full description)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": RENDER_FPS}

    def __init__(self, task: str = "swim", render_mode: str | None = None,
                 sensors: list | None = None, **kwargs: Any) -> None:
        """``kwargs``: the batch's arguments and the task's (:class:`BodyArgs`; the table of
        the module's docstring)."""
        check_render_mode(render_mode)
        self.core = make_core(1, BodyArgs.of({"task": task, **kwargs}))
        self.observer = Observer(self.core, sensors)
        self.action_space = action_space_of(self.core)
        self.observation_space = self.observer.single_space
        self.render_mode = render_mode
        self.dt = self.core.dt
        self.body_length = self.core.body.length
        self.metadata = {**self.metadata, "render_fps": int(round(1.0 / self.dt))}
        self._renderer: BodyRenderer | SeaWorldRenderer | None = None
        self._started = False

    def episode_summary(self) -> SingleEpisodeSummary:
        """The task's metrics of the episode :meth:`reset` began, from each step's ``info``
        (``update(info)``, then ``summary()``)."""
        return SingleEpisodeSummary(self.task)

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.core.reset_rows(np.array([0]), [self.np_random])
        info, kinematics = self.core.measure()
        self._started = True
        obs = self.observer.row(self.observer.observe(self.core, kinematics), 0)
        return obs, {k: v[0] for k, v in info.items()}

    def step(self, action):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        actions = validate_actions(action, self.action_space.shape)[None]
        reward, info, kinematics = self.core.step(actions)
        obs = self.observer.row(self.observer.observe(self.core, kinematics), 0)
        return obs, float(reward[0]), False, bool(self.core.truncated[0]), {
            k: v[0] for k, v in info.items()}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            self._renderer = make_renderer(self.core)
        return render_row(self._renderer, self.core, 0)

    def get_state(self) -> dict:
        """Everything that changes, as arrays and plain values: the fish's state
        (:meth:`BodyBatch.get_state`) and the random generator that the next reset draws
        from. :meth:`set_state` on an env of the same arguments continues exactly from here."""
        return {"core": self.core.get_state(), "rng": self.np_random.bit_generator.state,
                "started": self._started}

    def set_state(self, saved: dict) -> None:
        """Continue from ``saved`` (:meth:`get_state`'s dict); ValueError naming what does
        not fit, before anything is changed."""
        generator = generator_from_state(saved["rng"])
        self.core.set_state(saved["core"])
        self.np_random, self._started = generator, bool(saved["started"])

    @property
    def node_positions(self) -> np.ndarray:
        """(N, 3) node positions, world frame, m (a copy)."""
        return self.core.state.x[0].copy()

    @property
    def node_velocities(self) -> np.ndarray:
        """(N, 3) node velocities, world frame, m/s (a copy)."""
        return self.core.state.v[0].copy()


class BodyVectorEnv(PublicSurface, VectorEnv):
    """B fish in one batched simulation.

    Sub-env i seeded with ``seed + i`` draws exactly what a single :class:`BodyEnv` reset with
    that seed draws, and steps bit for bit like it. ``autoreset_mode``: Gymnasium's
    ``next_step`` (default: the step after an episode's end resets it) or ``same_step`` (it is
    reset at once; the last observation is in ``info["final_obs"]``, masked by
    ``info["_final_obs"]``), the form stable-baselines3 expects.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": RENDER_FPS,
                "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, task: str = "swim", render_mode: str | None = None,
                 sensors: list | None = None,
                 autoreset_mode: str | AutoresetMode = AutoresetMode.NEXT_STEP,
                 **kwargs: Any) -> None:
        """``kwargs``: the batch's arguments and the task's (:class:`BodyArgs`; the table of
        the module's docstring)."""
        mode = parse_autoreset_mode(autoreset_mode)
        self.autoreset_mode = mode
        self.metadata = {**self.metadata, "autoreset_mode": mode}
        check_render_mode(render_mode)
        self.num_envs = check_integer("num_envs", num_envs, 1, MAX_NUM_ENVS)
        self.core = make_core(self.num_envs, BodyArgs.of({"task": task, **kwargs}))
        self.observer = Observer(self.core, sensors)
        self.single_action_space = action_space_of(self.core)
        self.single_observation_space = self.observer.single_space
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.render_mode = render_mode
        self.dt = self.core.dt
        self.body_length = self.core.body.length
        self._rngs = [seeding.np_random(None)[0] for _ in range(self.num_envs)]
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._renderer: BodyRenderer | SeaWorldRenderer | None = None
        self._started = False

    def reset(self, *, seed: int | list[int | None] | None = None, options: dict | None = None):
        seeds = sub_env_seeds(seed, self.num_envs)
        if seeds is not None:
            self._rngs = [seeding.np_random(s)[0] for s in seeds]
        self.core.reset_rows(np.arange(self.num_envs), self._rngs)
        self._autoreset[:] = False
        self._started = True
        info, kinematics = self.core.measure()
        return self.observer.observe(self.core, kinematics), self._with_masks(info)

    def step(self, actions):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        actions = validate_actions(actions, self.action_space.shape)
        reward, info, kinematics = self.core.step(actions)
        truncated = self.core.truncated.copy()
        rows = np.flatnonzero(self._autoreset)
        if rows.size:
            self.core.reset_rows(rows, [self._rngs[r] for r in rows])
            fresh, kinematics = self.core.measure()
            for key, value in info.items():
                value[rows] = fresh[key][rows] if key in fresh else 0.0
            reward[rows] = 0.0
            truncated[rows] = False
        obs = self.observer.observe(self.core, kinematics)
        terminated = np.zeros(self.num_envs, dtype=bool)
        if self.autoreset_mode == AutoresetMode.SAME_STEP:
            return self._reset_finished(obs, reward, terminated, truncated, info)
        self._autoreset = truncated
        return obs, reward, terminated, truncated, self._with_masks(info)

    def _reset_finished(self, obs, reward, terminated, truncated, info):
        """Same-step autoreset: restart finished episodes now, keeping their last obs."""
        done = terminated | truncated
        info = self._with_masks(info)
        rows = np.flatnonzero(done)
        if rows.size:
            info["final_obs"], info["_final_obs"] = self.observer.copy(obs), done.copy()
            self.core.reset_rows(rows, [self._rngs[r] for r in rows])
            obs = self.observer.observe(self.core, self.core.kinematics())
        return obs, reward, terminated, truncated, info

    def _with_masks(self, info: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        mask = np.ones(self.num_envs, dtype=bool)
        return {**info, **{f"_{k}": mask for k in info}}

    def render(self):
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            self._renderer = make_renderer(self.core)
        return tuple(render_row(self._renderer, self.core, row) for row in range(self.num_envs))

    def get_state(self) -> dict:
        """Everything that changes, as arrays and plain values: the batch's state
        (:meth:`BodyBatch.get_state`), each sub-env's random generator (what its next reset
        draws) and the pending next-step autoresets. :meth:`set_state` on a vector env of the
        same arguments continues exactly from here (a checkpointed PPO run resumes with it)."""
        return {"core": self.core.get_state(), "rngs": [g.bit_generator.state for g in self._rngs],
                "autoreset": self._autoreset.copy(), "started": self._started}

    def set_state(self, saved: dict) -> None:
        """Continue from ``saved`` (:meth:`get_state`'s dict); ValueError naming what does
        not fit, before anything is changed."""
        if len(saved["rngs"]) != self.num_envs:
            raise ValueError(f"a state of {len(saved['rngs'])} sub-envs, not {self.num_envs}")
        rngs = [generator_from_state(state) for state in saved["rngs"]]
        autoreset = np.asarray(saved["autoreset"])
        if autoreset.shape != (self.num_envs,) or autoreset.dtype != bool:
            raise ValueError(f"autoreset must be {self.num_envs} booleans, got {autoreset!r}")
        self.core.set_state(saved["core"])
        self._rngs, self._autoreset = rngs, autoreset.copy()
        self._started = bool(saved["started"])

    @property
    def node_positions(self) -> np.ndarray:
        """(B, N, 3) node positions, world frame, m (a copy)."""
        return self.core.state.x.copy()

    @property
    def node_velocities(self) -> np.ndarray:
        """(B, N, 3) node velocities, world frame, m/s (a copy)."""
        return self.core.state.v.copy()
