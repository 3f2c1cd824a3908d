"""Food particles of the living world: they sink slowly and drift with a current, rest on the
seabed, and are eaten; a feeder releases a new particle at the top of the water for every one
eaten, so the world keeps its ``count``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .oracle import Obstacles, clearance_to, first_min_per_row, obstacles_near, pairs_within
from .percepts import Tank


@dataclass(frozen=True)
class FoodParams:
    """count: particles; sink_speed: m/s down; drift: m/s, the current's largest speed (a
    steady current per episode, drawn within it); eat_radius: m from a fish's head within
    which it eats a particle; release_depth: (low, high) m under the top where new ones appear;
    clearance: m new particles keep from obstacles (and currents cannot carry them into one)."""

    count: int = 15
    sink_speed: float = 0.002
    drift: float = 0.01
    eat_radius: float = 0.08
    release_depth: tuple[float, float] = (0.15, 0.35)
    clearance: float = 0.25

    def __post_init__(self) -> None:
        if self.count < 0 or self.sink_speed < 0 or self.drift < 0 or self.eat_radius <= 0:
            raise ValueError("food: count, sink_speed and drift must be >= 0, eat_radius > 0")


def release(rng: np.random.Generator, count: int, tank: Tank, obstacles: Obstacles,
            params: FoodParams, depth: tuple[float, float] | None = None) -> np.ndarray:
    """(count, 3) m: new particles at random over the tank (not inside an obstacle), within
    ``depth`` (low, high) z m (default: ``release_depth`` under the top)."""
    low, high = depth or (tank.top_z - params.release_depth[1],
                          tank.top_z - params.release_depth[0])
    out = np.empty((count, 3))
    for k in range(count):
        for _ in range(10_000):
            point = np.array([*rng.uniform(-0.9, 0.9, 2) * tank.half_size,
                              rng.uniform(low, high)])
            if not len(obstacles.radii) or np.all(obstacles.clearance(point) > params.clearance):
                out[k] = point
                break
        else:
            raise ValueError(f"food: no place {params.clearance:g} m clear of the obstacles")
    return out


def drift(food: np.ndarray, current: np.ndarray, dt: float, tank: Tank, obstacles: Obstacles,
          params: FoodParams) -> np.ndarray:
    """(M, 3) the particles after ``dt`` s: carried by ``current`` (3,) m/s, sinking, held on
    the seabed (there the current no longer moves them), inside the tank and (the current
    parting round them) ``clearance`` m clear of obstacles."""
    moved = food + dt * (current + [0.0, 0.0, -params.sink_speed])
    on_bed = food[:, 2] <= tank.seabed_z + 1e-9
    moved[on_bed] = food[on_bed]
    particle, k = obstacles_near(moved[:, None], moved, obstacles, params.clearance)
    if len(k):
        close = clearance_to(moved[particle, None], obstacles, k)[:, 0] < params.clearance
        blocked = np.unique(particle[close])
        moved[blocked, :2] = food[blocked, :2]
    moved[:, 2] = np.maximum(moved[:, 2], tank.seabed_z)
    moved[:, :2] = np.clip(moved[:, :2], -tank.half_size, tank.half_size)
    return moved


def eaten(heads: np.ndarray, food: np.ndarray, eaters: np.ndarray,
          params: FoodParams) -> tuple[np.ndarray, np.ndarray]:
    """Which fish eat which particle this step: (F,) meals per fish, (M,) bool eaten. A particle
    within ``eat_radius`` of several eaters' heads (``eaters`` (F,) bool) goes to the nearest."""
    fish, particle = pairs_within(heads, food, params.eat_radius)
    fish, particle = fish[eaters[fish]], particle[eaters[fish]]
    distance = np.linalg.norm(heads[fish] - food[particle], axis=-1)
    within = distance < params.eat_radius
    fish, particle, distance = fish[within], particle[within], distance[within]
    gone = np.zeros(len(food), bool)
    gone[particle] = True
    winner = first_min_per_row(particle, distance, fish)  # each particle's nearest eater
    meals = np.bincount(fish[winner], minlength=len(heads)).astype(float)
    return meals, gone
