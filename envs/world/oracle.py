"""The perceptual oracle of world fish (the paper's footnote 4, after Tu and Terzopoulos): what
each fish perceives, read from the world model rather than from rendered eyes.

A fish perceives a thing when it is within range (``range`` m for fish and obstacles, the
longer ``food_range`` m for food), inside its ``field_deg`` field of view about its heading
(300 deg: all but a blind cone behind) or within ``lateral_line`` m (a fish feels what moves
close to it all round), and not hidden behind an obstacle. Obstacles are
vertical cylinders standing on the seabed (:class:`Obstacles`); a line of sight is hidden when
it passes through one below its top. All functions are batched: F observers, T targets.

Only the pairs within reach are looked at, so that the cost grows with the number of fish,
not its square: :func:`pairs_within` returns every (query, point) pair whose horizontal
distance may be below ``reach`` (those in the cells of a uniform grid over the tank's floor
plan that the query's reach overlaps: a superset, never missing one), and the callers (here,
:mod:`~animat.envs.world.percepts`, :mod:`~animat.envs.world.world`,
:mod:`~animat.envs.world.food`) apply their exact test to those pairs alone, with the same
arithmetic as on all pairs, so a world steps the same whether a pair was looked at or not.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# --- which things are near which: a grid over the tank's floor plan -------------------------
_KEY = np.int64(1 << 31)  # cell (i, j) -> i * _KEY + j (cell indices far below 2^30)
ALL_PAIRS = 4096  # up to this many (query, point) pairs, all are returned without a grid


def _cells(xy: np.ndarray, cell: float) -> tuple[np.ndarray, np.ndarray]:
    return (np.floor(xy[:, 0] / cell).astype(np.int64),
            np.floor(xy[:, 1] / cell).astype(np.int64))


def _ranges(starts: np.ndarray, counts: np.ndarray) -> np.ndarray:
    """The concatenation of ``arange(s, s + c)`` for each start s and count c."""
    total = int(counts.sum())
    if total == 0:
        return np.zeros(0, np.int64)
    offsets = np.repeat(np.cumsum(counts) - counts, counts)
    return np.arange(total, dtype=np.int64) - offsets + np.repeat(starts, counts)


def pairs_within(queries: np.ndarray, points: np.ndarray, reach: float
                 ) -> tuple[np.ndarray, np.ndarray]:
    """(q, p) index arrays, sorted by q then p: every pair of ``queries`` (Q, >=2) and
    ``points`` (P, >=2) m whose horizontal (x, y) distance is below ``reach`` m, and some
    farther ones (the points in the cells of side ``reach`` next to the query's; every pair
    when there are at most :data:`ALL_PAIRS`)."""
    if len(queries) == 0 or len(points) == 0 or not reach > 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    if len(queries) * len(points) <= ALL_PAIRS:  # few: every pair costs less than the grid
        return (np.repeat(np.arange(len(queries)), len(points)),
                np.tile(np.arange(len(points)), len(queries)))
    cell = float(reach)
    pi, pj = _cells(np.asarray(points, float), cell)
    keys = pi * _KEY + pj
    order = np.argsort(keys, kind="stable")
    sorted_keys = keys[order]
    qi, qj = _cells(np.asarray(queries, float), cell)
    found_q, found_p = [], []
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            wanted = (qi + di) * _KEY + (qj + dj)
            low = np.searchsorted(sorted_keys, wanted, "left")
            counts = np.searchsorted(sorted_keys, wanted, "right") - low
            found_q.append(np.repeat(np.arange(len(queries)), counts))
            found_p.append(order[_ranges(low, counts)])
    q, p = np.concatenate(found_q), np.concatenate(found_p)
    both = np.lexsort((p, q))
    return q[both], p[both]


@dataclass(frozen=True)
class OracleParams:
    """range, food_range: m; field_deg: the field of view, deg, centred on the heading;
    lateral_line: m within which anything is perceived whatever its bearing."""

    range: float = 1.5
    food_range: float = 2.5
    field_deg: float = 300.0
    lateral_line: float = 0.3

    def __post_init__(self) -> None:
        if not (self.range > 0 and self.food_range > 0 and 0 < self.field_deg <= 360):
            raise ValueError("oracle: range and food_range must be > 0 m, field_deg in (0, 360]")


@dataclass(frozen=True)
class Obstacles:
    """K vertical cylinders: ``centres`` (K, 2) m (x, y), ``radii`` (K,) m, ``tops`` (K,) m (z
    of the top; the bottom is the seabed)."""

    centres: np.ndarray
    radii: np.ndarray
    tops: np.ndarray

    @classmethod
    def none(cls) -> Obstacles:
        return cls(np.zeros((0, 2)), np.zeros(0), np.zeros(0))

    def clearance(self, points: np.ndarray) -> np.ndarray:
        """(..., K) m from ``points`` (..., 3) to each cylinder's side (negative: inside), or
        to its top for a point above it."""
        offset = points[..., None, :2] - self.centres
        side = np.linalg.norm(offset, axis=-1) - self.radii
        above = points[..., None, 2] - self.tops
        return np.where(above > 0, np.hypot(np.maximum(side, 0.0), above), side)


def clearance_to(points: np.ndarray, obstacles: Obstacles, k: np.ndarray) -> np.ndarray:
    """(M, P) m from ``points`` (M, P, 3) to obstacle ``k[m]`` (M,) each, as
    :meth:`Obstacles.clearance` measures it."""
    offset = points[..., None, :2] - obstacles.centres[k][:, None, None]
    side = np.linalg.norm(offset, axis=-1)[..., 0] - obstacles.radii[k][:, None]
    above = points[..., 2] - obstacles.tops[k][:, None]
    return np.where(above > 0, np.hypot(np.maximum(side, 0.0), above), side)


def obstacles_near(points: np.ndarray, centres: np.ndarray, obstacles: Obstacles,
                   margin: float) -> tuple[np.ndarray, np.ndarray]:
    """(fish, obstacle) index pairs, sorted, of every obstacle that may come within
    ``margin`` m of any of fish f's ``points`` (F, P, 3) gathered about ``centres`` (F, 3)
    (the grid at the points' widest spread about their centre, plus the margin and the
    widest radius)."""
    if len(obstacles.radii) == 0 or len(points) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    spread = np.linalg.norm(points[..., :2] - centres[:, None, :2], axis=-1).max()
    return pairs_within(centres, obstacles.centres, spread + margin + obstacles.radii.max())


def first_min_per_row(rows: np.ndarray, values: np.ndarray, columns: np.ndarray
                      ) -> np.ndarray:
    """Indices into the pair arrays of each row's smallest value (the smallest column
    among equals, as ``argmin`` along a dense row picks), one per row that has pairs."""
    order = np.lexsort((columns, values, rows))
    first = np.ones(len(order), bool)
    first[1:] = rows[order][1:] != rows[order][:-1]
    return order[first]


def hidden(eyes: np.ndarray, targets: np.ndarray, obstacles: Obstacles,
           reach: float = np.inf) -> np.ndarray:
    """(P,) True where the line from eye p (P, 3) to target p (P, 3), no longer than
    ``reach`` m, passes through an obstacle below its top (the lower end of the line
    counts: a conservative occlusion). Only the obstacles that can reach the line are looked
    at: those whose axis is within ``reach`` plus the widest radius of the eye."""
    blocked = np.zeros(len(eyes), bool)
    if len(obstacles.radii) == 0 or len(eyes) == 0:
        return blocked
    line, k = pairs_within(eyes, obstacles.centres, min(reach, 1e6) + obstacles.radii.max())
    a, b, c = eyes[line], targets[line], obstacles.centres[k]
    d = (b - a)[:, :2]
    length2 = np.maximum(np.einsum("mj,mj->m", d, d), 1e-12)
    s = np.clip(np.einsum("mj,mj->m", c - a[:, :2], d) / length2, 0.0, 1.0)
    closest = a[:, :2] + s[:, None] * d
    through = np.linalg.norm(closest - c, axis=-1) < obstacles.radii[k]
    low = np.minimum(a[:, 2], b[:, 2]) < obstacles.tops[k]
    blocked[line[through & low]] = True
    return blocked


def perceived(eyes: np.ndarray, headings: np.ndarray, targets: np.ndarray, reach: float,
              obstacles: Obstacles, params: OracleParams,
              pairs: tuple[np.ndarray, np.ndarray] | None = None
              ) -> tuple[np.ndarray, np.ndarray]:
    """Which targets (T, 3) each fish (eyes (F, 3), unit headings (F, 3)) perceives within
    ``reach`` m: (F, T) bool, and the distances (F, T) m of the pairs within reach and in
    the field (inf elsewhere: read them where perceived). Only the pairs the grid
    (:func:`pairs_within`) puts within reach are looked at, or the (fish, target) index
    ``pairs`` given, sorted by fish then target: those that may count, the caller knowing
    the others cannot (the pursuit's worlds: a fish of another world is not there)."""
    f, t = pairs_within(eyes, targets, reach) if pairs is None else pairs
    offsets = targets[t] - eyes[f]
    distance = np.linalg.norm(offsets, axis=-1)
    cosine = np.einsum("pk,pk->p", offsets, headings[f]) / np.maximum(distance, 1e-9)
    in_field = (cosine >= np.cos(np.radians(0.5 * params.field_deg))) | (
        distance < params.lateral_line)
    near = (distance < reach) & in_field
    f, t, distance = f[near], t[near], distance[near]
    seen = np.zeros((len(eyes), len(targets)), bool)
    dist = np.full((len(eyes), len(targets)), np.inf)
    dist[f, t] = distance
    visible = ~hidden(eyes[f], targets[t], obstacles, reach)
    seen[f[visible], t[visible]] = True
    return seen, dist


def nearest(seen: np.ndarray, distance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F,) index of the nearest perceived target (-1: none) and its distance (inf: none)."""
    masked = np.where(seen, distance, np.inf)
    index = np.argmin(masked, axis=1) if masked.shape[1] else np.zeros(len(masked), int)
    best = masked[np.arange(len(masked)), index] if masked.shape[1] else np.full(
        len(masked), np.inf)
    return np.where(np.isfinite(best), index, -1), best
