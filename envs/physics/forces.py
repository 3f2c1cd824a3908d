"""Force terms on one body, each a small compiled function (Numba) of the body's nodes.

Arrays per body: ``x``, ``v`` (N, 3) node positions (m) and velocities (m/s) in the world
frame; ``f`` (N, 3) a force accumulator (N) that each ``add_*`` function adds into. They are
called by the integrator (:mod:`envs.physics.integrator`) for every body of a batch.

The hydrodynamic terms are the data sheet's reaction force ``f = -kappa A (n.v)|v| n`` on a face
moving into the water. They are applied explicitly, with the magnitude limited so that one step
can at most stop the face's normal motion (``1 / (1 + dt kappa A |v| / m_face)``, the
semi-implicit form of quadratic drag): a light tail fin with a large face stays stable.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def submerged(z: float, surface_z: float) -> float:
    """1 below the water surface, 0 above it (the hook a surface-crossing body uses)."""
    return 1.0 if z < surface_z else 0.0


@njit(cache=True, inline="always")
def centroid(x: np.ndarray, nodes: np.ndarray) -> tuple[float, float, float]:
    """Mean position of ``nodes`` as a tuple (x, y, z)."""
    c0 = c1 = c2 = 0.0
    for k in range(nodes.shape[0]):
        c0 += x[nodes[k], 0]
        c1 += x[nodes[k], 1]
        c2 += x[nodes[k], 2]
    n = nodes.shape[0]
    return c0 / n, c1 / n, c2 / n


@njit(cache=True, inline="always")
def _unit(a0: float, a1: float, a2: float) -> tuple[float, float, float]:
    norm = np.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
    return a0 / norm, a1 / norm, a2 / norm


@njit(cache=True)
def body_frame_into(x, front, back, up, down, frame) -> None:
    """Write the body frame into ``frame`` (3, 3): rows forward, left, up (right-handed)."""
    f0, f1, f2 = centroid(x, front)
    b0, b1, b2 = centroid(x, back)
    f0, f1, f2 = _unit(f0 - b0, f1 - b1, f2 - b2)
    u0, u1, u2 = centroid(x, up)
    d0, d1, d2 = centroid(x, down)
    u0, u1, u2 = u0 - d0, u1 - d1, u2 - d2
    along = u0 * f0 + u1 * f1 + u2 * f2
    u0, u1, u2 = _unit(u0 - along * f0, u1 - along * f1, u2 - along * f2)
    frame[0, 0], frame[0, 1], frame[0, 2] = f0, f1, f2
    frame[1, 0], frame[1, 1], frame[1, 2] = u1 * f2 - u2 * f1, u2 * f0 - u0 * f2, u0 * f1 - u1 * f0
    frame[2, 0], frame[2, 1], frame[2, 2] = u0, u1, u2


@njit(cache=True, inline="always")
def limited_drag(kappa: float, area: float, normal_speed: float, speed: float, mass: float,
                 dt: float) -> float:
    """Magnitude of ``kappa A v_n |v|`` limited so one step cannot reverse v_n, N."""
    rate = kappa * area * speed
    return rate * normal_speed / (1.0 + dt * rate / mass)


@njit(cache=True)
def add_face_forces(x, v, faces, weights, face_mass, kappa_water, kappa_air, surface_z,
                    current, dt, f) -> None:
    """Reaction force on every face moving into the water (``faces`` (F, 4), ``weights`` (F, 4)).

    A face's area vector is half the cross product of its diagonals (exact for a planar quad
    and for a triangle given as a quad with a repeated corner); its velocity and height are
    the weighted means of its corners'."""
    for k in range(faces.shape[0]):
        a, b, c, d = faces[k, 0], faces[k, 1], faces[k, 2], faces[k, 3]
        p0, p1, p2 = x[c, 0] - x[a, 0], x[c, 1] - x[a, 1], x[c, 2] - x[a, 2]
        q0, q1, q2 = x[d, 0] - x[b, 0], x[d, 1] - x[b, 1], x[d, 2] - x[b, 2]
        n0, n1, n2 = 0.5 * (p1 * q2 - p2 * q1), 0.5 * (p2 * q0 - p0 * q2), 0.5 * (p0 * q1 - p1 * q0)
        area = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        if area == 0.0:
            continue
        n0, n1, n2 = n0 / area, n1 / area, n2 / area
        w0, w1, w2, height = -current[0], -current[1], -current[2], 0.0
        for q in range(4):
            node, share = faces[k, q], weights[k, q]
            w0 += share * v[node, 0]
            w1 += share * v[node, 1]
            w2 += share * v[node, 2]
            height += share * x[node, 2]
        normal_speed = n0 * w0 + n1 * w1 + n2 * w2
        if normal_speed <= 0.0:
            continue
        kappa = kappa_air + (kappa_water - kappa_air) * submerged(height, surface_z)
        speed = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
        magnitude = limited_drag(kappa, area, normal_speed, speed, face_mass[k], dt)
        for q in range(4):
            node, share = faces[k, q], weights[k, q] * magnitude
            f[node, 0] -= share * n0
            f[node, 1] -= share * n1
            f[node, 2] -= share * n2


@njit(cache=True)
def add_fin_forces(x, v, frame, fin_nodes, fin_areas, fin_mass, fin_angles, kappa_water,
                   kappa_air, surface_z, current, dt, f) -> None:
    """Pectoral fins as two-sided plates; fin p's normal is the body's up vector pitched by
    ``fin_angles[p]`` (rad) about the body's lateral axis, leading edge up for a positive angle.
    Same angle on both fins: lift (pitch, depth); opposite angles: roll; a large angle on one
    side: drag on that side (yaw)."""
    for p in range(fin_nodes.shape[0]):
        sin_a, cos_a = np.sin(fin_angles[p]), np.cos(fin_angles[p])
        n0 = -sin_a * frame[0, 0] + cos_a * frame[2, 0]
        n1 = -sin_a * frame[0, 1] + cos_a * frame[2, 1]
        n2 = -sin_a * frame[0, 2] + cos_a * frame[2, 2]
        nodes = fin_nodes[p]
        count = nodes.shape[0]
        w0, w1, w2 = -current[0], -current[1], -current[2]
        for q in range(count):
            w0 += v[nodes[q], 0] / count
            w1 += v[nodes[q], 1] / count
            w2 += v[nodes[q], 2] / count
        height = centroid(x, nodes)[2]
        kappa = kappa_air + (kappa_water - kappa_air) * submerged(height, surface_z)
        speed = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
        normal_speed = n0 * w0 + n1 * w1 + n2 * w2
        magnitude = limited_drag(kappa, fin_areas[p], normal_speed, speed, fin_mass[p], dt)
        for q in range(count):
            f[nodes[q], 0] -= magnitude * n0 / count
            f[nodes[q], 1] -= magnitude * n1 / count
            f[nodes[q], 2] -= magnitude * n2 / count


@njit(cache=True)
def add_gravity_buoyancy(x, masses, volumes, density, gravity, surface_z, f) -> None:
    """Weight ``-m g`` on every node and buoyancy ``rho g V`` on every submerged node, along z."""
    for i in range(x.shape[0]):
        f[i, 2] += gravity * (density * volumes[i] * submerged(x[i, 2], surface_z) - masses[i])


@njit(cache=True)
def muscle_rest_lengths(rest, actuator, max_contraction, activation, out) -> None:
    """Rest lengths (E,) with muscle e shortened to ``l0 (1 - max_contraction u)``, m."""
    for e in range(rest.shape[0]):
        a = actuator[e]
        out[e] = rest[e] if a < 0 else rest[e] * (1.0 - max_contraction * activation[a])
