"""``Animat/MarineWorld-v0``: the living marine world of the paper's Section 2.

## Description
The paper's scenario (its footnote 3): 10 fishes, 15 food particles and 5 static obstacles in a
6 m x 6 m tank 0.6 m deep (:mod:`animat.envs.world.world`). Every fish is the 0.30 m
mass-spring fish of :mod:`animat.envs.bodies.fish` on one batched physics, and lives by its habits
(one shark that hunts minnows; six minnows that school, forage and flee it; three angelfish
that forage, flee and court), its mind (hunger, libido, fear), the perceptual oracle (300 deg,
1.5 m; food 2.5 m), its intention generator and its behaviour routines, which act only through
its motor controllers. One fish, ``agent``, can be driven from outside instead (a learner);
with ``vision`` one predator sees through its real eyes (two foveated retinas,
:mod:`animat.envs.vision.retina`) and hunts by the paper's active vision
(:class:`animat.envs.world.pursuit.policy.ActiveVisionPolicy`, its colour model the reddish
minnow) in place of the oracle; its reflexes (collision avoidance, flight) stay the
oracle's.

## Action Space
``control="behaviour"`` (default): ``Box(-1, 1, (3,))``, ignored: every fish lives by its
behaviours. ``control="navigation"``: the agent's (speed, turn, pitch), speed mapped from
[-1, 1] to [0, 1] (:class:`animat.envs.motor.navigation.Navigator`). ``control="muscles"``:
``Box(-1, 1, (8,))``, the agent's six actuations and two fins, as the fish envs with
``fins=True``. A wrong shape or a NaN raises ``ValueError``.

## Observation Space
``Box(-1e4, 1e4, (162,), float32)``, of the agent (fish 0 without one): the fish envs' 150
proprioceptive entries, its hunger, libido and fear, and the nearest perceived food particle,
predator and prey in its body frame (BL; zeros where there is none).

## Rewards
The agent's food particles eaten plus prey caught, minus the obstacle and fish collisions it
begins, this step (``reward_food``, ``reward_catch``, ``reward_collisions`` in ``info``: they
sum to the reward).

## Info
This step's world totals: ``food_eaten``, ``catches``, ``matings``, ``obstacle_collisions``
(contacts with an obstacle begun), ``fish_collisions`` (pairs of fish that began to touch),
``school_cohesion_bl`` (mean distance of schooling fish from their school's centre, BL);
``intentions`` (F,) codes (:data:`animat.envs.world.intention.NAMES`), ``hunger``,
``libido``, ``fear`` (F,), ``time`` s; and the reward terms.

## Starting State
Obstacles, fish (random headings, 0.45 m apart and 0.3 m from obstacles), food, the current,
hunger (0.3-0.8) and libido (0-0.6) drawn from the seed.

## Episode End
No termination; truncation after ``duration`` s (60).

## Arguments
``duration`` (s, 60; in (0, 86400]), ``species`` ({name: count} of shark, minnow, angelfish;
default 1, 6, 3; each count in [0, 1000]), ``food`` (15; in [0, 10000]), ``obstacles`` (5;
in [0, 1000]), ``tank_size`` (the tank's side, 6 m; in [2, 200]: a larger world at the paper's
density is ``species`` and ``food`` times k and ``tank_size`` times sqrt(k), as ``animat
world-bench --fish`` makes it), ``agent`` (a fish index or None), ``control``,
``vision`` (a fish index or None: that fish hunts by its eyes), ``water`` (the water's fields,
``Water.from_dict``, e.g. ``{"model": "resistive"}``, the paper's; default the reactive water;
the fishes' motor controllers calibrated for its model), ``render_mode``
(``"rgb_array"``: the tank from above a corner, 480x360). Public: ``world``, ``dt``,
``body_length``, ``episode_steps``, ``episode_summary()``.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np

from ..checks import check_integer, check_number, shown
from ..core.arguments import MAX_DURATION
from ..core.batch import OBS_LIMIT
from .food import FoodParams
from .percepts import Tank
from .scene import WorldView
from .start import ANGELFISH, MINNOW, SHARK, WorldParams
from .world import MarineWorld

SPECIES = {"shark": SHARK, "minnow": MINNOW, "angelfish": ANGELFISH}
CONTROLS = ("behaviour", "navigation", "muscles")
SUMMED = ("food_eaten", "catches", "matings", "obstacle_collisions", "fish_collisions")
MAX_SPECIES_COUNT, MAX_FOOD, MAX_OBSTACLES = 1000, 10_000, 1000  # the sizes the env accepts
TANK_SIZES = (2.0, 200.0)  # m, the tank's side the env accepts
DEFAULT_DURATION = 60.0  # s, an episode where none is given


def world_params(duration: float, species: dict | None, food: int, obstacles: int,
                 water: dict | None = None, tank_size: float = 6.0) -> WorldParams:
    """The world of the env's arguments, each checked (a ValueError of one line naming it):
    ``duration`` in (0, 86400] s, ``species`` a dict of known names to counts in [0, 1000]
    with at least one fish, ``food`` in [0, 10000], ``obstacles`` in [0, 1000], ``water`` the
    water's fields (checked by ``Water.from_dict`` when the world is made), ``tank_size`` the
    tank's side in [2, 200] m."""
    check_number("duration", duration, 0.0, MAX_DURATION, "s", low_open=True)
    counts = {"shark": 1, "minnow": 6, "angelfish": 3} if species is None else species
    if not isinstance(counts, dict):
        raise ValueError(f"species must be a dict of {{name: count}}, got {shown(counts)}")
    unknown = sorted(map(str, set(counts) - set(SPECIES)))
    if unknown:
        raise ValueError(f"species: unknown {unknown}; choose from {sorted(SPECIES)}")
    counts = {name: check_integer(f"species.{name}", n, 0, MAX_SPECIES_COUNT)
              for name, n in counts.items()}
    if sum(counts.values()) < 1:
        raise ValueError(f"species must give at least one fish, got {shown(species)}")
    chosen = tuple((SPECIES[name], n) for name, n in counts.items() if n > 0)
    side = check_number("tank_size", tank_size, *TANK_SIZES, "m")
    return WorldParams(species=chosen, obstacles=check_integer("obstacles", obstacles, 0,
                                                               MAX_OBSTACLES),
                       tank=Tank(half_size=0.5 * side), duration=float(duration), water=water,
                       food=FoodParams(count=check_integer("food", food, 0, MAX_FOOD)))


class MarineSummary:
    """Episode figures from each step's info: the totals of :data:`SUMMED` and the mean
    ``school_cohesion_bl`` (the interface of :class:`animat.envs.tasks.base.EpisodeSummary`)."""

    def __init__(self) -> None:
        self.totals = dict.fromkeys(SUMMED, 0.0)
        self.cohesion: list[float] = []

    def update(self, info: dict) -> None:
        for key in SUMMED:
            self.totals[key] += float(info[key])
        if np.isfinite(info["school_cohesion_bl"]):
            self.cohesion.append(float(info["school_cohesion_bl"]))

    def summary(self) -> dict[str, float]:
        cohesion = float(np.mean(self.cohesion)) if self.cohesion else float("nan")
        return {**self.totals, "school_cohesion_bl": cohesion}


class MarineWorldEnv(gym.Env):
    """The living marine world (see the module docstring)."""

    default_duration = DEFAULT_DURATION  # s
    metadata = {"render_modes": ["rgb_array"], "render_fps": 20}

    def __init__(self, render_mode: str | None = None, duration: float = DEFAULT_DURATION,
                 species: dict | None = None, food: int = 15, obstacles: int = 5,
                 agent: int | None = None, control: str = "behaviour",
                 vision: int | None = None, water: dict | None = None,
                 tank_size: float = 6.0) -> None:
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode must be None or 'rgb_array', got {render_mode!r}")
        if control not in CONTROLS:
            raise ValueError(f"control must be one of {CONTROLS}, got {control!r}")
        self.world = MarineWorld(world_params(duration, species, food, obstacles, water,
                                              tank_size))
        f = self.world.num_fish
        for name, row in (("agent", agent), ("vision", vision)):
            if row is not None and not (isinstance(row, int) and not isinstance(row, bool)
                                        and 0 <= row < f):
                raise ValueError(f"{name} must be a fish index in [0, {f}) or None, got "
                                 f"{shown(row)}")
        if control != "behaviour" and agent is None:
            raise ValueError(f"control {control!r} needs an agent (a fish index)")
        if vision is not None and (vision == agent or not self.world.habits[vision].predator):
            raise ValueError("vision must be a predator that is not the agent (it hunts by sight)")
        self.render_mode, self.control = render_mode, control
        self.agent, self.vision = agent, vision
        self.dt, self.body_length = self.world.dt, self.world.length
        self.view = WorldView(self.world)
        size = 8 if control == "muscles" else 3
        self.action_space = gym.spaces.Box(-1.0, 1.0, (size,), np.float32)
        self.observation_space = gym.spaces.Box(-OBS_LIMIT, OBS_LIMIT,
                                                (self.world.core.obs_size + 12,), np.float32)
        self.policy = None
        if vision is not None:
            from .pursuit.policy import ActiveVisionParams, ActiveVisionPolicy

            # a hunter closes in to catch: no range keeping (the pursuit's policy keeps its
            # distance, ActiveVisionParams.hold_range_bl)
            self.policy = ActiveVisionPolicy(ActiveVisionParams(hold_range_bl=0.0),
                                             retina=self.view.retina)
        self.gaze = np.zeros(4)
        self._started = False

    @property
    def episode_steps(self) -> int:
        return self.world.core.episode_steps

    def episode_summary(self) -> MarineSummary:
        return MarineSummary()

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.world.reset(self.np_random)
        self.view.reset()
        self.gaze[:] = 0.0
        if self.policy is not None:
            self.policy.reset()
        self._started = True
        return self._observe(), self._info({}, {})

    def _me(self) -> int:
        return 0 if self.agent is None else self.agent

    def _observe(self) -> np.ndarray:
        world, me = self.world, self._me()
        k = world.core.kinematics()
        proprioception = world.core.observe(k)[me]
        p = world.percepts
        frame, head = k.frames[me], world.core.state.x[me, 0]
        seen = [p.food_position[me], p.predator_position[me], p.prey_position[me]]
        relative = [np.zeros(3) if not np.isfinite(q[0]) else frame @ (q - head) / world.length
                    for q in seen]
        mind = [world.mind.hunger[me], world.mind.libido[me], world.mind.fear[me]]
        return np.clip(np.concatenate([proprioception, mind, *relative]), -OBS_LIMIT,
                       OBS_LIMIT).astype(np.float32)

    def _vision_command(self) -> np.ndarray:
        """The vision fish's (speed, turn, pitch) from its eyes, by active vision; its gaze
        moves for the next frame."""
        world, row = self.world, self.vision
        images = self.view.eyes(row, self.gaze.reshape(2, 2) * GAZE_RANGE)
        stacked = [np.concatenate(list(eye), axis=-1) for eye in images]
        k = world.core.kinematics()
        obs = {"left_eye": stacked[0], "right_eye": stacked[1], "gaze": self.gaze,
               "proprioception": world.core.observe(k)[row]}
        action, _ = self.policy.predict(obs)
        self.gaze[:] = action[3:]
        return np.array([0.5 * (action[0] + 1.0), action[1], action[2]])

    def _outside(self, action) -> tuple[dict, dict, dict]:
        """{fish: command} and {fish: actions} that replace behaviours this step, and the
        vision fish's {fish: command} (used where it hunts: :meth:`MarineWorld.step`)."""
        commands, actions = {}, {}
        if self.control == "navigation":
            commands[self.agent] = np.array([0.5 * (action[0] + 1.0), action[1], action[2]])
        elif self.control == "muscles":
            actions[self.agent] = action.astype(np.float32)
        pursue = {} if self.vision is None else {self.vision: self._vision_command()}
        return commands, actions, pursue

    def step(self, action):
        if not self._started:
            raise RuntimeError("call reset() before step()")
        action = np.asarray(action, dtype=np.float64)
        if action.shape != self.action_space.shape or not np.all(np.isfinite(action)):
            raise ValueError(f"action must be {self.action_space.shape[0]} finite numbers, got "
                             f"{action.tolist()}")
        commands, actions, pursue = self._outside(np.clip(action, -1.0, 1.0))
        events = self.world.step(commands, actions, pursue)
        me = self._me()
        terms = {"reward_food": float(events["meals"][me]),
                 "reward_catch": float(events["catches"][me]),
                 "reward_collisions": -float(events["obstacle_contacts"][me]
                                             + events["fish_contacts"][me])}
        truncated = self.world.truncated
        return self._observe(), float(sum(terms.values())), False, truncated, self._info(
            events, terms)

    def _info(self, events: dict, terms: dict) -> dict:
        world = self.world
        info = {"food_eaten": float(events["meals"].sum()) if events else 0.0,
                "catches": float(events["catches"].sum()) if events else 0.0,
                "matings": float(events["mated"].sum()) / 2.0 if events else 0.0,
                "obstacle_collisions": float(events["obstacle_contacts"].sum())
                if events else 0.0,
                "fish_collisions": float(events["fish_contacts"].sum()) / 2.0
                if events else 0.0,
                "school_cohesion_bl": events["school_cohesion_bl"] if events
                else world.school_cohesion(world.core.kinematics().com),
                "intentions": world.intention.copy(), "hunger": world.mind.hunger.copy(),
                "libido": world.mind.libido.copy(), "fear": world.mind.fear.copy(),
                "time": world.time}
        return {**info, **(terms or dict.fromkeys(("reward_food", "reward_catch",
                                                    "reward_collisions"), 0.0))}

    def render(self):
        if self.render_mode == "rgb_array":
            return self.view.third_person()
        return None


GAZE_RANGE = np.array([np.radians(60.0), np.radians(30.0)])  # the pursuit's gaze units
