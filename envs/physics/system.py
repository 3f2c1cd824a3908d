"""Fixed physical parameters of a simulation (the frozen ``System``) and the per-step ``State``.

Following Brax's split, everything that does not change during a rollout (the body, the
water, the integration step, the matrices derived from them) lives in a frozen
:class:`System`; the moving parts (node positions and velocities, time) live in a
:class:`State` of batched arrays. ``System.kernel_args`` packs the constants in the order the
compiled step kernel (:mod:`envs.physics.integrator`) expects.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from envs.body import BodySpec, frozen_array


@dataclass(frozen=True)
class Water:
    """The medium the body moves in.

    Attributes:
        fluid_coefficient: scales the face reaction force ``-A (n.v)|v| n``, kg/m^3.
            ``0.5 * rho * C_d`` with rho = 1000 kg/m^3 and a flat-plate C_d of 1 gives 500.
        air_coefficient: the same above the surface (0.5 * 1.2 kg/m^3 * 1).
        density: water density for buoyancy, kg/m^3.
        gravity: m/s^2, acting along -z.
        surface_z: height of the water surface, m (``inf``: no surface, everything submerged).
        current: (3,) water velocity in the world frame, m/s.
    """

    fluid_coefficient: float = 500.0
    air_coefficient: float = 0.6
    density: float = 1000.0
    gravity: float = 9.81
    surface_z: float = float("inf")
    current: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        for name in ("fluid_coefficient", "air_coefficient", "density", "gravity"):
            value = getattr(self, name)
            if not np.isfinite(value) or value < 0:
                raise ValueError(f"Water.{name} must be finite and >= 0, got {value!r}")
        if len(self.current) != 3 or not np.all(np.isfinite(self.current)):
            raise ValueError(f"Water.current must be 3 finite numbers, got {self.current!r}")


@dataclass(frozen=True, eq=False)
class System:
    """A body in water, integrated with a fixed step ``dt`` (s) and ``iterations`` solver sweeps
    (Chebyshev-accelerated with spectral-radius estimate ``chebyshev_rho``; 0 turns it off).

    Derived constants (computed once):
        inverse_matrix: (N, N) inverse of ``M/dt^2 + L_c + L_gamma/dt``, the constant matrix of
            the implicit step (M: masses, L_c and L_gamma: stiffness- and damping-weighted
            graph Laplacians of the elements). It is the same for x, y and z and every body.
        face_mass: (F,) mass a face's normal motion meets in one implicit step, kg.
        fin_mass: (P,) the same for each fin, kg.
    """

    body: BodySpec
    water: Water = field(default_factory=Water)
    dt: float = 0.025
    iterations: int = 10
    chebyshev_rho: float = 0.9
    inverse_matrix: np.ndarray = field(init=False, repr=False)
    face_mass: np.ndarray = field(init=False, repr=False)
    fin_mass: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"System.dt must be a positive number of seconds, got {self.dt!r}")
        if int(self.iterations) < 1:
            raise ValueError(f"System.iterations must be >= 1, got {self.iterations!r}")
        inverse = np.linalg.inv(implicit_matrix(self.body, self.dt))
        fin_weights = np.full(self.body.fin_nodes.shape, 1.0 / self.body.fin_nodes.shape[1])
        object.__setattr__(self, "inverse_matrix", frozen_array(inverse))
        object.__setattr__(self, "face_mass", frozen_array(implicit_masses(
            inverse, self.body.faces, self.body.face_weights, self.dt)))
        object.__setattr__(self, "fin_mass", frozen_array(implicit_masses(
            inverse, self.body.fin_nodes, fin_weights, self.dt)))

    @cached_property
    def kernel_args(self) -> tuple:
        """Constants for :func:`envs.physics.integrator.step_batch`, in its argument order."""
        b, w = self.body, self.water
        return (
            b.masses, b.volumes, b.elements, b.stiffness, b.damping, b.rest_lengths, b.actuator,
            float(b.max_contraction), b.faces, b.face_weights, self.face_mass, b.fin_nodes,
            b.fin_areas, self.fin_mass, b.frame_front, b.frame_back, b.frame_up, b.frame_down,
            self.inverse_matrix, float(w.fluid_coefficient), float(w.air_coefficient),
            float(w.density), float(w.gravity), float(w.surface_z),
            np.asarray(w.current, dtype=np.float64), float(self.dt), int(self.iterations),
            float(self.chebyshev_rho),
        )


def implicit_matrix(body: BodySpec, dt: float) -> np.ndarray:
    """(N, N) matrix ``M/dt^2 + L_c + L_gamma/dt`` of the projective implicit-Euler step."""
    n = body.num_nodes
    weights = body.stiffness + body.damping / dt
    laplacian = np.zeros((n, n))
    i, j = body.elements[:, 0], body.elements[:, 1]
    np.add.at(laplacian, (i, i), weights)
    np.add.at(laplacian, (j, j), weights)
    np.add.at(laplacian, (i, j), -weights)
    np.add.at(laplacian, (j, i), -weights)
    return np.diag(body.masses / dt**2) + laplacian


def implicit_masses(inverse: np.ndarray, nodes: np.ndarray, weights: np.ndarray,
                    dt: float) -> np.ndarray:
    """(F,) mass that a force spread over ``nodes`` (F, K) with ``weights`` (F, K) meets in one
    implicit step, kg: ``dt^2 / (w' A^-1 w)``. It counts the nodes the elements tie to the
    face, so the drag limiter of :mod:`envs.physics.forces` is the step's own response."""
    compliance = np.zeros(nodes.shape[0])
    for k in range(nodes.shape[1]):
        for q in range(nodes.shape[1]):
            compliance += weights[:, k] * weights[:, q] * inverse[nodes[:, k], nodes[:, q]]
    return dt**2 / compliance
