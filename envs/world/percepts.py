"""What each world fish perceives this step (:class:`Percepts`), from the perceptual oracle
(:mod:`animat.envs.world.oracle`): the nearest food, predator, prey and mate it perceives, its
schoolmates, and whether a collision is imminent (an obstacle, a tank wall, the seabed, the
top of the water layer or another fish ahead), with the way out.

Relations between fish are (F, F) bool matrices (``relations[i, j]``: fish i to fish j):
``hunts``, ``fears``, ``schools_with`` and ``courts``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .oracle import (
    Obstacles,
    OracleParams,
    clearance_to,
    first_min_per_row,
    nearest,
    obstacles_near,
    pairs_within,
    perceived,
)


@dataclass(frozen=True)
class Tank:
    """The water the world fish live in: ``half_size`` m (|x|, |y| within it), ``seabed_z``
    and ``top_z`` m (the swimming layer between them)."""

    half_size: float = 3.0
    seabed_z: float = -0.6
    top_z: float = 0.0

    def __post_init__(self) -> None:
        if not (self.half_size > 0 and self.top_z > self.seabed_z):
            raise ValueError("tank: half_size must be > 0 m and top_z above seabed_z")


@dataclass(frozen=True)
class AvoidParams:
    """look_ahead: m ahead of the head a collision is looked for; margin: m of clearance
    wanted from obstacles, walls, the seabed and the top; fish_distance: m between centres of
    mass below which a fish ahead is a collision danger."""

    look_ahead: float = 0.35
    margin: float = 0.15
    fish_distance: float = 0.3


class Percepts(NamedTuple):
    """Per fish (F,): the index of the nearest perceived food particle, predator, prey and
    mate (-1: none), their distances (m, inf: none) and positions (F, 3) (nan: none);
    ``school_centre`` and ``school_heading`` (F, 3) of the perceived schoolmates (nan: none)
    and their ``school_count``; ``danger`` (bool), with ``escape_turn`` (+1 left, -1 right,
    0 none) and ``escape_pitch`` (+1 up, -1 down, 0 none); ``food_seen`` (F, M) and
    ``fish_seen`` (F, F) bool, all that each fish perceives."""

    food: np.ndarray
    food_distance: np.ndarray
    food_position: np.ndarray
    predator: np.ndarray
    predator_distance: np.ndarray
    predator_position: np.ndarray
    prey: np.ndarray
    prey_distance: np.ndarray
    prey_position: np.ndarray
    mate: np.ndarray
    mate_distance: np.ndarray
    mate_position: np.ndarray
    school_centre: np.ndarray
    school_heading: np.ndarray
    school_count: np.ndarray
    danger: np.ndarray
    escape_turn: np.ndarray
    escape_pitch: np.ndarray
    food_seen: np.ndarray
    fish_seen: np.ndarray


def _positions(index: np.ndarray, points: np.ndarray) -> np.ndarray:
    out = np.full((len(index), 3), np.nan)
    found = index >= 0
    out[found] = points[index[found]]
    return out


def _nearest_related(seen, distance, relation, points):
    index, dist = nearest(seen & relation, distance)
    return index, dist, _positions(index, points)


def _side(headings: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """(F,) +1 where ``offsets`` (F, 3) lie to the left of ``headings`` (F, 3), else -1."""
    return np.where(headings[:, 0] * offsets[:, 1] - headings[:, 1] * offsets[:, 0] > 0,
                    1.0, -1.0)


def collision_danger(heads, headings, com, obstacles: Obstacles, tank: Tank,
                     avoid: AvoidParams, bodies: np.ndarray | None = None,
                     exempt: np.ndarray | None = None, feeding: np.ndarray | None = None,
                     pairs: tuple[np.ndarray, np.ndarray] | None = None
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(F,) danger, escape_turn, escape_pitch for heads (F, 3) going along headings (F, 3),
    centres of mass com (F, 3): an obstacle within ``margin`` of the way ahead, or of the
    body's nodes ``bodies`` (F, N, 3) (one passing alongside), or another fish ahead within
    ``fish_distance``, except those ``exempt`` (F, F) (the prey it hunts, the partner it
    courts: those it means to reach); the seabed is no danger to a fish ``feeding`` (F,)
    (food rests on it). ``pairs``: the (fish, fish) index pairs that may count, sorted, in
    place of the grid's (:func:`~animat.envs.world.oracle.perceived`)."""
    f = len(heads)
    probes = heads[:, None] + np.linspace(0.0, avoid.look_ahead, 4)[None, :, None] * headings[
        :, None]  # (F, 4, 3)
    turn, pitch = np.zeros(f), np.zeros(f)
    near = probes if bodies is None else np.concatenate([probes, bodies], axis=1)
    fish, k = obstacles_near(near, heads, obstacles, avoid.margin)
    if len(k):
        clearance = clearance_to(near[fish], obstacles, k).min(axis=1)  # per pair
        best = first_min_per_row(fish, clearance, k)
        close = best[clearance[best] < avoid.margin]
        rows, k = fish[close], k[close]
        towards = np.concatenate([obstacles.centres[k], heads[rows, 2:]], axis=1) - heads[rows]
        turn[rows] = -_side(headings[rows], towards)
    ahead = probes[:, -1]
    for axis in (0, 1):  # the tank's walls: turn towards its centre
        out = np.abs(ahead[:, axis]) > tank.half_size - avoid.margin
        turn = np.where(out & (turn == 0), _side(headings, -heads), turn)
    low = probes[:, :, 2].min(axis=1) < tank.seabed_z + avoid.margin
    if feeding is not None:
        low &= ~feeding
    pitch = np.where(low, 1.0, pitch)
    pitch = np.where(probes[:, :, 2].max(axis=1) > tank.top_z - avoid.margin, -1.0, pitch)
    i, j = pairs_within(com, com, avoid.fish_distance) if pairs is None else pairs
    i, j = i[i != j], j[i != j]
    offsets = com[j] - com[i]  # i to j
    gap = np.linalg.norm(offsets, axis=-1)
    crowd = (gap < avoid.fish_distance) & (np.einsum("pk,pk->p", offsets, headings[i]) > 0.0)
    if exempt is not None:
        crowd &= ~exempt[i, j]
    i, j, gap, offsets = i[crowd], j[crowd], gap[crowd], offsets[crowd]
    nearest_ahead = first_min_per_row(i, gap, j)
    rows = i[nearest_ahead]
    free = turn[rows] == 0
    turn[rows[free]] = -_side(headings[rows[free]], offsets[nearest_ahead[free]])
    return (turn != 0) | (pitch != 0), turn, pitch


def perceive(heads, headings, com, com_vel, food, relations: dict,
             obstacles: Obstacles, tank: Tank, oracle: OracleParams,
             avoid: AvoidParams, bodies: np.ndarray | None = None,
             exempt: np.ndarray | None = None, feeding: np.ndarray | None = None,
             pairs: tuple[np.ndarray, np.ndarray] | None = None) -> Percepts:
    """Percepts of F fish: heads (F, 3) m (the eye point), unit headings (F, 3), com and
    com_vel (F, 3); food (M, 3) m (every particle there is, eaten ones already replaced);
    ``relations`` the (F, F)
    matrices named in the module docstring; ``bodies`` (F, N, 3) the fish's nodes (their
    own sense of touch: an obstacle alongside); ``exempt`` (F, F) the fish each means to
    reach (no collision danger); ``feeding`` (F,) those the seabed does not turn back;
    ``pairs`` the (fish, fish) index pairs that may count, sorted (all others left out: the
    pursuit's worlds), in place of the grid's."""
    seen_food, food_dist = perceived(heads, headings, food, oracle.food_range, obstacles, oracle)
    food_index, food_d = nearest(seen_food, food_dist)
    seen, dist = perceived(heads, headings, com, oracle.range, obstacles, oracle, pairs)
    seen &= ~np.eye(len(com), dtype=bool)
    pred = _nearest_related(seen, dist, relations["fears"], com)
    prey = _nearest_related(seen, dist, relations["hunts"], com)
    mate = _nearest_related(seen, dist, relations["courts"], com)
    mates = seen & relations["schools_with"]
    count = mates.sum(axis=1)
    with np.errstate(invalid="ignore"):
        centre = (mates @ com) / count[:, None]
        heading = mates @ com_vel
        heading /= np.linalg.norm(heading, axis=1, keepdims=True)
    danger, turn, pitch = collision_danger(heads, headings, com, obstacles, tank, avoid,
                                           bodies, exempt, feeding, pairs)
    return Percepts(food_index, food_d, _positions(food_index, food), *pred, *prey, *mate,
                    np.where(count[:, None] > 0, centre, np.nan),
                    np.where(count[:, None] > 0, heading, np.nan), count, danger, turn, pitch,
                    seen_food, seen)
