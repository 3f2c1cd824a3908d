"""The reward of every fish environment: its weights (:class:`RewardWeights`) and the control
energy (:func:`control_energy`); :meth:`animat.envs.core.batch.BodyBatch.step` sums them.

Reward (the paper's Eq. 1, per env step of ``dt`` seconds):
``r = -(mu1 E_u + mu2 E_v) dt``, ``E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2) / 2`` over the six
actuations u in [0, 1] (finite differences over env steps), E_v from the task.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from ..checks import check_number, shown

MAX_REWARD_WEIGHT = 1e6


@dataclass(frozen=True)
class RewardWeights:
    """Weights of Eq. (1): mu1 (controller), mu2 (trajectory); nu1 (|du/dt|^2), nu2
    (|d^2u/dt^2|^2). Each a finite number in [0, ``MAX_REWARD_WEIGHT``] (1e6)."""

    mu1: float = 1e-4
    mu2: float = 1.0
    nu1: float = 1.0
    nu2: float = 0.01

    def __post_init__(self) -> None:
        for name in ("mu1", "mu2", "nu1", "nu2"):
            check_number(f"reward_weights.{name}", getattr(self, name), 0.0, MAX_REWARD_WEIGHT)

    @classmethod
    def from_value(cls, value: RewardWeights | dict | None) -> RewardWeights:
        """The weights of an env's ``reward_weights`` argument: None (the defaults), weights,
        or a dict of some of mu1, mu2, nu1, nu2; anything else, or an unknown name, is a
        ValueError of one line naming it."""
        if value is None or isinstance(value, RewardWeights):
            return value or cls()
        if not isinstance(value, dict):
            raise ValueError(f"reward_weights must be a dict of mu1, mu2, nu1, nu2, got "
                             f"{shown(value)}")
        unknown = sorted(map(str, set(value) - {"mu1", "mu2", "nu1", "nu2"}))
        if unknown:
            raise ValueError(f"reward_weights: unknown weight(s) {shown(unknown)}; known: "
                             "['mu1', 'mu2', 'nu1', 'nu2']")
        return cls(**value)


@njit(cache=True)
def control_energy(u, u_prev, u_prev2, dt, nu1, nu2):
    """(B,) E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2) / 2 by finite differences over env steps
    of ``dt`` s, actuations u, u_prev, u_prev2 (B, A) at this and the two previous steps."""
    out = np.zeros(u.shape[0])
    for b in range(u.shape[0]):
        first = second = 0.0
        for k in range(u.shape[1]):
            du = (u[b, k] - u_prev[b, k]) / dt
            ddu = (u[b, k] - 2.0 * u_prev[b, k] + u_prev2[b, k]) / (dt * dt)
            first += du * du
            second += ddu * ddu
        out[b] = 0.5 * (nu1 * first + nu2 * second)
    return out
