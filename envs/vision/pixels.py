"""Retinal observations sized for learners: the same eyes, fewer and smaller pictures.

The full retina (:class:`~animat.envs.vision.retina.Retina`) gives each eye four 64x64 RGB
cameras: 98 KB an observation, 393 KB over four frames, more than a pixel learner on two cores
can learn from at a usable rate (DrQ-v2 takes three 84x84 RGB frames, 63 KB; Procgen one 64x64
RGB frame, 12 KB). These sensors read the same eyes (the same poses, fields of view and scene)
and give less of what they see, channel-first uint8 as image networks take it:

* :class:`RetinaPixels` (``pixels``): the cameras of the chosen ``levels`` (e.g. (0, 3): the
  120 deg periphery and the 15 deg fovea), drawn at ``size`` pixels a side (the same field of
  view, fewer pixels), in colour or grey (ITU-R BT.601 luma);
* :class:`TargetEvidence` (``evidence``): the paper's perception without its controller, each
  chosen camera's histogram backprojection of a target's colour memory (Swain and Ballard's
  localisation, :func:`~animat.envs.vision.perception.backproject`), drawn at the retina's own
  size and shrunk to ``size`` by area: 255 where a pixel's colour is all target, 0 where none.

Neither shows a learner anything the eyes do not: each is a function of the eyes' cameras, and
the evidence of a colour memory made beforehand (for the pursuit, the prey's model images:
:func:`~animat.envs.world.pursuit.memory.prey_model_histogram`). With ``frames`` the pursuit
stacks them over time along their first axis (:class:`~animat.envs.world.pursuit.shell.FrameStack`).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import cv2
import gymnasium as gym
import numpy as np

from ..checks import shown
from .perception import CV_CHANNELS, backproject_layers, scaled
from .retina import Retina, RetinaParams, Sighted

LUMA = np.array([299, 587, 114], np.int32)  # ITU-R BT.601 weights, per mille


def grey(images: np.ndarray) -> np.ndarray:
    """(..., H, W) uint8 luma of RGB images (..., H, W, 3): ``(299 R + 587 G + 114 B) / 1000``,
    rounded."""
    x = images.astype(np.int32)  # per channel, not a matmul: NumPy has no integer BLAS
    return ((x[..., 0] * LUMA[0] + x[..., 1] * LUMA[1] + x[..., 2] * LUMA[2] + 500)
            // 1000).astype(np.uint8)


def chosen_cameras(levels: Any, size: Any, retina: RetinaParams) -> RetinaParams:
    """``retina`` drawing only ``levels`` (distinct levels of it, in order) at ``size`` pixels
    (an integer in [8, retina.size]); a ValueError of one line naming a bad one."""
    if not isinstance(levels, (list, tuple)) or not levels or any(
            type(k) is not int or not 0 <= k < retina.levels for k in levels) or len(
            set(levels)) < len(levels):
        raise ValueError(f"levels must be distinct levels of the retina (0 .. "
                         f"{retina.levels - 1}), e.g. [0, 3], got {shown(levels)}")
    if type(size) is not int or not 8 <= size <= retina.size:
        raise ValueError(f"size must be an integer in [8, {retina.size}] pixels, got "
                         f"{shown(size)}")
    return replace(retina, size=size, drawn=tuple(levels))


def _eyes_of(source: Any) -> RetinaParams:
    """The retina whose eyes ``source`` offers (its ``retina``, else the default); a
    ValueError for a source without eyes."""
    if not isinstance(source, Sighted):
        raise ValueError(f"sensors: the eyes' pictures need an observer with eyes (e.g. "
                         f"Animat/FishPursuit-v0), got a {type(source).__name__}")
    return getattr(source, "retina", None) or RetinaParams()


class RetinaPixels:
    """The chosen cameras of both eyes as one channel-first image: ``Box(0, 255, (2 L C,
    size, size), uint8)``, L = ``len(levels)``, C = 1 grey or 3 RGB; channels in the order
    left eye then right, each eye's levels as given, each level's channels (R, G, B)."""

    name = "pixels"
    channels_first = True

    def __init__(self, levels: list[int] | tuple[int, ...] = (0, 3), size: int = 32,
                 colour: bool = False) -> None:
        if not isinstance(colour, bool):
            raise ValueError(f"colour must be true or false, got {shown(colour)}")
        chosen_cameras(levels, size, RetinaParams())
        self.levels, self.size, self.colour = tuple(levels), int(size), colour

    def space(self, source: Any) -> gym.spaces.Box:
        _eyes_of(source)
        channels = 2 * len(self.levels) * (3 if self.colour else 1)
        return gym.spaces.Box(0, 255, (channels, self.size, self.size), np.uint8)

    def read(self, source: Any, kinematics: Any) -> np.ndarray:
        """(B, 2 L C, size, size) uint8."""
        cameras = chosen_cameras(self.levels, self.size, _eyes_of(source))
        images = Retina(cameras).images(source, kinematics)  # (B, 2, L, S, S, 3)
        if not self.colour:
            return grey(images).reshape(len(images), -1, self.size, self.size)
        return np.ascontiguousarray(np.moveaxis(images, -1, 3)).reshape(
            len(images), -1, self.size, self.size)


class TargetEvidence:
    """Each chosen camera's backprojection of the colour memory ``model`` (one histogram of
    :data:`~animat.envs.vision.perception.BINS`, or one per model image (V, ...), weighted
    alike as :func:`~animat.envs.vision.active_vision.detect` weighs them), blurred by a disk
    of ``radius`` pixels, as uint8 (evidence 0..1 times 255) shrunk by area to ``size``:
    ``Box(0, 255, (2 L, size, size), uint8)``, the left eye's levels then the right's."""

    name = "evidence"
    channels_first = True

    def __init__(self, model: np.ndarray, levels: list[int] | tuple[int, ...] = (0, 3),
                 size: int = 32, radius: int = 2) -> None:
        views = np.asarray(model, np.float64)
        views = views.reshape((-1,) + views.shape[-3:])
        counts = views.reshape(len(views), -1).sum(axis=1)
        if not np.all(np.isfinite(counts)) or np.any(counts <= 0):
            raise ValueError("model: every colour histogram must hold some counts")
        if type(radius) is not int or not 0 <= radius <= 16:
            raise ValueError(f"radius must be an integer in [0, 16] pixels, got {shown(radius)}")
        chosen_cameras(levels, size, RetinaParams())
        self.memory = (views / counts[:, None, None, None]).sum(axis=0)
        self.levels, self.size, self.radius = tuple(levels), int(size), radius

    def space(self, source: Any) -> gym.spaces.Box:
        _eyes_of(source)
        return gym.spaces.Box(0, 255, (2 * len(self.levels), self.size, self.size), np.uint8)

    def read(self, source: Any, kinematics: Any) -> np.ndarray:
        """(B, 2 L, size, size) uint8."""
        retina = _eyes_of(source)
        cameras = chosen_cameras(self.levels, retina.size, retina)
        images = Retina(cameras).images(source, kinematics)  # (B, 2, L, S, S, 3)
        eyes = np.moveaxis(images, 2, 4).reshape((-1,) + images.shape[3:5] + images.shape[2:3]
                                                 + (3,))  # (B 2, S, S, L, 3), no copy
        whole = scaled(self.memory, float(retina.size * retina.size))
        layers = backproject_layers(eyes, whole, self.radius)  # (S, S, B 2 L) in [0, 1]
        if self.size != retina.size:
            layers = np.concatenate([cv2.resize(
                layers[:, :, k:k + CV_CHANNELS], (self.size, self.size),
                interpolation=cv2.INTER_AREA).reshape(self.size, self.size, -1)
                for k in range(0, layers.shape[2], CV_CHANNELS)], axis=2)
        maps = np.clip(np.rint(255.0 * layers), 0, 255).astype(np.uint8)
        return maps.transpose(2, 0, 1).reshape(len(images), -1, self.size, self.size)
