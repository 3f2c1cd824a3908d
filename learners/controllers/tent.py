"""The paper's discretised controller: u_i(t) = sum_j u_i^j B^j(t) with tent basis functions.

A :class:`TentController` holds the nodal values u_i^j of N actuators at M nodes evenly spaced
on [t0, t1]; u(t) is their linear interpolation (held constant outside the interval). It is
played through an env as the action sequence ``a_k = 2 u((k + 1) dt) - 1``: the env ramps the
activation linearly within each step, so a controller whose nodes fall on step boundaries is
played exactly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def play(actuation, dt: float, steps: int, t0: float = 0.0) -> np.ndarray:
    """The env actions (steps, N) float32 that play ``actuation(t) -> u (..., N)``: the env step
    k ends at t0 + (k + 1) dt, where the activation must be u, so a_k = 2 u - 1 (u clipped to
    [0, 1])."""
    t = t0 + dt * np.arange(1, steps + 1)
    return (2.0 * np.clip(actuation(t), 0.0, 1.0) - 1.0).astype(np.float32)


@dataclass(frozen=True)
class TentController:
    """Nodal values ``nodes`` (N, M) in [0, 1] on [t0, t1] s (M >= 2)."""

    nodes: np.ndarray
    t0: float = 0.0
    t1: float = 1.0

    def __post_init__(self) -> None:
        nodes = np.asarray(self.nodes, dtype=float)
        if nodes.ndim != 2 or nodes.shape[1] < 2:
            raise ValueError(f"nodes must have shape (N, M >= 2), got {nodes.shape}")
        if not np.all(np.isfinite(nodes)):
            raise ValueError("nodes must be finite")
        if not self.t1 > self.t0:
            raise ValueError(f"need t1 > t0, got [{self.t0}, {self.t1}]")
        object.__setattr__(self, "nodes", nodes)

    @property
    def num_actuators(self) -> int:
        return self.nodes.shape[0]

    @property
    def num_nodes(self) -> int:
        return self.nodes.shape[1]

    @property
    def node_times(self) -> np.ndarray:
        """(M,) times of the nodes, s."""
        return np.linspace(self.t0, self.t1, self.num_nodes)

    @property
    def duration(self) -> float:
        return self.t1 - self.t0

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        """u(t), shape t.shape + (N,)."""
        t = np.asarray(t, dtype=float)
        values = [np.interp(t, self.node_times, row) for row in self.nodes]
        return np.stack(values, axis=-1)

    def derivative(self, t: np.ndarray | float) -> np.ndarray:
        """du/dt (piecewise constant; the right derivative at nodes), shape t.shape + (N,)."""
        t = np.asarray(t, dtype=float)
        spacing = self.duration / (self.num_nodes - 1)
        slopes = np.diff(self.nodes, axis=1) / spacing  # (N, M - 1)
        index = np.clip(((t - self.t0) / spacing).astype(int), 0, self.num_nodes - 2)
        inside = (t >= self.t0) & (t < self.t1)
        return np.where(inside[..., None], slopes.T[index], 0.0)

    def control_energy(self, nu1: float, nu2: float, samples: int = 1000) -> float:
        """Integral over [t0, t1] of E_u = (nu1 |du/dt|^2 + nu2 |d^2u/dt^2|^2) / 2. The second
        derivative of a piecewise-linear u is a train of impulses at the nodes; it is taken
        here as the slope change over one node spacing (the finite difference the envs use)."""
        t = np.linspace(self.t0, self.t1, samples, endpoint=False)
        first = np.sum(self.derivative(t) ** 2, axis=-1).mean() * self.duration
        spacing = self.duration / (self.num_nodes - 1)
        kinks = np.diff(self.nodes, n=2, axis=1) / spacing**2
        second = np.sum(kinks**2) * spacing
        return 0.5 * (nu1 * first + nu2 * second)

    def actions(self, dt: float, steps: int) -> np.ndarray:
        """(steps, N) float32 env actions: a_k = 2 u(t0 + (k + 1) dt) - 1."""
        return play(self, dt, steps, self.t0)

    @classmethod
    def from_vector(cls, vector: np.ndarray, num_actuators: int, t0: float, t1: float
                    ) -> TentController:
        """Build from a flat parameter vector (N * M,), actuator-major."""
        return cls(np.asarray(vector, dtype=float).reshape(num_actuators, -1), t0, t1)
