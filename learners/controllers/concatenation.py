"""Concatenating abstracted controllers (the paper's Fig. 10): controllers played in sequence,
each pair of neighbours blended by fading one out and the other in linearly over an overlap of
about 5% of each."""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

Controller = Callable[[np.ndarray], np.ndarray]  # u(t): t.shape -> t.shape + (N,)


def schedule(durations: Sequence[float], overlap: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """Start times (K,) and blend lengths (K - 1,) of K controllers with ``durations`` (s):
    controller k + 1 starts ``blend_k = overlap * min(d_k, d_k+1)`` before controller k ends."""
    durations = np.asarray(durations, dtype=float)
    if durations.ndim != 1 or len(durations) == 0 or np.any(durations <= 0):
        raise ValueError(f"durations must be positive seconds, got {durations.tolist()}")
    if not 0.0 <= overlap < 0.5:
        raise ValueError(f"overlap must be in [0, 0.5), got {overlap!r}")
    blends = overlap * np.minimum(durations[:-1], durations[1:])
    starts = np.concatenate([[0.0], np.cumsum(durations[:-1] - blends)])
    return starts, blends


def concatenate(controllers: Sequence[Controller], durations: Sequence[float],
                overlap: float = 0.05) -> tuple[Controller, float]:
    """A controller that plays ``controllers[k]`` (each on its own time from 0) for
    ``durations[k]`` s in turn, blended over the overlaps. Returns it and its total duration."""
    if len(controllers) != len(durations):
        raise ValueError("need one duration per controller")
    starts, blends = schedule(durations, overlap)
    ends = starts + np.asarray(durations, dtype=float)

    def blended(t: np.ndarray | float) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        total = 0.0
        for k, controller in enumerate(controllers):
            local = t - starts[k]
            weight = ((local >= 0) & (t < ends[k])).astype(float)
            if k > 0 and blends[k - 1] > 0:  # fade in over the overlap with the previous one
                weight = weight * np.clip(local / blends[k - 1], 0.0, 1.0)
            if k < len(controllers) - 1 and blends[k] > 0:  # fade out into the next one
                weight = weight * np.clip((ends[k] - t) / blends[k], 0.0, 1.0)
            if k == len(controllers) - 1:
                weight = np.where(t >= ends[k], 1.0, weight)  # hold the last one at the end
            total = total + weight[..., None] * controller(np.maximum(local, 0.0))
        return total

    return blended, float(ends[-1])
