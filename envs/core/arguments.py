"""What a fish batch accepts: the ranges of its arguments (so that a step and an episode cost a
bounded time), their checks (:func:`check_arguments`) and the check of each step's actions
(:func:`validate_actions`). Each bad value is a ValueError of one line naming it.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..checks import check_flag, check_integer, check_number

# What a batch accepts, so that a step and an episode cost a bounded time (one integration
# step of one fish takes ~5 us): one env step at most MAX_FRAME_SKIP integration steps (~0.05 s
# a fish), an episode at most MAX_DURATION s and MAX_EPISODE_SUBSTEPS integration steps.
MAX_FRAME_SKIP = 10_000
MAX_DURATION = 86_400.0  # s, a simulated day
MAX_EPISODE_SUBSTEPS = 10**9  # duration / physics_dt
MIN_PHYSICS_DT, MAX_PHYSICS_DT = 1e-6, 1.0  # s (the body's stability bound is lower: System)
MAX_NUM_ENVS = 65_536
# BL: up to about a third of the tail's ring half size: noise much beyond it starts a fish so
# crumpled that random actions can blow it up in the reactive water
MAX_RESET_NOISE = 0.01


def check_arguments(num_envs: int, physics_dt: float, frame_skip: int, duration: float,
                    reset_noise_scale: float, fins: bool, fin_max_angle: float) -> None:
    """Check a batch's arguments (:class:`~animat.envs.core.batch.BodyBatch`), each a
    ValueError of one line naming it: ``num_envs`` an integer in [1, 65536]; ``physics_dt`` a
    finite number in [1e-6, 1] s (:class:`~envs.physics.system.System` refuses one above the
    body's stability bound); ``frame_skip`` an integer in [1, 10000]; ``duration`` a finite
    number in (0, 86400] s and at most 1e9 integration steps (``duration / physics_dt``);
    ``reset_noise_scale`` in [0, 0.01] BL; ``fins`` a bool; ``fin_max_angle`` in [0, pi/2] rad."""
    check_integer("num_envs", num_envs, 1, MAX_NUM_ENVS)
    dt = check_number("physics_dt", physics_dt, MIN_PHYSICS_DT, MAX_PHYSICS_DT, "s")
    check_integer("frame_skip", frame_skip, 1, MAX_FRAME_SKIP)
    longest = min(MAX_DURATION, MAX_EPISODE_SUBSTEPS * dt)
    note = "" if longest == MAX_DURATION else (
        f"at most {MAX_EPISODE_SUBSTEPS:.0e} steps of physics_dt {dt:g} s an episode")
    check_number("duration", duration, 0.0, longest, "s", low_open=True, note=note)
    check_number("reset_noise_scale", reset_noise_scale, 0.0, MAX_RESET_NOISE, "BL")
    check_flag("fins", fins)
    check_number("fin_max_angle", fin_max_angle, 0.0, np.pi / 2, "rad")


def validate_actions(actions: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    """Return ``actions`` as float64 of ``shape``, clipped to [-1, 1]; raise ValueError naming
    the problem for a wrong shape, NaN or infinity (before anything is changed)."""
    array = np.asarray(actions, dtype=np.float64)
    if array.shape != shape:
        raise ValueError(f"action must have shape {shape}, got {array.shape}")
    clipped = np.empty_like(array)
    if not _clip_finite(array.reshape(-1), clipped.reshape(-1)):
        bad = "NaN" if np.isnan(array).any() else "infinite"
        raise ValueError(f"action contains {bad} values: {np.asarray(actions).tolist()}")
    return clipped


@njit(cache=True)
def _clip_finite(values, out) -> bool:
    """out = values clipped to [-1, 1]; False if any value is NaN or infinite (one pass)."""
    for k in range(values.shape[0]):
        value = values[k]
        if not np.isfinite(value):
            return False
        out[k] = min(max(value, -1.0), 1.0)
    return True
