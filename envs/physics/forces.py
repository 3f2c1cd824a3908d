"""Force terms on a chunk of bodies, each a small compiled function (Numba).

Arrays are in lane layout, bodies innermost, so every loop runs over the bodies in SIMD and a
body's arithmetic is the same whatever the batch width L: ``x``, ``v`` (N, 3, L) node positions
(m) and velocities (m/s) in the world frame; ``f`` (N, 3, L) a force accumulator (N) that each
``add_*`` function adds into. The integrator (:mod:`envs.physics.integrator`) calls them once a
step.

Internal forces (:func:`add_element_forces`) are the Voigt elements' ``(c e + gamma de/dt) r/|r|``:
each acts along its element, equally and oppositely on its two nodes, so they can change neither
the linear nor the angular momentum of a body, and the damper term only removes energy.

The hydrodynamic terms act on each face with area A, unit outward normal n and velocity w
relative to the water (the weighted mean of its corners'):

* the reaction force of the data sheet, on a face moving into the water (``w.n > 0``):
  ``-kappa A (n.w) |w| n`` (``Water.reaction="paper"``) or the cross-flow form
  ``-kappa A (n.w)^2 n`` (``"crossflow"``, Taylor's resistive principle for slender bodies: the
  normal force depends on the normal velocity only, so an inclined face sliding forward is not
  charged for the whole speed);
* skin friction along the face, ``-kappa_f A |w_t| w_t`` with ``w_t`` the tangential velocity
  (``Water.friction_coefficient``; 0 turns it off).

Each magnitude is limited so that one step can at most stop the face's motion (the
semi-implicit form of quadratic drag, ``1 / (1 + dt kappa A |w| / m_face)``): light faces stay
stable, and the limiter tends to 1 as the step shrinks.
"""

from __future__ import annotations

import numpy as np
from numba import njit

FAST = {"cache": True, "fastmath": {"contract"}, "error_model": "numpy"}


@njit(cache=True, inline="always")
def submerged(z: float, surface_z: float) -> float:
    """1 below the water surface, 0 above it (the hook a surface-crossing body uses)."""
    return 1.0 if z < surface_z else 0.0


@njit(cache=True, inline="always")
def limited_drag(rate: float, normal_speed: float, mass: float, dt: float) -> float:
    """Magnitude ``rate * normal_speed`` (rate = kappa A |w|, kg/s) limited so that one step
    cannot reverse the motion it opposes, N."""
    return rate * normal_speed / (1.0 + dt * rate / mass)


@njit(**FAST)
def add_element_forces(x, v, elements, stiffness, damping, rest, f) -> None:
    """Voigt elements: ``(c (|r| - l) + gamma d|r|/dt) r/|r|`` on node i, the opposite on node j,
    with ``r = x_j - x_i``; ``rest`` (E, L) the current rest lengths, m."""
    for e in range(elements.shape[0]):
        i, j = elements[e, 0], elements[e, 1]
        c, gamma = stiffness[e], damping[e]
        for b in range(x.shape[2]):
            r0, r1, r2 = x[j, 0, b] - x[i, 0, b], x[j, 1, b] - x[i, 1, b], x[j, 2, b] - x[i, 2, b]
            length = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
            rate = ((v[j, 0, b] - v[i, 0, b]) * r0 + (v[j, 1, b] - v[i, 1, b]) * r1
                    + (v[j, 2, b] - v[i, 2, b]) * r2) / length
            scale = (c * (length - rest[e, b]) + gamma * rate) / length
            f[i, 0, b] += scale * r0
            f[i, 1, b] += scale * r1
            f[i, 2, b] += scale * r2
            f[j, 0, b] -= scale * r0
            f[j, 1, b] -= scale * r1
            f[j, 2, b] -= scale * r2


@njit(**FAST)
def add_face_forces(x, v, faces, weights, face_mass, water, dt, f) -> None:
    """Reaction force and skin friction on every face (``faces`` (F, 4), ``weights`` (F, 4)).

    A face's area vector is half the cross product of its diagonals (exact for a planar quad
    and for a triangle given as a quad with a repeated corner); its velocity and height are the
    weighted means of its corners'. ``water`` is :attr:`envs.physics.system.System.water_args`."""
    kappa_water, kappa_air, friction_water, friction_air, crossflow, surface_z = water[:6]
    c0, c1, c2 = water[6], water[7], water[8]
    lanes = x.shape[2]
    for k in range(faces.shape[0]):
        a, b, c, d = faces[k, 0], faces[k, 1], faces[k, 2], faces[k, 3]
        for lane in range(lanes):
            p0, p1, p2 = (x[c, 0, lane] - x[a, 0, lane], x[c, 1, lane] - x[a, 1, lane],
                          x[c, 2, lane] - x[a, 2, lane])
            q0, q1, q2 = (x[d, 0, lane] - x[b, 0, lane], x[d, 1, lane] - x[b, 1, lane],
                          x[d, 2, lane] - x[b, 2, lane])
            n0, n1, n2 = (0.5 * (p1 * q2 - p2 * q1), 0.5 * (p2 * q0 - p0 * q2),
                          0.5 * (p0 * q1 - p1 * q0))
            area = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
            if area == 0.0:
                continue
            n0, n1, n2 = n0 / area, n1 / area, n2 / area
            w0, w1, w2, height = -c0, -c1, -c2, 0.0
            for q in range(4):
                node, share = faces[k, q], weights[k, q]
                w0 += share * v[node, 0, lane]
                w1 += share * v[node, 1, lane]
                w2 += share * v[node, 2, lane]
                height += share * x[node, 2, lane]
            wet = submerged(height, surface_z)
            normal_speed = n0 * w0 + n1 * w1 + n2 * w2
            t0, t1, t2 = w0 - normal_speed * n0, w1 - normal_speed * n1, w2 - normal_speed * n2
            tangential = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
            normal_force = 0.0
            if normal_speed > 0.0:
                kappa = kappa_air + (kappa_water - kappa_air) * wet
                along = normal_speed if crossflow else np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
                normal_force = limited_drag(kappa * area * along, normal_speed, face_mass[k], dt)
            friction = 0.0
            if tangential > 0.0:
                kappa_f = friction_air + (friction_water - friction_air) * wet
                friction = limited_drag(kappa_f * area * tangential, 1.0, face_mass[k], dt)
            g0 = normal_force * n0 + friction * t0
            g1 = normal_force * n1 + friction * t1
            g2 = normal_force * n2 + friction * t2
            for q in range(4):
                node, share = faces[k, q], weights[k, q]
                f[node, 0, lane] -= share * g0
                f[node, 1, lane] -= share * g1
                f[node, 2, lane] -= share * g2


@njit(cache=True, inline="always")
def _centroid(x, nodes, axis, lane) -> float:
    total = 0.0
    for k in range(nodes.shape[0]):
        total += x[nodes[k], axis, lane]
    return total / nodes.shape[0]


@njit(cache=True)
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


@njit(cache=True)
def add_fin_forces(x, v, frame_nodes, fin_nodes, fin_areas, fin_mass, sin_cos, water, dt, f,
                   frame) -> None:
    """Pectoral fins as two-sided plates; fin p's normal is the body's up vector pitched by the
    fin angle about the body's lateral axis (``sin_cos`` (L, P, 2) its sine and cosine),
    leading edge up for a positive angle. Same angle on both fins: lift (pitch, depth);
    opposite angles: roll; a large angle on one side: drag on that side (yaw). ``frame_nodes``:
    (front, back, up, down) node lists; ``frame`` (3, 3) scratch space."""
    kappa_water, kappa_air, surface_z = water[0], water[1], water[5]
    c0, c1, c2 = water[6], water[7], water[8]
    front, back, up, down = frame_nodes
    for lane in range(x.shape[2]):
        body_frame_into(x, lane, front, back, up, down, frame)
        for p in range(fin_nodes.shape[0]):
            sin_a, cos_a = sin_cos[lane, p, 0], sin_cos[lane, p, 1]
            n0 = -sin_a * frame[0, 0] + cos_a * frame[2, 0]
            n1 = -sin_a * frame[0, 1] + cos_a * frame[2, 1]
            n2 = -sin_a * frame[0, 2] + cos_a * frame[2, 2]
            nodes = fin_nodes[p]
            count = nodes.shape[0]
            w0, w1, w2 = -c0, -c1, -c2
            for q in range(count):
                w0 += v[nodes[q], 0, lane] / count
                w1 += v[nodes[q], 1, lane] / count
                w2 += v[nodes[q], 2, lane] / count
            kappa = kappa_air + (kappa_water - kappa_air) * submerged(
                _centroid(x, nodes, 2, lane), surface_z)
            speed = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
            magnitude = limited_drag(kappa * fin_areas[p] * speed, n0 * w0 + n1 * w1 + n2 * w2,
                                     fin_mass[p], dt)
            for q in range(count):
                f[nodes[q], 0, lane] -= magnitude * n0 / count
                f[nodes[q], 1, lane] -= magnitude * n1 / count
                f[nodes[q], 2, lane] -= magnitude * n2 / count


@njit(**FAST)
def add_gravity_buoyancy(x, masses, volumes, density, gravity, surface_z, f) -> None:
    """Weight ``-m g`` on every node and buoyancy ``rho g V`` on every submerged node, along z."""
    for i in range(x.shape[0]):
        weight, lift = gravity * masses[i], gravity * density * volumes[i]
        for b in range(x.shape[2]):
            f[i, 2, b] += lift * submerged(x[i, 2, b], surface_z) - weight
