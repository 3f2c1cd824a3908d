"""The pursuit's batched core: N pursuit worlds stepped together, what both the single env
(N = 1) and the native vector env run.

World w's F fish (the observer, the prey, the distractors, the passers: the rows of
:mod:`animat.envs.world.pursuit.start`) are rows w F .. w F + F - 1 of one
:class:`~animat.envs.core.batch.BodyBatch`, one :class:`~animat.envs.motor.navigation.Navigator`
and one :class:`~animat.envs.world.pursuit.others.OtherFish`; every world has its own clock,
gaze, scenery and random generator. Nothing of one world reaches another (the physics is per
body, the minds' relations are within a world), so a world steps bit for bit as it would alone.

The eyes of all N observers are drawn by one kernel
(:func:`animat.envs.render.cameras.draw_cameras`, the cameras over threads) from each world's
triangles: the fish's shadows and skins made for the whole batch at once, the scenery's shaded
quads kept from the world's reset.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ...core.batch import BodyBatch, Kinematics
from ...motor.navigation import Navigator, forward_speeds, navigation_for
from ...render.camera import SHADOW_LIFT, Scene, fish_skin, shade, subdivide, yaw_matrix
from ...render.cameras import SHADOW, draw_cameras, groups_in_space
from ...render.raster import quads_into
from ...render.scenery import furnish
from ...tasks.locomotion import SwimTask
from ...vision.retina import RetinaParams, eye_poses_batch
from .others import OtherFish
from .senses import PHI_RANGE, THETA_RANGE
from .start import PREY, SEABED_Z, colours, place, scenery

QUADS_CULLED = 16  # quads (32 triangles) the cameras leave out together, behind one sphere
SCENERY_CELL = 0.5  # m: the squares along which the scenery's quads are grouped


@dataclass(frozen=True)
class PursuitParams:
    """A pursuit's settings, already checked by the env (see its docstring's Arguments)."""

    duration: float
    start_distance_bl: tuple[float, float]
    bearing_deg: tuple[float, float]
    flee_distance_bl: float
    prey_speed: float
    distractors: int
    passers: int
    occluders: bool
    glances: int
    water: dict | None


class PursuitWorlds:
    """N pursuit worlds (``num_worlds``) of ``params``, the observers' eyes ``retina``."""

    def __init__(self, num_worlds: int, params: PursuitParams,
                 retina: RetinaParams = RetinaParams()) -> None:
        self.params, self.retina, self.num_worlds = params, retina, int(num_worlds)
        fish = self.fish = 2 + params.distractors + params.passers
        self.core = BodyBatch(self.num_worlds * fish, SwimTask(), duration=params.duration,
                              fins=True, water=params.water, start_spread="point")
        self.core.state.x[:] = self.core.body.rest_positions  # a body everywhere till reset
        self.dt, self.body_length = self.core.dt, self.core.body.length
        self.observers = np.arange(self.num_worlds) * fish  # each world's observer's row
        self.navigator = Navigator(len(self.core.state.x), navigation_for(self.core.system.water))
        self.others = OtherFish(params.distractors, params.passers, params.prey_speed,
                                0.5 * params.flee_distance_bl * self.body_length,
                                self.num_worlds)
        self.skins = [fish_skin(self.core.body, colour)
                      for colour in colours(params.distractors, params.passers)]
        self.gaze = np.zeros((self.num_worlds, 4))  # as commanded, in the action's units
        self.time = np.zeros(self.num_worlds)  # s
        self.glance = np.zeros(self.num_worlds, int)  # looks taken in this frame
        self.distance = np.zeros(self.num_worlds)  # m, head to the prey's centre of mass
        self.scenery: list[list] = [[] for _ in range(self.num_worlds)]
        # every world's triangles and colours (:meth:`triangles`): shadows, skins, scenery
        self._triangles = np.zeros((self.num_worlds, 0, 3, 3))
        self._colours = np.zeros((self.num_worlds, 0, 3), np.uint8)
        self._groups = np.zeros((self.num_worlds, 0), np.int64)  # each triangle's (culling)
        self._poses: tuple | None = None  # the kinematics and gaze of the eye poses kept

    # --- episodes ------------------------------------------------------------------------
    def rows(self, world: int) -> np.ndarray:
        """(F,) world ``world``'s rows of the batch."""
        return np.arange(world * self.fish, (world + 1) * self.fish)

    def reset(self, worlds: Sequence[int], rngs: Sequence[np.random.Generator]) -> Kinematics:
        """Start new episodes in ``worlds``, world w's drawn from ``rngs`` (in this order: the
        bodies' noise, the placement, the scenery). Returns the batch's kinematics."""
        p, core = self.params, self.core
        for world, rng in zip(worlds, rngs):
            rows = self.rows(world)
            core.reset_rows(rows, [rng] * self.fish)
            starts = place(rng, self.body_length, p.start_distance_bl, p.bearing_deg,
                           p.distractors, p.passers)
            for row, start in enumerate(starts, start=rows[PREY]):
                state = core.state
                turned = (state.x[row] - core.body.rest_positions[0]) @ yaw_matrix(start.yaw).T
                state.x[row], state.v[row] = turned + start.position, 0.0
            self.scenery[world] = scenery(rng, p.occluders)
        kinematics = core.kinematics()  # of the placed fish
        for world in worlds:
            rows = self.rows(world)
            core.state.origin[rows] = kinematics.com[rows]
            self.navigator.reset(rows)
            self.others.reset(world, kinematics.frames[rows, 0])
            self._keep_scenery(world)
        self.gaze[worlds], self.time[worlds], self.glance[worlds] = 0.0, 0.0, 0
        self.distance[worlds] = self.distances(kinematics)[worlds]
        return kinematics

    def step(self, actions: np.ndarray, rngs: Sequence[np.random.Generator]
             ) -> tuple[np.ndarray, bool, Kinematics]:
        """One env step of every world with ``actions`` (N, 7) (already checked and clipped),
        the wanderers drawing from ``rngs`` (N). Returns each world's distance closed (N,) m
        (0 on a look within a frame), whether the bodies moved, and the kinematics."""
        if np.any(self.glance < self.params.glances - 1):  # a look within the frame
            if not np.all(self.glance < self.params.glances - 1):
                raise RuntimeError("the worlds of a batch must look and move in step")
            self.glance += 1
            self.gaze[:] = actions[:, 3:]
            return np.zeros(self.num_worlds), False, self.core.kinematics()
        self.glance[:] = 0
        kinematics = self.core.kinematics()
        commands = self.others.commands(self.core.state.x[:, 0], kinematics, self.time, self.dt,
                                        rngs)
        commands[self.observers] = np.stack([0.5 * (actions[:, 0] + 1.0), actions[:, 1],
                                             actions[:, 2]], axis=1)
        moves = self.navigator.actions(commands, np.repeat(self.time, self.fish),
                                       forward=forward_speeds(kinematics, self.body_length))
        self.gaze[:] = actions[:, 3:]
        _, _, kinematics = self.core.step(moves.astype(np.float64))
        self.time += self.dt
        distance = self.distances(kinematics)
        closed, self.distance = self.distance - distance, distance
        return closed, True, kinematics

    @property
    def truncated(self) -> np.ndarray:
        """(N,) whether each world's episode has used its ``duration``."""
        return self.core.truncated[self.observers]

    def distances(self, kinematics: Kinematics) -> np.ndarray:
        """(N,) m: each observer's head to its prey's centre of mass."""
        offsets = kinematics.com[self.observers + PREY] - self.core.state.x[self.observers, 0]
        return np.array([np.linalg.norm(offset) for offset in offsets])

    # --- what the eyes see ---------------------------------------------------------------
    def scene(self, world: int = 0) -> Scene:
        """What there is to see now in world ``world``: its fish in their skins, its scenery."""
        scene = furnish(Scene(seabed_z=SEABED_Z), self.scenery[world])
        for row, skin in zip(self.rows(world), self.skins):
            scene.add(self.core.body, self.core.state.x[row], skin)
        return scene

    def gaze_angles(self) -> np.ndarray:
        """(N, 2, 2) rad: (theta, phi) of each observer's left and right eye, from the head."""
        return self.gaze.reshape(-1, 2, 2) * [THETA_RANGE, PHI_RANGE]

    def eye_poses(self, kinematics: Kinematics, fresh: bool = False
                  ) -> tuple[np.ndarray, np.ndarray]:
        """(N, 2, 3) m eye positions and (N, 2, 3, 3) camera rotations of every observer's
        eyes (:func:`~animat.envs.vision.retina.eye_poses_batch`), computed once per
        ``kinematics`` and gaze (``fresh``: again even so, e.g. to time it)."""
        kept = self._poses
        if (not fresh and kept is not None and kept[0] is kinematics
                and np.array_equal(kept[1], self.gaze)):
            return kept[2]
        poses = eye_poses_batch(kinematics.frames[self.observers],
                                self.core.state.x[self.observers, 0], self.body_length,
                                self.gaze_angles(), self.retina)
        self._poses = (kinematics, self.gaze.copy(), poses)
        return poses

    def eye_images(self, params: RetinaParams, kinematics: Kinematics) -> np.ndarray:
        """(N, 2, levels, size, size, 3) uint8: every observer's eyes, through ``params``'
        cameras (its ``drawn_levels``), drawn in one call (the cameras of all worlds over
        threads)."""
        positions, rotations = self.eye_poses(kinematics)
        triangles, colours = self.triangles()
        drawn, n = params.drawn_levels, self.num_worlds
        levels = len(drawn)
        focals = np.array([params.focal(level) for level in drawn])
        images = draw_cameras(
            triangles, colours, np.repeat(np.arange(n), 2 * levels),
            np.repeat(positions.reshape(-1, 3), levels, axis=0),
            np.repeat(rotations.reshape(-1, 3, 3), levels, axis=0), np.tile(focals, 2 * n),
            np.full(n, SEABED_Z), np.full(n, Scene.grid), np.full(n, Scene.visibility),
            (params.size, params.size), levels, self._groups)
        size = params.size  # the levels stay where stacking them wants them (a view)
        return np.moveaxis(images.reshape(n, 2, size, size, levels, 3), 4, 2)

    def _keep_scenery(self, world: int) -> None:
        """Write world ``world``'s scenery, shaded, after its fish in the triangle buffers."""
        things = self.scenery[world]
        quads = np.concatenate([corners for corners, _ in things])
        base = np.concatenate([colours for _, colours in things])
        fish = self.fish * len(self.core.body.faces) * 5  # shadows, then 4 sub-faces each
        if self._triangles.shape[1] != 2 * (fish + len(quads)):
            self._triangles = np.zeros((self.num_worlds, 2 * (fish + len(quads)), 3, 3))
            self._colours = np.zeros((self.num_worlds, 2 * (fish + len(quads)), 3), np.uint8)
            self._groups = np.zeros((self.num_worlds, 2 * (fish + len(quads))), np.int64)
        put_quads(self._triangles[world], self._colours[world], fish, quads,
                  shade(quads, base, Scene().light))
        # the fish's quads come body by body, face by face: runs of them lie together; the
        # scenery's lie anywhere, so they are grouped by where they are; a quad's two
        # triangles (:func:`put_quads`) together
        groups = np.concatenate([np.arange(fish) // QUADS_CULLED, -(-fish // QUADS_CULLED)
                                 + groups_in_space(quads.mean(axis=1), SCENERY_CELL,
                                                   QUADS_CULLED)])
        self._groups[world] = np.concatenate([groups, groups])

    def triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(N, T, 3, 3) m and (N, T, 3) uint8: every world's triangles and colours now, in
        the order of :meth:`Scene.prepare` (shadows, skins, scenery; each quad's first
        triangle, then each quad's second). The batch's own buffers: the fish are written
        again at each call, the scenery at reset."""
        n, body = self.num_worlds, self.core.body
        shadows = self.core.state.x.reshape(n, self.fish, -1, 3)[:, :, body.faces].reshape(
            n, -1, 4, 3)
        count = shadows.shape[1]
        skins = subdivide(shadows.reshape(-1, 4, 3)).reshape(n, -1, 4, 3)
        shadows[..., 2] = SEABED_Z + SHADOW_LIFT
        put_quads(self._triangles, self._colours, 0, shadows, SHADOW)
        put_quads(self._triangles, self._colours, count, skins,
                  shade(skins, np.concatenate(self.skins), Scene().light))
        return self._triangles, self._colours


def put_quads(triangles: np.ndarray, colours: np.ndarray, start: int, quads: np.ndarray,
              shades: np.ndarray) -> None:
    """Write ``quads`` (..., Q, 4, 3) m of colours ``shades`` (..., Q, 3) uint8 (or one
    colour) into the buffers of T triangles ``triangles`` (..., T, 3, 3) and ``colours``
    (..., T, 3), at ``start`` (:func:`~animat.envs.render.raster.quads_into`: each quad's two
    triangles T / 2 apart)."""
    quads_into(triangles, start, quads)
    half, stop = colours.shape[-2] // 2, start + quads.shape[-3]
    colours[..., start:stop, :] = shades
    colours[..., half + start:half + stop, :] = shades
