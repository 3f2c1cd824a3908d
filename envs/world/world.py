"""The living marine world: F fish of several species on one batched physics
(:class:`animat.envs.core.batch.BodyBatch`), each with a mind, the perceptual oracle, an
intention generator and behaviour routines; food particles; static obstacles; a tank.

One :meth:`MarineWorld.step` (one env step of ``dt`` s): every fish perceives
(:func:`~animat.envs.world.percepts.perceive`), its mind advances, its intention is chosen, its
behaviour gives a navigation command and the :class:`~animat.envs.motor.navigation.Navigator` turns
that into muscle and fin actions; the physics steps all fish at once; then the world's events:
food eaten (head within reach of a particle), prey caught (a predator's head within
``catch_radius`` of a prey's body: the prey is taken, and a new one enters at the tank's edge),
matings (a courting pair within ``court_distance`` for ``court_time`` s) and contacts (a body
node inside an obstacle; two fish's nodes within ``contact_distance``, a predator touching its
prey aside: that is a hunt), counted once per contact as it begins (for two fish: after they
have been apart ``apart_time`` s, so that one brush is one collision). Any fish's command or
actions can come from outside instead (:meth:`step`'s ``commands`` and ``actions``): a learner
or an eye-driven fish. The world's params, species and start places are in :mod:`.start`.
"""

from __future__ import annotations

import numpy as np

from ..core.batch import BodyBatch
from ..motor.navigation import Navigator, forward_speeds, navigation_for
from ..render.camera import yaw_matrix
from ..tasks.locomotion import SwimTask
from . import food as food_mod
from .intention import AVOID, EAT, HUNT, MATE, NAMES, IntentionGenerator
from .life import Lives
from .mind import MentalState
from .oracle import Obstacles, clearance_to, first_min_per_row, obstacles_near, pairs_within
from .percepts import perceive
from .start import WorldParams, free_spot, place_obstacles, relations


class MarineWorld:
    """The world's state and its step (see the module docstring)."""

    def __init__(self, params: WorldParams = WorldParams()) -> None:
        self.params = params
        self.habits = params.habits
        f = len(self.habits)
        self.core = BodyBatch(f, SwimTask(), duration=params.duration, fins=True,
                              water=params.water, start_spread="point")  # placed by the world
        self.dt, self.length = self.core.dt, self.core.body.length
        self.navigator = Navigator(f, navigation_for(self.core.system.water))
        self.intentions = IntentionGenerator(f, params.intention)
        self.relations = relations(self.habits)
        self.arrays = {name: np.array([getattr(h, name) for h in self.habits])
                       for name in ("eats_food", "predator", "schooling", "mates", "appetite")}
        self.cruise = np.array([h.speed for h in self.habits])
        self.sprint = np.array([h.sprint for h in self.habits])
        self.obstacles = Obstacles.none()
        self.rng = np.random.default_rng(0)
        self.time = 0.0

    @property
    def num_fish(self) -> int:
        return len(self.habits)

    # --- the start ---------------------------------------------------------------------
    def place_fish(self, row: int, position: np.ndarray, yaw: float) -> None:
        """Put fish ``row`` at rest with its head at ``position`` (3,) m, heading ``yaw`` rad
        (a start: staging a scene, a new fish entering; never a behaviour)."""
        rest = self.core.body.rest_positions
        self.core.state.x[row] = (rest - rest[0]) @ yaw_matrix(yaw).T + position
        self.core.state.v[row] = 0.0

    def reset(self, rng: np.random.Generator) -> None:
        """A new episode: obstacles, fish, food and minds drawn from ``rng``."""
        self.rng, f, p = rng, self.num_fish, self.params
        self.core.reset_rows(np.arange(f), [rng] * f)
        self.obstacles = place_obstacles(rng, p)
        taken: list[np.ndarray] = []
        schools: dict[str, tuple[np.ndarray, float]] = {}
        for row, habits in enumerate(self.habits):
            if habits.schooling and habits.name in schools:  # a school starts as one
                centre, yaw = schools[habits.name]
                taken.append(free_spot(rng, p.tank, self.obstacles, taken, near=centre))
                self.place_fish(row, taken[-1], yaw + rng.uniform(-0.3, 0.3))
                continue
            taken.append(free_spot(rng, p.tank, self.obstacles, taken))
            yaw = rng.uniform(-np.pi, np.pi)
            schools.setdefault(habits.name, (taken[-1], yaw))
            self.place_fish(row, taken[-1], yaw)
        self.core.state.origin[:] = self.core.kinematics().com
        self.food = food_mod.release(rng, p.food.count, p.tank, self.obstacles, p.food)
        angle = rng.uniform(-np.pi, np.pi)
        self.current = p.food.drift * rng.uniform(0, 1) * np.array([np.cos(angle),
                                                                   np.sin(angle), 0.0])
        mind = MentalState.start(rng.uniform(0.3, 0.8, f), rng.uniform(0.0, 0.6, f))
        self.intentions.reset()
        self.navigator.reset(np.arange(f))
        wander = self.core.kinematics().frames[:, 0].copy()  # on as it faces
        wander[:, 2] = 0.0
        self.lives = Lives(mind, self.intentions, wander,
                           rng.uniform(0.0, p.behaviour.wander_change, f), self.arrays,
                           self.cruise, self.sprint, p.mind, p.behaviour, p.tank)
        self.courting = np.zeros((f, f))
        self.obstacle_contact = np.zeros((f, len(self.obstacles.radii)), bool)
        self.fish_contact = np.zeros((f, f), bool)
        self.apart = np.full((f, f), np.inf)
        self.apart_before = self.apart.copy()
        self.meals, self.mated = np.zeros(f), np.zeros(f, bool)
        self.time, self.steps = 0.0, 0
        self.percepts = self._perceive()

    def stage(self, obstacles: Obstacles | None = None, food: np.ndarray | None = None) -> None:
        """After :meth:`reset`, set a scene by hand (tests, figures): ``obstacles``, ``food``
        (M, 3) m, and any fish moved with :meth:`place_fish` or minds set; the episode then
        starts from it."""
        if obstacles is not None:
            self.obstacles = obstacles
        if food is not None:
            self.food = np.asarray(food, float).reshape(-1, 3).copy()
        self.core.state.origin[:] = self.core.kinematics().com
        self.obstacle_contact = np.zeros((self.num_fish, len(self.obstacles.radii)), bool)
        self.intentions.focus[:] = -1  # the things it focused on may be gone
        self.percepts = self._perceive()

    # --- a step ------------------------------------------------------------------------
    def kinematics(self):
        """(heads (F, 3), headings (F, 3), com (F, 3), com_vel (F, 3))."""
        k = self.core.kinematics()
        return self.core.state.x[:, 0], k.frames[:, 0], k.com, k.com_vel

    def _perceive(self):
        heads, headings, com, com_vel = self.kinematics()
        p = self.params
        exempt = np.zeros((self.num_fish, self.num_fish), bool)
        on, focus = self.intentions.resumed, self.intentions.focus
        seeking = np.isin(on, (HUNT, MATE)) & (focus >= 0)
        exempt[np.flatnonzero(seeking), focus[seeking]] = True
        return perceive(heads, headings, com, com_vel, self.food, self.relations,
                        self.obstacles, p.tank, p.oracle, p.avoid, self.core.state.x, exempt,
                        feeding=on == EAT)

    def _focus_positions(self, intention: np.ndarray, com: np.ndarray) -> np.ndarray:
        focus = self.intentions.focus
        out = np.full((self.num_fish, 3), np.nan)
        on_food = (intention == EAT) & (focus >= 0)
        out[on_food] = self.food[focus[on_food]]
        on_fish = np.isin(intention, (HUNT, MATE)) & (focus >= 0)
        out[on_fish] = com[focus[on_fish]]
        return out

    def behaviour_commands(self) -> np.ndarray:
        """(F, 3) this step's navigation commands from every fish's mind and behaviours (and
        the intention each is acting on: :attr:`intention`)."""
        heads, headings, com, _ = self.kinematics()
        return self.lives.commands(self.percepts, heads, headings, com, self.time, self.dt,
                                   self.meals, self.mated, self.rng,
                                   lambda intention: self._focus_positions(intention, com))

    @property
    def mind(self) -> MentalState:
        return self.lives.mind

    @property
    def wander(self) -> np.ndarray:
        """(F, 3) each wanderer's heading (set its rows to stage a scene)."""
        return self.lives.wander

    @property
    def wander_due(self) -> np.ndarray:
        """(F,) s when each wanderer's heading is renewed."""
        return self.lives.wander_due

    @property
    def intention(self) -> np.ndarray:
        return self.intentions.intention

    @property
    def truncated(self) -> bool:
        """The episode's ``duration`` is over (the world's clock: a fish that entered after a
        catch does not restart it)."""
        return self.steps >= self.core.episode_steps

    def step(self, commands: dict[int, np.ndarray] | None = None,
             actions: dict[int, np.ndarray] | None = None,
             pursue: dict[int, np.ndarray] | None = None) -> dict[str, np.ndarray]:
        """Advance one env step. ``commands`` {fish: (3,) navigation command} and ``actions``
        {fish: (8,) fish-env action} replace those fish's behaviours; ``pursue`` {fish:
        command} replaces them only where this step's intention is to hunt or less urgent
        (an eye-driven hunter, whose reflexes and flight stay its own). Returns the step's
        events (see :meth:`_events`)."""
        wanted = self.behaviour_commands()
        for row, command in (pursue or {}).items():
            if self.intention[row] >= HUNT:
                wanted[row] = command
        for row, command in (commands or {}).items():
            wanted[row] = command
        forward = forward_speeds(self.core.kinematics(), self.length)
        moves = self.navigator.actions(wanted, self.time, reflex=self.intention == AVOID,
                                       forward=forward)
        for row, action in (actions or {}).items():
            moves[row] = action
        self.core.step(moves.astype(np.float64))
        self.time += self.dt
        self.steps += 1
        self.food = food_mod.drift(self.food, self.current, self.dt, self.params.tank,
                                   self.obstacles, self.params.food)
        events = self._events()
        self.percepts = self._perceive()
        return events

    # --- the world's events ------------------------------------------------------------
    def _eat(self, heads: np.ndarray) -> np.ndarray:
        p = self.params
        meals, gone = food_mod.eaten(heads, self.food, self.arrays["eats_food"], p.food)
        if gone.any():  # the feeder replaces what was eaten; no one goes on seeking it
            self.food[gone] = food_mod.release(self.rng, int(gone.sum()), p.tank,
                                               self.obstacles, p.food)
            seeking = (self.intentions.resumed == EAT) & np.isin(self.intentions.focus,
                                                                 np.flatnonzero(gone))
            self.intentions.focus[seeking] = -1
        return meals

    def _catch(self, heads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(F,) catches per predator and (F,) bool prey caught; a caught prey is taken and a
        new one of its species enters at the tank's edge."""
        x = self.core.state.x
        com = x.mean(axis=1)
        spread = np.linalg.norm(x[..., :2] - com[:, None, :2], axis=-1).max()
        hunter, prey = pairs_within(heads, com, self.params.catch_radius + spread)
        hunts = self.relations["hunts"][hunter, prey]
        hunter, prey = hunter[hunts], prey[hunts]
        reach = np.linalg.norm(x[prey] - heads[hunter, None], axis=-1).min(axis=1)
        within = reach < self.params.catch_radius
        hunter, prey, reach = hunter[within], prey[within], reach[within]
        caught = np.zeros(self.num_fish, bool)
        caught[prey] = True
        caught_by = np.zeros((self.num_fish, self.num_fish), bool)  # to the nearest hunter
        first = first_min_per_row(prey, reach, hunter)
        caught_by[hunter[first], prey[first]] = True
        prey = np.flatnonzero(caught)
        for row in prey:
            self.core.reset_rows(np.array([row]), [self.rng])
            self.intentions.reset(np.array([row]))
            for pairs, fresh in ((self.courting, 0.0), (self.fish_contact, False),
                                 (self.apart, np.inf), (self.apart_before, np.inf)):
                pairs[row, :] = pairs[:, row] = fresh  # a new fish: no past with the others
            others = [heads[k] for k in range(self.num_fish) if k != row]
            spot = free_spot(self.rng, self.params.tank, self.obstacles, others, True)
            self.place_fish(row, spot, np.arctan2(-spot[1], -spot[0]))
            self.core.state.origin[row] = self.core.kinematics().com[row]
            self.navigator.reset(np.array([row]))
            self.mind.fear[row] = 0.0
        self.mind.hunger[:] = np.clip(self.mind.hunger - 2 * self.params.mind.meal
                                      * caught_by.sum(axis=1), 0.0, 1.0)
        return caught_by.sum(axis=1).astype(float), caught

    def _mate(self, com: np.ndarray) -> np.ndarray:
        focus, intention = self.intentions.focus, self.intention
        f = self.num_fish
        pair = np.zeros((f, f), bool)
        courting = (intention == MATE) & (focus >= 0)
        pair[np.flatnonzero(courting), focus[courting]] = True
        mutual = pair & pair.T
        i, j = np.nonzero(mutual)
        mutual[i, j] = np.linalg.norm(com[i] - com[j], axis=-1) < self.params.court_distance
        self.courting = np.where(mutual, self.courting + self.dt, 0.0)
        done = self.courting >= self.params.court_time
        self.courting[done] = 0.0
        return done.any(axis=1)

    def _contacts(self) -> tuple[np.ndarray, np.ndarray]:
        """(F,) new obstacle contacts and (F,) new fish contacts of each fish this step."""
        x = self.core.state.x
        f = len(x)
        com = x.mean(axis=1)
        inside = np.zeros((f, len(self.obstacles.radii)), bool)
        fish, k = obstacles_near(x, com, self.obstacles, 0.0)
        inside[fish, k] = (clearance_to(x[fish], self.obstacles, k) < 0).any(axis=1)
        new_obstacle = (inside & ~self.obstacle_contact).sum(axis=1)
        self.obstacle_contact = inside
        i, j = pairs_within(com, com, self.length)  # broad phase
        near = (i < j) & (np.linalg.norm(com[i] - com[j], axis=-1) < self.length)
        i, j = i[near], j[near]
        d = x[i][:, :, None] - x[j][:, None]
        touch = np.einsum("pabk,pabk->pab", d, d).min(axis=(1, 2)) < self.params.contact_distance**2
        touching = np.zeros((f, f), bool)
        touching[i[touch], j[touch]] = touching[j[touch], i[touch]] = True
        touching &= ~(self.relations["hunts"] | self.relations["hunts"].T)  # catches
        self.apart = np.where(touching, 0.0, self.apart + self.dt)
        new_fish = (touching & ~self.fish_contact & (self.apart_before >= self.params.apart_time)
                    ).sum(axis=1)
        self.apart_before = self.apart.copy()
        self.fish_contact = touching
        return new_obstacle.astype(float), new_fish.astype(float)

    def school_cohesion(self, com: np.ndarray) -> float:
        """Mean distance of schooling fish from their school's centre of mass, BL (nan: no
        school of 2 or more)."""
        spreads, weights = [], []
        for name in {h.name for h in self.habits if h.schooling}:
            members = np.array([h.name == name for h in self.habits])
            if members.sum() >= 2:
                centre = com[members].mean(axis=0)
                spreads.append(np.linalg.norm(com[members] - centre, axis=1).mean())
                weights.append(members.sum())
        return float(np.average(spreads, weights=weights) / self.length) if spreads else np.nan

    def _events(self) -> dict[str, np.ndarray]:
        """The step's events, per fish (F,): ``meals`` (food particles eaten), ``catches``
        (prey caught), ``caught`` (taken by a predator), ``mated``, ``obstacle_contacts`` and
        ``fish_contacts`` (contacts begun), ``intention`` (its code); and
        ``school_cohesion_bl`` (a float)."""
        heads = self.core.state.x[:, 0]
        self.meals = self._eat(heads)
        catches, caught = self._catch(heads)
        com = self.core.kinematics().com  # after a caught fish was replaced
        self.mated = self._mate(com)
        obstacle, fish = self._contacts()
        return {"meals": self.meals.copy(), "catches": catches, "caught": caught,
                "mated": self.mated.copy(), "obstacle_contacts": obstacle,
                "fish_contacts": fish, "intention": self.intention.copy(),
                "school_cohesion_bl": self.school_cohesion(com)}


INTENTION_NAMES = NAMES
