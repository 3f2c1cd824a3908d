"""The optimisers' one rule for a candidate whose body diverged: its energy (E = -return) is
not finite, and it counts as the worst there is, +inf, so that no optimiser keeps it."""

from __future__ import annotations

import numpy as np


def worst_if_diverged(energies) -> np.ndarray:
    """``energies`` (P,) as floats, each one that is not finite (NaN, +-inf) made +inf."""
    energies = np.asarray(energies, dtype=float)
    return np.where(np.isfinite(energies), energies, np.inf)
