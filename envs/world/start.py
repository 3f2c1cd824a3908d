"""What a marine world is made of and where its episodes start: the paper's species
(:data:`SHARK`, :data:`MINNOW`, :data:`ANGELFISH`), the world's params
(:class:`WorldParams`), the species' relations to one another (:func:`relations`), and the
drawing of start places for the obstacles (:func:`place_obstacles`) and the fish
(:func:`free_spot`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .behaviours import BehaviourParams
from .food import FoodParams
from .intention import IntentionParams
from .mind import Habits, MindParams
from .oracle import Obstacles, OracleParams
from .percepts import AvoidParams, Tank

SHARK = Habits("shark", (70, 85, 120), predator=True, prey=("minnow",), eats_food=False,
               speed=0.7)
MINNOW = Habits("minnow", (220, 50, 40), schooling=True, fears=("shark",), speed=0.6,
                sprint=0.8, appetite=0.7)
ANGELFISH = Habits("angelfish", (230, 210, 40), mates=True, fears=("shark",), speed=0.5,
                   sprint=0.8)
PAPER_SPECIES = ((SHARK, 1), (MINNOW, 6), (ANGELFISH, 3))  # 10 fishes
MAX_TRIES, NEAR_TRIES = 10_000, 200  # random draws for a start place before giving up


@dataclass(frozen=True)
class WorldParams:
    """The world: ``species`` ((Habits, count), ...); ``obstacles`` (count of pillars);
    ``obstacle_radius`` (low, high) m; the other parts' params; ``catch_radius``,
    ``court_distance`` m, ``court_time`` s, ``contact_distance`` m, ``apart_time`` s (see
    :mod:`animat.envs.world.world`);
    ``duration`` s per episode; ``water`` the water's fields (``Water.from_dict``, e.g.
    ``{"model": "resistive"}``, the paper's; default the default, reactive, water), the fishes'
    motor controllers calibrated for its model."""

    species: tuple = PAPER_SPECIES
    obstacles: int = 5
    obstacle_radius: tuple[float, float] = (0.12, 0.25)
    tank: Tank = field(default_factory=Tank)
    food: FoodParams = field(default_factory=FoodParams)
    mind: MindParams = field(default_factory=MindParams)
    intention: IntentionParams = field(default_factory=IntentionParams)
    behaviour: BehaviourParams = field(default_factory=BehaviourParams)
    oracle: OracleParams = field(default_factory=OracleParams)
    avoid: AvoidParams = field(default_factory=AvoidParams)
    catch_radius: float = 0.1
    court_distance: float = 0.3
    court_time: float = 2.0
    contact_distance: float = 0.02
    apart_time: float = 1.0
    duration: float = 60.0
    water: dict | None = None

    def __post_init__(self) -> None:
        if not self.species or any(count < 1 for _, count in self.species):
            raise ValueError("world: species needs at least one (habits, count >= 1)")
        if self.obstacles < 0 or not 0 < self.obstacle_radius[0] <= self.obstacle_radius[1]:
            raise ValueError("world: obstacles must be >= 0 and 0 < obstacle_radius low <= high")

    @property
    def habits(self) -> list[Habits]:
        """(F,) the habits of each fish, species by species."""
        return [h for h, count in self.species for _ in range(count)]


def relations(habits: list[Habits]) -> dict[str, np.ndarray]:
    """(F, F) bool ``hunts``, ``fears``, ``schools_with``, ``courts`` (sexes alternate within
    a species: its even members female, odd male)."""
    f = len(habits)
    index = {}
    sex = np.zeros(f, int)
    for k, h in enumerate(habits):
        sex[k] = index.setdefault(h.name, 0) % 2
        index[h.name] += 1
    same = np.array([[a.name == b.name for b in habits] for a in habits]) & ~np.eye(f, dtype=bool)
    return {"hunts": np.array([[a.predator and b.name in a.prey for b in habits]
                               for a in habits]),
            "fears": np.array([[b.name in a.fears for b in habits] for a in habits]),
            "schools_with": same & np.array([h.schooling for h in habits])[:, None],
            "courts": same & np.array([h.mates for h in habits])[:, None]
            & (sex[:, None] != sex[None])}


def place_obstacles(rng: np.random.Generator, p: WorldParams) -> Obstacles:
    """``p.obstacles`` pillars drawn from ``rng`` in the middle of the tank, 0.5 m apart;
    ValueError if they do not fit."""
    tank = p.tank
    centres, radii = [], []
    for _ in range(MAX_TRIES):
        if len(centres) == p.obstacles:
            break
        c = rng.uniform(-0.6, 0.6, 2) * tank.half_size
        r = rng.uniform(*p.obstacle_radius)
        if all(np.linalg.norm(c - o) > r + q + 0.5 for o, q in zip(centres, radii)):
            centres.append(c)
            radii.append(r)
    else:
        raise ValueError(f"world: {p.obstacles} obstacles do not fit 0.5 m apart in the "
                         f"middle of a {2 * tank.half_size:g} m tank")
    return Obstacles(np.array(centres).reshape(-1, 2), np.array(radii),
                     np.full(len(radii), tank.top_z + 0.1))


def free_spot(rng: np.random.Generator, tank: Tank, obstacles: Obstacles,
              taken: list[np.ndarray], edge: bool = False,
              near: np.ndarray | None = None) -> np.ndarray:
    """A start point drawn from ``rng``, 0.3 m clear of ``obstacles`` and 0.45 m from those
    ``taken``: anywhere in the tank, on its rim (``edge``), or within 0.8 m of ``near`` (3,)
    (after ``NEAR_TRIES`` draws that find none there, anywhere); ValueError if none is
    found."""
    placed = np.asarray(taken, float).reshape(-1, 3)
    for attempt in range(MAX_TRIES):
        xy = rng.uniform(-0.8, 0.8, 2) * tank.half_size
        if near is not None and attempt < NEAR_TRIES:
            xy = np.clip(near[:2] + rng.uniform(-0.8, 0.8, 2), -0.8 * tank.half_size,
                         0.8 * tank.half_size)
        if edge:  # on the rim of the tank
            side = rng.integers(2)
            xy[side] = np.sign(xy[side] or 1.0) * 0.85 * tank.half_size
        z = rng.uniform(tank.seabed_z + 0.2, tank.top_z - 0.2)
        point = np.array([*xy, z])
        if np.all(obstacles.clearance(point) > 0.3) and np.all(
                np.linalg.norm(placed - point, axis=1) > 0.45):
            return point
    raise ValueError(f"world: no start 0.45 m from {len(taken)} fish and 0.3 m from the "
                     f"obstacles in a {2 * tank.half_size:g} m tank: too many fish")
