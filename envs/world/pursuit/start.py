"""Where a pursuit episode starts: the prey, the distractors and the passers placed about the
observer (at the origin, heading +x), and the occluders among the scenery.

The layout is drawn from the env's seeded generator, in one fixed order, so that a seed gives
one episode. Rows of the env's batch: the observer, the prey, then ``distractors`` fish of a
similar hue and the same size (salmon against the prey's red: a different colour histogram,
not a different colour family), then ``passers`` fish of other colours that swim across the
line of sight.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...render.scenery import SceneryParams, scatter

OBSERVER, PREY, DISTRACTOR = 0, 1, 2  # rows; the distractors from DISTRACTOR on, then passers
OBSERVER_COLOUR, PREY_COLOUR = (250, 140, 60), (220, 50, 40)
DISTRACTOR_COLOUR = (240, 120, 110)  # salmon: red's family, its own histogram
PASSER_COLOURS = ((230, 210, 40), (70, 120, 210), (190, 195, 200))  # yellow, blue, silver
SEABED_Z = -0.5  # m
# on the seabed, below the swimming layer; then the occluders: kelp and boulders that rise
# through it (they hide what is behind them but do not stop a fish: no collisions here)
SEABED = SceneryParams(rocks=5, plants=12, food=15, low=(-2.0, -5.0), high=(6.0, 5.0))
OCCLUDERS = SceneryParams(rocks=3, plants=8, food=0, low=(-1.0, -4.0), high=(5.0, 4.0),
                          rock_height=0.9, plant_height=1.1, plant_width=0.12)


def colours(distractors: int, passers: int) -> list[tuple[int, int, int]]:
    """The skins' colours by row: observer, prey, the distractors, the passers (cycling)."""
    cycle = [PASSER_COLOURS[k % len(PASSER_COLOURS)] for k in range(passers)]
    return [OBSERVER_COLOUR, PREY_COLOUR, *[DISTRACTOR_COLOUR] * distractors, *cycle]


@dataclass(frozen=True)
class Placement:
    """A fish's start: its nose at ``position`` (3,) m, heading ``yaw`` rad (about z)."""

    position: np.ndarray
    yaw: float


def _at(distance: float, bearing: float) -> np.ndarray:
    return distance * np.array([np.cos(bearing), np.sin(bearing), 0.0])


def place(rng: np.random.Generator, length: float, distance_bl: tuple[float, float],
          bearing_deg: tuple[float, float], distractors: int, passers: int
          ) -> list[Placement]:
    """The starts of the prey, the distractors and the passers, in row order (the observer's
    is the origin). The prey: at ``distance_bl`` (BL) and a bearing drawn from
    ``bearing_deg``, heading away within +-60 deg. Each distractor: at its own distance and
    bearing drawn from the same ranges, heading anywhere. The first passer 3 BL to a random
    side of the line of sight to the prey and 2 BL beyond it, heading across it; each further
    one 2-4 BL to a side, at 0.3-1.5 of the prey's distance, heading across."""
    distance = rng.uniform(*distance_bl) * length
    bearing = np.radians(rng.uniform(*bearing_deg))
    prey_at = _at(distance, bearing)
    out = [Placement(prey_at, bearing + np.radians(rng.uniform(-60.0, 60.0)))]
    for _ in range(distractors):
        at = _at(rng.uniform(*distance_bl) * length, np.radians(rng.uniform(*bearing_deg)))
        out.append(Placement(at, rng.uniform(-np.pi, np.pi)))
    across = np.array([-np.sin(bearing), np.cos(bearing), 0.0])
    for k in range(passers):
        side = rng.choice([-1.0, 1.0])
        if k == 0:
            along, off = distance + 2.0 * length, 3.0 * length
        else:
            along, off = rng.uniform(0.3, 1.5) * distance, rng.uniform(2.0, 4.0) * length
        out.append(Placement(_at(along, bearing) + side * off * across,
                             bearing - side * np.pi / 2))
    return out


def scenery(rng: np.random.Generator, occluders: bool) -> list:
    """The seeded scenery: the seabed's rocks, plants and food, then (``occluders``) the kelp
    and boulders that rise through the swimming layer."""
    things = scatter(rng, SEABED_Z, SEABED)
    return things + scatter(rng, SEABED_Z, OCCLUDERS) if occluders else things
