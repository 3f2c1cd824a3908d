"""The still part of the marine world the eyes see: rocks on the seabed, plants, food particles.

Each thing is a rigid mesh of quads (:meth:`animat.envs.render.camera.Scene.add_mesh`) with a
colour per
face, so that it has texture for optical flow and shading for shape. :func:`scatter` lays out a
seeded set of them over an area; the envs add it to their scene every frame. Nothing here
takes part in the physics yet: rocks stand on the seabed below the swimming layer, food drifts
nowhere and is not eaten (the living world, with collisions and eating, is a later module).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .camera import BOX_FACES, Scene, box, box_corners

ROCK, PLANT, FOOD = (115, 105, 95), (45, 125, 55), (235, 225, 150)  # RGB


def rock(base, size, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A boulder: a box of ``size`` (3,) m standing on the point ``base`` (3,), its top
    corners lowered at random by up to a third of its height; (6, 4, 3) corners, (6, 3) RGB
    (a shade per face)."""
    size = np.asarray(size, float)
    corners = box_corners(np.asarray(base, float) + [0.0, 0.0, 0.5 * size[2]], size)
    corners[4:, 2] -= rng.uniform(0.0, 1.0 / 3.0, 4) * size[2]
    colours = np.asarray(ROCK, float) * rng.uniform(0.8, 1.15, (6, 1))
    return corners[BOX_FACES], colours


def plant(base, height: float, rng: np.random.Generator, segments: int = 4,
          width: float = 0.04) -> tuple[np.ndarray, np.ndarray]:
    """A frond of seaweed rising from ``base`` (3,) m: two crossed ribbons of ``segments``
    quads each, ``width`` m wide, leaning a little at random; (2 * segments, 4, 3) corners and a
    green of varying shade per quad."""
    base = np.asarray(base, float)
    lean = rng.normal(0.0, 0.08, 2) * height
    levels = np.linspace(0.0, 1.0, segments + 1)
    spine = base + np.stack([lean[0] * levels**2, lean[1] * levels**2, height * levels], axis=1)
    quads = []
    for angle in rng.uniform(0.0, np.pi) + np.array([0.0, np.pi / 2]):
        side = 0.5 * width * np.array([np.cos(angle), np.sin(angle), 0.0])
        taper = (1.0 - 0.6 * levels)[:, None]
        for k in range(segments):
            quads.append([spine[k] - taper[k] * side, spine[k] + taper[k] * side,
                          spine[k + 1] + taper[k + 1] * side, spine[k + 1] - taper[k + 1] * side])
    colours = np.asarray(PLANT, float) * rng.uniform(0.75, 1.2, (len(quads), 1))
    return np.array(quads), colours


def food(centre, size: float = 0.012) -> tuple[np.ndarray, np.ndarray]:
    """A food particle: a cube of ``size`` m at ``centre`` (3,) m."""
    return box(centre, [size] * 3), np.tile(np.asarray(FOOD, float), (6, 1))


@dataclass(frozen=True)
class SceneryParams:
    """How much of each, over the rectangle ``low`` .. ``high`` (x, y) m: ``rocks`` standing on
    the seabed (up to ``rock_height`` m tall), ``plants`` (up to ``plant_height`` m tall,
    ``plant_width`` m wide), ``food`` particles floating within ``food_depth`` m of z = 0."""

    rocks: int = 5
    plants: int = 12
    food: int = 15
    low: tuple[float, float] = (-1.5, -1.5)
    high: tuple[float, float] = (1.5, 1.5)
    rock_height: float = 0.25
    plant_height: float = 0.35
    plant_width: float = 0.04
    food_depth: float = 0.3


def scatter(rng: np.random.Generator, seabed_z: float, params: SceneryParams = SceneryParams()
            ) -> list[tuple[np.ndarray, np.ndarray]]:
    """A seeded layout of rocks, plants and food: [(corners (F, 4, 3) m, colours (F, 3))]."""
    low, high = np.asarray(params.low, float), np.asarray(params.high, float)
    things = []
    for _ in range(params.rocks):
        size = rng.uniform(0.4, 1.0, 3) * [0.4, 0.4, params.rock_height]
        things.append(rock([*rng.uniform(low, high), seabed_z], size, rng))
    for _ in range(params.plants):
        height = rng.uniform(0.5, 1.0) * params.plant_height
        things.append(plant([*rng.uniform(low, high), seabed_z], height, rng,
                            width=params.plant_width))
    for _ in range(params.food):
        depth = rng.uniform(-params.food_depth, params.food_depth)
        things.append(food([*rng.uniform(low, high), depth]))
    return things


def furnish(scene: Scene, things: list[tuple[np.ndarray, np.ndarray]]) -> Scene:
    """``scene`` with all of ``things`` added as one mesh (one concatenation per frame, not
    one per thing)."""
    if things:
        scene.add_mesh(np.concatenate([corners for corners, _ in things]),
                       np.concatenate([colours for _, colours in things]))
    return scene
