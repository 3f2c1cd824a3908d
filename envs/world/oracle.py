"""The perceptual oracle of world fish (the paper's footnote 4, after Tu and Terzopoulos): what
each fish perceives, read from the world model rather than from rendered eyes.

A fish perceives a thing when it is within range (``range`` m for fish and obstacles, the
longer ``food_range`` m for food), inside its ``field_deg`` field of view about its heading
(300 deg: all but a blind cone behind) or within ``lateral_line`` m (a fish feels what moves
close to it all round), and not hidden behind an obstacle. Obstacles are
vertical cylinders standing on the seabed (:class:`Obstacles`); a line of sight is hidden when
it passes through one below its top. All functions are batched: F observers, T targets.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


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


def hidden(eyes: np.ndarray, targets: np.ndarray, obstacles: Obstacles) -> np.ndarray:
    """(F, T) True where the line from eye f (F, 3) to target t (T, 3) passes through an
    obstacle below its top (the lower end of the line counts: a conservative occlusion)."""
    if len(obstacles.radii) == 0:
        return np.zeros((len(eyes), len(targets)), bool)
    a, b = eyes[:, None, None, :], targets[None, :, None, :]  # (F, 1, 1, 3), (1, T, 1, 3)
    c = obstacles.centres[None, None]  # (1, 1, K, 2)
    d = (b - a)[..., :2]
    length2 = np.maximum(np.einsum("ftkj,ftkj->ftk", d, d), 1e-12)
    s = np.clip(np.einsum("ftkj,ftkj->ftk", c - a[..., :2], d) / length2, 0.0, 1.0)
    closest = a[..., :2] + s[..., None] * d
    through = np.linalg.norm(closest - c, axis=-1) < obstacles.radii
    low = np.minimum(a[..., 2], b[..., 2]) < obstacles.tops
    return np.any(through & low, axis=-1)


def perceived(eyes: np.ndarray, headings: np.ndarray, targets: np.ndarray, reach: float,
              obstacles: Obstacles, params: OracleParams) -> tuple[np.ndarray, np.ndarray]:
    """Which targets (T, 3) each fish (eyes (F, 3), unit headings (F, 3)) perceives within
    ``reach`` m: (F, T) bool, and the distances (F, T) m."""
    offsets = targets[None] - eyes[:, None]
    distance = np.linalg.norm(offsets, axis=-1)
    cosine = np.einsum("ftk,fk->ft", offsets, headings) / np.maximum(distance, 1e-9)
    in_field = (cosine >= np.cos(np.radians(0.5 * params.field_deg))) | (
        distance < params.lateral_line)
    seen = (distance < reach) & in_field & ~hidden(eyes, targets, obstacles)
    return seen, distance


def nearest(seen: np.ndarray, distance: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F,) index of the nearest perceived target (-1: none) and its distance (inf: none)."""
    masked = np.where(seen, distance, np.inf)
    index = np.argmin(masked, axis=1) if masked.shape[1] else np.zeros(len(masked), int)
    best = masked[np.arange(len(masked)), index] if masked.shape[1] else np.full(
        len(masked), np.inf)
    return np.where(np.isfinite(best), index, -1), best
