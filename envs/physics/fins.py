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

from .forces import BATCH, FAST, add_nodes, lane_count, limited_drag, submerged
from .system import AIR_COEFFICIENT, CURRENT_X, CURRENT_Y, CURRENT_Z, FLUID_COEFFICIENT, SURFACE_Z


@njit(cache=True, inline="always")
def _centroid(x, nodes, axis, lane) -> float:
    total = 0.0
    for k in range(nodes.shape[0]):
        total += x[nodes[k], axis, lane]
    return total / nodes.shape[0]


@njit(cache=True, inline="always")
def _frame_rows(f0, f1, f2, u0, u1, u2):
    """The body frame's rows (forward, left, up: nine numbers, right-handed) from the forward
    axis f and the up axis u (m): f normalised, u made normal to it and normalised, left =
    up x forward."""
    norm = np.sqrt(f0 * f0 + f1 * f1 + f2 * f2)
    f0, f1, f2 = f0 / norm, f1 / norm, f2 / norm
    along = u0 * f0 + u1 * f1 + u2 * f2
    u0, u1, u2 = u0 - along * f0, u1 - along * f1, u2 - along * f2
    norm = np.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    u0, u1, u2 = u0 / norm, u1 / norm, u2 / norm
    return (f0, f1, f2, u1 * f2 - u2 * f1, u2 * f0 - u0 * f2, u0 * f1 - u1 * f0, u0, u1, u2)


@njit(cache=True, inline="always")
def _lane_frame(x, lane, front, back, up, down):
    """Body ``lane``'s frame rows (:func:`_frame_rows`) from its nodes, x (N, 3, L)."""
    return _frame_rows(
        _centroid(x, front, 0, lane) - _centroid(x, back, 0, lane),
        _centroid(x, front, 1, lane) - _centroid(x, back, 1, lane),
        _centroid(x, front, 2, lane) - _centroid(x, back, 2, lane),
        _centroid(x, up, 0, lane) - _centroid(x, down, 0, lane),
        _centroid(x, up, 1, lane) - _centroid(x, down, 1, lane),
        _centroid(x, up, 2, lane) - _centroid(x, down, 2, lane))


@njit(cache=True, inline="always")
def body_frame_into(x, lane, front, back, up, down, frame) -> None:
    """Write body ``lane``'s frame into ``frame`` (3, 3): rows forward, left, up (right-handed);
    x (N, 3, L)."""
    rows = _lane_frame(x, lane, front, back, up, down)
    frame[0, 0], frame[0, 1], frame[0, 2] = rows[0], rows[1], rows[2]
    frame[1, 0], frame[1, 1], frame[1, 2] = rows[3], rows[4], rows[5]
    frame[2, 0], frame[2, 1], frame[2, 2] = rows[6], rows[7], rows[8]


@njit(**FAST)
def _frames_into_lanes(x, front, back, up, down, out) -> None:
    """out[0:9] (9, L): every lane's :func:`body_frame_into` rows, forward, left, up, in lane
    loops that run in SIMD (rather than the frame computed body by body). The same operations
    in the same order, so the same numbers."""
    sums = np.zeros((12, x.shape[2]))  # each node group's coordinates summed, in order from 0
    add_nodes(x, front, 1.0, sums[0:3])  # (as _centroid sums them: times 1.0 is exact)
    add_nodes(x, back, 1.0, sums[3:6])
    add_nodes(x, up, 1.0, sums[6:9])
    add_nodes(x, down, 1.0, sums[9:12])
    n_front, n_back, n_up, n_down = front.shape[0], back.shape[0], up.shape[0], down.shape[0]
    for lane in range(x.shape[2]):
        rows = _frame_rows(sums[0, lane] / n_front - sums[3, lane] / n_back,
                           sums[1, lane] / n_front - sums[4, lane] / n_back,
                           sums[2, lane] / n_front - sums[5, lane] / n_back,
                           sums[6, lane] / n_up - sums[9, lane] / n_down,
                           sums[7, lane] / n_up - sums[10, lane] / n_down,
                           sums[8, lane] / n_up - sums[11, lane] / n_down)
        out[0, lane], out[1, lane], out[2, lane] = rows[0], rows[1], rows[2]
        out[3, lane], out[4, lane], out[5, lane] = rows[3], rows[4], rows[5]
        out[6, lane], out[7, lane], out[8, lane] = rows[6], rows[7], rows[8]


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
    lanes = lane_count(x, one_body)
    if one_body is None:
        _frames_into_lanes(x, front, back, up, down, scratch)
    else:  # one body: faster without the lane loops (no vector set-up for one lane)
        rows = _lane_frame(x, 0, front, back, up, down)
        scratch[0, 0], scratch[1, 0], scratch[2, 0] = rows[0], rows[1], rows[2]
        scratch[3, 0], scratch[4, 0], scratch[5, 0] = rows[3], rows[4], rows[5]
        scratch[6, 0], scratch[7, 0], scratch[8, 0] = rows[6], rows[7], rows[8]
    for p in range(fin_nodes.shape[0]):
        nodes = fin_nodes[p]
        share = 1.0 / nodes.shape[0]
        for row in range(9, 13):
            for lane in range(lanes):
                scratch[row, lane] = 0.0
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
