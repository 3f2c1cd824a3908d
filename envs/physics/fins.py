"""The pectoral fins' force (Numba), and the body frame it pitches them in.

Arrays as in :mod:`animat.envs.physics.forces` (lane layout, bodies innermost): ``x``, ``v``
(N, 3, L) node positions (m) and velocities (m/s), ``f`` (N, 3, L) the force accumulator
:func:`add_fin_forces` adds into. A fin is a two-sided plate at the mean of its nodes, with the
drag law and limiter of the faces (:func:`animat.envs.physics.forces.limited_drag`), wet or dry
as its centre is under the surface or not. :func:`body_frame_into` is also the body frame the
sensors report (:mod:`animat.envs.physics.observe`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .forces import BATCH, FAST, lane_count, limited_drag, submerged
from .system import AIR_COEFFICIENT, CURRENT_X, CURRENT_Y, CURRENT_Z, FLUID_COEFFICIENT, SURFACE_Z


@njit(cache=True, inline="always")
def _centroid(x, nodes, axis, lane) -> float:
    total = 0.0
    for k in range(nodes.shape[0]):
        total += x[nodes[k], axis, lane]
    return total / nodes.shape[0]


@njit(cache=True, inline="always")
def body_frame_into(x, lane, front, back, up, down, frame) -> None:
    """Write body ``lane``'s frame into ``frame`` (3, 3): rows forward, left, up (right-handed);
    x (N, 3, L)."""
    f0 = _centroid(x, front, 0, lane) - _centroid(x, back, 0, lane)
    f1 = _centroid(x, front, 1, lane) - _centroid(x, back, 1, lane)
    f2 = _centroid(x, front, 2, lane) - _centroid(x, back, 2, lane)
    norm = np.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
    f0, f1, f2 = f0 / norm, f1 / norm, f2 / norm
    u0 = _centroid(x, up, 0, lane) - _centroid(x, down, 0, lane)
    u1 = _centroid(x, up, 1, lane) - _centroid(x, down, 1, lane)
    u2 = _centroid(x, up, 2, lane) - _centroid(x, down, 2, lane)
    along = u0 * f0 + u1 * f1 + u2 * f2
    u0, u1, u2 = u0 - along * f0, u1 - along * f1, u2 - along * f2
    norm = np.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    u0, u1, u2 = u0 / norm, u1 / norm, u2 / norm
    frame[0, 0], frame[0, 1], frame[0, 2] = f0, f1, f2
    frame[1, 0], frame[1, 1], frame[1, 2] = u1 * f2 - u2 * f1, u2 * f0 - u0 * f2, u0 * f1 - u1 * f0
    frame[2, 0], frame[2, 1], frame[2, 2] = u0, u1, u2


@njit(**FAST)
def add_fin_forces(x, v, frame_nodes, fin_nodes, fin_areas, fin_mass, sin_cos, water, dt, f,
                   scratch, one_body=BATCH) -> None:
    """Pectoral fins as two-sided plates; fin p's normal is the body's up vector pitched by the
    fin angle about the body's lateral axis (``sin_cos`` (P, 2, L) its sine and cosine),
    leading edge up for a positive angle. Same angle on both fins: lift (pitch, depth);
    opposite angles: roll; a large angle on one side: drag on that side (yaw). ``frame_nodes``:
    (front, back, up, down) node lists; ``scratch`` (16, L) work space; ``one_body``:
    :func:`animat.envs.physics.forces.lane_count`."""
    kappa_water, kappa_air = water[FLUID_COEFFICIENT], water[AIR_COEFFICIENT]
    surface_z = water[SURFACE_Z]
    c0, c1, c2 = water[CURRENT_X], water[CURRENT_Y], water[CURRENT_Z]
    front, back, up, down = frame_nodes
    frame = np.empty((3, 3))
    lanes = lane_count(x, one_body)
    for lane in range(lanes):
        body_frame_into(x, lane, front, back, up, down, frame)
        for row in range(3):
            for axis in range(3):
                scratch[3 * row + axis, lane] = frame[row, axis]
    for p in range(fin_nodes.shape[0]):
        nodes = fin_nodes[p]
        share = 1.0 / nodes.shape[0]
        scratch[9:13] = 0.0
        for q in range(nodes.shape[0]):
            node = nodes[q]
            for lane in range(lanes):
                scratch[9, lane] += share * v[node, 0, lane]
                scratch[10, lane] += share * v[node, 1, lane]
                scratch[11, lane] += share * v[node, 2, lane]
                scratch[12, lane] += share * x[node, 2, lane]
        area, mass = fin_areas[p], fin_mass[p]
        for lane in range(lanes):
            sin_a, cos_a = sin_cos[p, 0, lane], sin_cos[p, 1, lane]
            n0 = -sin_a * scratch[0, lane] + cos_a * scratch[6, lane]
            n1 = -sin_a * scratch[1, lane] + cos_a * scratch[7, lane]
            n2 = -sin_a * scratch[2, lane] + cos_a * scratch[8, lane]
            w0, w1, w2 = scratch[9, lane] - c0, scratch[10, lane] - c1, scratch[11, lane] - c2
            kappa = kappa_air + (kappa_water - kappa_air) * submerged(scratch[12, lane], surface_z)
            speed = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
            magnitude = share * limited_drag(kappa * area * speed, n0 * w0 + n1 * w1 + n2 * w2,
                                             mass, dt)
            scratch[13, lane], scratch[14, lane] = magnitude * n0, magnitude * n1
            scratch[15, lane] = magnitude * n2
        for q in range(nodes.shape[0]):
            node = nodes[q]
            for lane in range(lanes):
                f[node, 0, lane] -= scratch[13, lane]
                f[node, 1, lane] -= scratch[14, lane]
                f[node, 2, lane] -= scratch[15, lane]
