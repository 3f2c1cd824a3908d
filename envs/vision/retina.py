"""The foveated binocular retina: two eyes on the head, each four coaxial cameras.

Each eye (the paper's Section 3.1, Fig. 5) has ``levels`` cameras of ``size`` x ``size`` RGB
sharing one optical axis: level 0 sees ``field_of_view`` (120 deg), every further level half
the angle of the one before, so level 3 (15 deg) is the fovea. An eye sits on the head at
``offset`` in the body frame (the left eye at +y, the right at -y) and is turned by its gaze
angles relative to the head: theta about the head's up axis (positive: to the left), phi about
its lateral axis (positive: up); :func:`eye_poses` places both eyes of a head (every eye in the
world is placed by it). Rendering is a pure function of the scene and the eye poses,
through the same :class:`~envs.render.camera.Camera` and rasterizer as the third-person view.

The composite of an eye (Fig. 5(b)) is 2^(levels-1) * size pixels square: level l magnified
2^(levels-1-l) times and centred, finer levels on top, so every pixel shows the finest level
that sees it.

The eyes are a sensor like any other (:class:`Retina`, the protocol of
:class:`animat.envs.core.sensors.Sensor`): it reads the scene and the eye poses from what it is
given (a :class:`Sighted`, e.g. the pursuit's observer, :mod:`animat.envs.world.pursuit.senses`)
and gives ``left_eye`` and ``right_eye``, each eye's levels stacked (:func:`stack_levels`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import gymnasium as gym
import numpy as np

from ..render.camera import Camera, Frame, Scene


@dataclass(frozen=True)
class RetinaParams:
    """levels: coaxial cameras per eye; size: pixels per side of each; field_of_view: level
    0's full angle, deg (level l sees half of level l-1's); eye_offset: (forward, left, up)
    of the left eye in the head frame, body lengths (the right eye mirrors it in y); drawn:
    which levels' cameras are drawn, in order (default all: ``0 .. levels - 1``), e.g. (0, 3)
    for the widest and the fovea alone."""

    levels: int = 4
    size: int = 64
    field_of_view: float = 120.0
    eye_offset: tuple[float, float, float] = (-0.08, 0.05, 0.02)
    drawn: tuple[int, ...] | None = None

    def __post_init__(self) -> None:
        if self.levels < 1 or self.size < 8 or not 0.0 < self.field_of_view < 170.0:
            raise ValueError("RetinaParams: need levels >= 1, size >= 8, 0 < field_of_view "
                             "< 170 deg")
        drawn = self.drawn
        if drawn is not None and (not drawn or len(set(drawn)) < len(drawn) or any(
                type(k) is not int or not 0 <= k < self.levels for k in drawn)):
            raise ValueError(f"RetinaParams: drawn must name distinct levels in "
                             f"0..{self.levels - 1}, got {drawn!r}")

    @property
    def drawn_levels(self) -> tuple[int, ...]:
        """The levels whose cameras are drawn, in order."""
        return tuple(range(self.levels)) if self.drawn is None else tuple(self.drawn)

    def focal(self, level: int) -> float:
        """Focal length of level ``level``, pixels."""
        half = np.radians(self.field_of_view) / 2.0 / 2**level
        return 0.5 * self.size / np.tan(half)


def gaze_rotation(frame: np.ndarray, theta: float, phi: float) -> np.ndarray:
    """(3, 3) camera rotation (rows right, down, forward; world frame) of an eye turned by
    gaze angles theta (left, rad) and phi (up, rad) from the head's frame ``frame`` (3, 3)
    (rows forward, left, up)."""
    forward, left, up = frame
    ct, st, cp, sp = np.cos(theta), np.sin(theta), np.cos(phi), np.sin(phi)
    axis = cp * (ct * forward + st * left) + sp * up
    side = ct * left - st * forward  # the eye's left, still horizontal in the head frame
    top = np.cross(axis, side)
    return np.stack([-side, -top, axis])


def eye_positions(frame: np.ndarray, head: np.ndarray, length: float,
                  params: RetinaParams = RetinaParams()) -> np.ndarray:
    """(2, 3) world positions of the left and right eye: the head point ``head`` (3,) m (the
    nose) plus ``eye_offset`` body lengths in the head frame."""
    forward, left, up = frame
    a, b, c = params.eye_offset
    return np.stack([head + length * (a * forward + s * b * left + c * up) for s in (1.0, -1.0)])


def eye_poses(frame: np.ndarray, head: np.ndarray, length: float, gaze: np.ndarray,
              params: RetinaParams = RetinaParams()) -> tuple[np.ndarray, np.ndarray]:
    """The world's one way to place a head's eyes: (2, 3) m positions (:func:`eye_positions`)
    and (2, 3, 3) camera rotations (:func:`gaze_rotation`; rows right, down, forward) of the
    left and the right eye of a head with frame ``frame`` (3, 3) (rows forward, left, up),
    nose at ``head`` (3,) m, body ``length`` m, eyes turned by ``gaze`` (2, 2) rad ((theta,
    phi) of the left eye, then of the right)."""
    positions = eye_positions(frame, head, length, params)
    rotations = np.stack([gaze_rotation(frame, *angles) for angles in gaze])
    return positions, rotations


def eye_poses_batch(frames: np.ndarray, heads: np.ndarray, length: float, gaze: np.ndarray,
                    params: RetinaParams = RetinaParams()) -> tuple[np.ndarray, np.ndarray]:
    """:func:`eye_poses` of B heads at once, the same numbers: frames (B, 3, 3), noses
    ``heads`` (B, 3) m, ``gaze`` (B, 2, 2) rad; (B, 2, 3) m positions and (B, 2, 3, 3)
    camera rotations."""
    forward, left, up = (frames[:, None, k] for k in range(3))  # (B, 1, 3) each
    a, b, c = params.eye_offset
    positions = np.stack([heads + length * (a * frames[:, 0] + s * b * frames[:, 1]
                                            + c * frames[:, 2]) for s in (1.0, -1.0)], axis=1)
    theta, phi = gaze[..., 0:1], gaze[..., 1:2]  # (B, 2, 1)
    ct, st, cp, sp = np.cos(theta), np.sin(theta), np.cos(phi), np.sin(phi)
    axis = cp * (ct * forward + st * left) + sp * up
    side = ct * left - st * forward
    top = np.cross(axis, side)
    return positions, np.stack([-side, -top, axis], axis=2)


def render_eye(scene: Scene, position: np.ndarray, rotation: np.ndarray,
               params: RetinaParams = RetinaParams(), frame: Frame | None = None) -> np.ndarray:
    """(levels, size, size, 3) uint8: the eye's images from level 0 (widest) to the fovea (its
    ``drawn_levels``). ``frame``: the scene already prepared for this instant (both eyes share
    it)."""
    frame = scene.prepare() if frame is None else frame
    images = []
    for level in params.drawn_levels:
        camera = Camera(params.size, params.size, params.focal(level), position, rotation)
        images.append(camera.draw(frame))
    return np.stack(images)


def render_eyes(scene: Scene, positions: np.ndarray, rotations: np.ndarray,
                params: RetinaParams = RetinaParams(), frame: Frame | None = None
                ) -> np.ndarray:
    """(2, levels, size, size, 3) uint8: both eyes (positions (2, 3) m, rotations (2, 3, 3))
    from one preparation of the scene (``frame``: already prepared, e.g. shared by several
    observers)."""
    frame = scene.prepare() if frame is None else frame
    return np.stack([render_eye(scene, p, r, params, frame)
                     for p, r in zip(positions, rotations)])


def composite(levels: np.ndarray) -> np.ndarray:
    """(S, S, 3) uint8, S = 2^(L-1) * size: the eye's levels (L, size, size, 3) magnified
    2^(L-1-l) and centred, finer levels on top (Fig. 5(b))."""
    count, size = levels.shape[0], levels.shape[1]
    full = size * 2 ** (count - 1)
    out = np.zeros((full, full, 3), np.uint8)
    for level in range(count):
        scale = 2 ** (count - 1 - level)
        block = np.repeat(np.repeat(levels[level], scale, axis=0), scale, axis=1)
        start = (full - block.shape[0]) // 2
        out[start:start + block.shape[0], start:start + block.shape[1]] = block
    return out


def stack_levels(images: np.ndarray) -> np.ndarray:
    """(..., size, size, 3 * levels) uint8: an eye's levels (..., levels, size, size, 3) with
    their RGB stacked along the channels, level 0 (the widest) first, the fovea last."""
    *lead, levels, height, width, _ = images.shape
    return np.moveaxis(images, -4, -2).reshape(*lead, height, width, 3 * levels)


@runtime_checkable
class Sighted(Protocol):
    """What the retina reads: the scene and where the eyes of each of B observers are
    (``isinstance`` checks that both methods are there)."""

    def scene(self) -> Scene:
        """What there is to see now."""

    def eye_poses(self, kinematics: Any) -> tuple[np.ndarray, np.ndarray]:
        """(B, 2, 3) m eye positions and (B, 2, 3, 3) camera rotations (rows right, down,
        forward; world frame) of each observer's left and right eye."""


class Retina:
    """The two eyes as a sensor (:class:`animat.envs.core.sensors.Sensor`): its space a
    ``Dict`` of ``left_eye`` and ``right_eye``, each ``Box(0, 255, (size, size, 3 * levels),
    uint8)`` (:func:`stack_levels`); its read both eyes of every observer, rendered with
    ``params``' cameras (levels, size, field of view) from one preparation of the scene."""

    name = "retina"
    EYES = ("left_eye", "right_eye")

    def __init__(self, params: RetinaParams = RetinaParams()) -> None:
        self.params = params

    def space(self, source: Sighted) -> gym.spaces.Dict:
        """One observer's reading: both eyes' stacked levels. Raises ValueError if ``source``
        has no eyes (not a :class:`Sighted`, e.g. a body env's ``BodyBatch``)."""
        if not isinstance(source, Sighted):
            raise ValueError(f"sensors: the retina needs an observer with eyes (e.g. "
                             f"Animat/FishPursuit-v0), got a {type(source).__name__}")
        shape = (self.params.size, self.params.size, 3 * len(self.params.drawn_levels))
        return gym.spaces.Dict({eye: gym.spaces.Box(0, 255, shape, np.uint8)
                                for eye in self.EYES})

    def images(self, source: Sighted, kinematics: Any) -> np.ndarray:
        """(B, 2, levels, size, size, 3) uint8: what the B observers' eyes see now (a source
        whose observers each live in a world of their own draws them itself, in one call:
        its ``eye_images(params, kinematics)``)."""
        own = getattr(source, "eye_images", None)
        if own is not None:
            return own(self.params, kinematics)
        positions, rotations = source.eye_poses(kinematics)
        scene = source.scene()
        frame = scene.prepare()
        return np.stack([render_eyes(scene, places, turns, self.params, frame)
                         for places, turns in zip(positions, rotations)])

    def read(self, source: Sighted, kinematics: Any) -> dict[str, np.ndarray]:
        """``left_eye`` and ``right_eye``: (B, size, size, 3 * levels) uint8 each."""
        stacked = stack_levels(self.images(source, kinematics))
        return {eye: stacked[:, k] for k, eye in enumerate(self.EYES)}
