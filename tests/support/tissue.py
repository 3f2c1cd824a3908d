"""The tissue's measure: the least and the greatest length, relative to rest, of any passive
element over an episode of given actions, in either water (the resistive water's limits are
checked in ``tests/envs/physics/test_tissue.py``, the reactive's in ``test_reactive.py``)."""

import numpy as np

from animat.envs.core.batch import BodyBatch
from animat.envs.tasks.locomotion import SwimTask


def passive_strain_range(actions: np.ndarray, water: dict | None = None) -> tuple[float, float]:
    """Min and max passive strain over an episode of actions (T, B, 6) in ``water`` (default
    the default water), seeded starts."""
    core = BodyBatch(actions.shape[1], SwimTask(), duration=1e3, water=water)
    core.reset_rows(np.arange(actions.shape[1]),
                    [np.random.default_rng(k) for k in range(actions.shape[1])])
    body, low, high = core.body, np.inf, 0.0
    passive = body.actuator < 0
    for action in actions:
        core.step(action.astype(np.float64))
        x = core.state.x
        assert np.isfinite(x).all(), "a body blew up"  # min/max would pass over a NaN
        r = x[:, body.elements[passive, 1]] - x[:, body.elements[passive, 0]]
        strain = np.linalg.norm(r, axis=2) / body.rest_lengths[passive]
        low, high = min(low, strain.min()), max(high, strain.max())
    return low, high
