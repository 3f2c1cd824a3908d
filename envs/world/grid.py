"""Which things are near which: a uniform grid over the tank's floor plan (x, y), so that a
world's perception, collisions and catches look only at pairs within reach and their cost
grows with the number of fish, not its square.

:func:`pairs_within` returns every (query, point) pair whose horizontal distance may be below
``reach`` (those in the grid cells the query's reach overlaps: a superset, never missing one);
the callers then apply their exact test to those pairs alone, with the same arithmetic as on
all pairs, so a world steps the same whether a pair was looked at or not.
"""

from __future__ import annotations

import numpy as np

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
