"""What the living world looks like: its fish in their species' skins, the obstacles (stone
pillars: octagonal prisms from the seabed), the food particles and the seabed; a third-person
camera over the tank, and the eyes of one fish (:mod:`animat.envs.vision.retina`).
"""

from __future__ import annotations

import numpy as np

from ..render.camera import Camera, Scene, fish_skin, look_at
from ..render.scenery import ROCK, food
from ..vision.retina import RetinaParams, eye_poses, render_eyes

SIDES = 8


def pillar(centre: np.ndarray, radius: float, bottom: float, top: float,
           rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A stone pillar: a ``SIDES``-sided prism round ``centre`` (2,) m, circumscribing the
    cylinder of ``radius`` m, from ``bottom`` to ``top`` z m, in two stacked rings of faces
    (shading and texture for the eyes); (2 SIDES + 1, 4, 3) corners and their colours."""
    angles = np.linspace(0.0, 2.0 * np.pi, SIDES + 1)
    r = radius / np.cos(np.pi / SIDES)
    ring = np.stack([centre[0] + r * np.cos(angles), centre[1] + r * np.sin(angles)], axis=1)
    middle = 0.5 * (bottom + top)
    quads = []
    for low, high in ((bottom, middle), (middle, top)):
        for k in range(SIDES):
            a, b = ring[k], ring[k + 1]
            quads.append([[*a, low], [*b, low], [*b, high], [*a, high]])
    cap = [[*ring[k], top] for k in (0, 2, 4, 6)]
    quads.append(cap)
    colours = np.asarray(ROCK, float) * rng.uniform(0.75, 1.15, (len(quads), 1))
    return np.array(quads, float), colours


class WorldView:
    """Draws a :class:`~animat.envs.world.world.MarineWorld`: ``scene()`` (what there is to
    see now), ``third_person()`` (width x height RGB over the tank) and ``eyes(fish, gaze)``
    (that fish's two retinas)."""

    def __init__(self, world, width: int = 480, height: int = 360,
                 retina: RetinaParams = RetinaParams()) -> None:
        self.world, self.width, self.height, self.retina = world, width, height, retina
        self.skins = [fish_skin(world.core.body, h.colour) for h in world.habits]
        self._pillars: list = []

    def reset(self) -> None:
        """Build the still things of the episode that :meth:`MarineWorld.reset` drew."""
        o, tank = self.world.obstacles, self.world.params.tank
        rng = np.random.default_rng(len(o.radii))
        self._pillars = [pillar(c, r, tank.seabed_z, top, rng)
                         for c, r, top in zip(o.centres, o.radii, o.tops)]

    def scene(self) -> Scene:
        world = self.world
        scene = Scene(seabed_z=world.params.tank.seabed_z, visibility=12.0)
        things = self._pillars + [food(p) for p in world.food]
        if things:
            scene.add_mesh(np.concatenate([c for c, _ in things]), np.concatenate(
                [k for _, k in things]))
        for row in range(world.num_fish):
            scene.add(world.core.body, world.core.state.x[row], self.skins[row])
        return scene

    def third_person(self) -> np.ndarray:
        """(height, width, 3) uint8: the tank from above one corner."""
        tank = self.world.params.tank
        centre = np.array([0.0, 0.0, tank.seabed_z])
        eye = np.array([-1.0, -1.0, 0.75]) * tank.half_size + [0.0, 0.0, tank.top_z]
        camera = Camera(self.width, self.height, 0.9 * self.width, eye, look_at(eye, centre))
        return camera.render(self.scene())

    def eye_poses(self, fish: int, gaze: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions (2, 3) m and camera rotations (2, 3, 3) of fish ``fish``'s eyes at
        ``gaze`` (2, 2) rad (theta, phi per eye): :func:`~animat.envs.vision.retina.eye_poses`
        of its head."""
        world = self.world
        frame = world.core.kinematics().frames[fish]
        return eye_poses(frame, world.core.state.x[fish, 0], world.length, gaze, self.retina)

    def eyes(self, fish: int, gaze: np.ndarray) -> np.ndarray:
        """(2, levels, size, size, 3) uint8: what fish ``fish`` sees at ``gaze`` (2, 2) rad."""
        positions, rotations = self.eye_poses(fish, gaze)
        return render_eyes(self.scene(), positions, rotations, self.retina)
