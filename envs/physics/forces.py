"""Force terms on a chunk of bodies, each a small compiled function (Numba).

Arrays are in lane layout, bodies innermost, so every loop runs over the bodies in SIMD and a
body's arithmetic is the same whatever the batch width L: ``x``, ``v`` (N, 3, L) node positions
(m) and velocities (m/s) in the world frame; ``f`` (N, 3, L) a force accumulator (N) that each
``add_*`` function adds into. The integrator (:mod:`animat.envs.physics.integrator`) calls them
once a step, with the fins' force (:mod:`animat.envs.physics.fins`).

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
from numba import njit, types
from numba.core.errors import TypingError
from numba.extending import overload

from .system import (
    AIR_COEFFICIENT,
    AIR_FRICTION_COEFFICIENT,
    CROSSFLOW,
    CURRENT_X,
    CURRENT_Y,
    CURRENT_Z,
    DENSITY,
    FLUID_COEFFICIENT,
    FRICTION_COEFFICIENT,
    SURFACE_Z,
)

FAST = {"cache": True, "fastmath": {"contract"}, "error_model": "numpy"}

BATCH = None  # a kernel's ``one_body``: run the lanes the arrays hold (their last axis)
ONE_BODY = True  # ... or exactly one, a specialisation of its own (see lane_count)


def lane_count(lanes_array, one_body) -> int:
    """How many bodies a kernel's lane loops run over: ``lanes_array``'s last axis for
    ``one_body`` BATCH (None), or 1 for ONE_BODY (True).

    In compiled code the choice is made from ``one_body``'s type, so ONE_BODY compiles every
    kernel again with the constant 1: its lane loops unroll, with no vector set-up or overlap
    checks around the one body's arithmetic, which for one body costs more than the arithmetic
    itself (``animat bench --breakdown`` times both). The arithmetic is the same, and a body
    gets the same numbers bit for bit either way (tests/envs/physics/test_dynamics.py checks
    it: a fused multiply-add formed in one and not the other would break it). Pass BATCH or
    ONE_BODY only: any boolean is read as one body."""
    return lanes_array.shape[-1] if one_body is None else 1


@overload(lane_count, inline="always")
def _lane_count(lanes_array, one_body):
    if isinstance(one_body, (types.NoneType, types.Omitted)):
        return lambda lanes_array, one_body: lanes_array.shape[-1]
    if isinstance(one_body, types.Boolean):
        return lambda lanes_array, one_body: 1
    raise TypingError(f"one_body must be BATCH (None) or ONE_BODY (True), got {one_body}")


@njit(**FAST)
def add_nodes(x, nodes, share, out, one_body=BATCH) -> None:
    """out (3, L) += ``share`` times each of the ``nodes``' positions (x (N, 3, L)), node by
    node in order (a function of its own: inlined, its lane loop did not run in SIMD)."""
    lanes = lane_count(x, one_body)
    for k in range(nodes.shape[0]):
        node = nodes[k]
        for a in range(3):
            for lane in range(lanes):
                out[a, lane] += share * x[node, a, lane]


@njit(cache=True, inline="always")
def submerged(z: float, surface_z: float) -> float:
    """1 below the water surface, 0 above it (for a point: a fin)."""
    return 1.0 if z < surface_z else 0.0


@njit(cache=True, inline="always")
def wet_fraction(low: float, high: float, surface_z: float) -> float:
    """The share of a face spanning heights [low, high] m that is under the surface: from 0
    (all above) to 1 (all below), linear in between (a flat face's wetted area, nearly)."""
    return min(max((surface_z - low) / max(high - low, 1e-9), 0.0), 1.0)


@njit(cache=True, inline="always")
def sphere_submerged(z: float, radius: float, surface_z: float) -> float:
    """The submerged share of a sphere of ``radius`` m centred at height ``z``: the cap's
    volume, s^2 (3 - 2 s) with s = (surface_z - z + radius) / (2 radius) clipped to [0, 1]
    (smooth, so a floating body settles instead of chattering at the surface)."""
    s = min(max((surface_z - z + radius) / (2.0 * radius), 0.0), 1.0)
    return s * s * (3.0 - 2.0 * s)


@njit(cache=True, inline="always")
def limited_drag(rate: float, normal_speed: float, mass: float, dt: float) -> float:
    """Magnitude ``rate * normal_speed`` (rate = kappa A |w|, kg/s) limited so that one step
    cannot reverse the motion it opposes, N."""
    return rate * normal_speed / (1.0 + dt * rate / mass)


@njit(cache=True, inline="always")
def _element_force(x, v, i, j, rest, c, gamma, b) -> tuple[float, float, float]:
    """Lane b's Voigt force on an element's node i (N; node j gets its opposite); ``rest``
    the element's rest lengths (L,), m."""
    r0, r1, r2 = x[j, 0, b] - x[i, 0, b], x[j, 1, b] - x[i, 1, b], x[j, 2, b] - x[i, 2, b]
    length = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    inverse = 1.0 / length
    rate = ((v[j, 0, b] - v[i, 0, b]) * r0 + (v[j, 1, b] - v[i, 1, b]) * r1
            + (v[j, 2, b] - v[i, 2, b]) * r2) * inverse
    scale = (c * (length - rest[b]) + gamma * rate) * inverse
    return scale * r0, scale * r1, scale * r2


@njit(**FAST)
def add_element_forces(x, v, elements, stiffness, damping, rest, f, one_body=BATCH) -> None:
    """Voigt elements: ``(c (|r| - l) + gamma d|r|/dt) r/|r|`` on node i, the opposite on node j,
    with ``r = x_j - x_i``; ``rest`` (E, L) the current rest lengths, m. ``one_body``: BATCH
    or ONE_BODY (:func:`lane_count`), as in every kernel here.

    In a batch, each element's force is computed for every lane first, then added to its two
    nodes (:func:`_add_element_forces_lanes`). One body adds them as it goes. The same numbers
    either way."""
    if one_body is None:
        _add_element_forces_lanes(x, v, elements, stiffness, damping, rest, f)
        return
    for e in range(elements.shape[0]):
        i, j = elements[e, 0], elements[e, 1]
        f0, f1, f2 = _element_force(x, v, i, j, rest[e], stiffness[e], damping[e], 0)
        f[i, 0, 0] += f0
        f[i, 1, 0] += f1
        f[i, 2, 0] += f2
        f[j, 0, 0] -= f0
        f[j, 1, 0] -= f1
        f[j, 2, 0] -= f2


@njit(**FAST)
def _add_element_forces_lanes(x, v, elements, stiffness, damping, rest, f) -> None:
    """:func:`add_element_forces` over the lanes: a lane loop that reads x and v and writes f
    runs in SIMD only if f cannot overlap what it reads, which the compiler cannot tell, so
    the forces go through a scratch row, and the loop that computes them runs in SIMD."""
    lanes = x.shape[2]
    force = np.empty((3, lanes))
    for e in range(elements.shape[0]):
        i, j = elements[e, 0], elements[e, 1]
        c, gamma = stiffness[e], damping[e]
        for b in range(lanes):
            force[0, b], force[1, b], force[2, b] = _element_force(x, v, i, j, rest[e], c,
                                                                   gamma, b)
        for a in range(3):
            for b in range(lanes):
                f[i, a, b] += force[a, b]
        for a in range(3):
            for b in range(lanes):
                f[j, a, b] -= force[a, b]


@njit(**FAST)
def _face_forces_into(x, v, faces, weights, face_mass, water, dt, g, one_body, limit_dt) -> None:
    """g (F, 4, L): the force the water exerts on each face of every body, negated (rows 0-2),
    and the impact momentum of the share of the face going under the surface this step (row
    3: the splash, :func:`add_face_forces`). The lane
    loop is branch-free (blends and selects) and calls no function that takes an array, so it
    runs in SIMD across the bodies."""
    kappa_water, kappa_air = water[FLUID_COEFFICIENT], water[AIR_COEFFICIENT]
    friction_water, friction_air = water[FRICTION_COEFFICIENT], water[AIR_FRICTION_COEFFICIENT]
    crossflow, surface_z, density = water[CROSSFLOW], water[SURFACE_Z], water[DENSITY]
    c0, c1, c2 = water[CURRENT_X], water[CURRENT_Y], water[CURRENT_Z]
    cross = 1.0 if crossflow else 0.0
    for k in range(faces.shape[0]):
        _one_face_into(x, v, faces[k, 0], faces[k, 1], faces[k, 2], faces[k, 3], weights[k, 0],
                       weights[k, 1], weights[k, 2], weights[k, 3], face_mass[k], kappa_water,
                       kappa_air, friction_water, friction_air, cross, surface_z, c0, c1, c2,
                       density, dt, g[k], one_body, limit_dt)


@njit(inline="always", **FAST)
def _one_face_into(x, v, a, b, c, d, s0, s1, s2, s3, mass, kappa_water, kappa_air,
                   friction_water, friction_air, cross, surface_z, c0, c1, c2, density, dt,
                   g, one_body, limit_dt) -> None:
    for lane in range(lane_count(x, one_body)):
        p0, p1, p2 = (x[c, 0, lane] - x[a, 0, lane], x[c, 1, lane] - x[a, 1, lane],
                      x[c, 2, lane] - x[a, 2, lane])
        q0, q1, q2 = (x[d, 0, lane] - x[b, 0, lane], x[d, 1, lane] - x[b, 1, lane],
                      x[d, 2, lane] - x[b, 2, lane])
        n0, n1, n2 = 0.5 * (p1 * q2 - p2 * q1), 0.5 * (p2 * q0 - p0 * q2), 0.5 * (p0 * q1 - p1 * q0)
        area = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        inverse = 1.0 / max(area, 1e-300)
        n0, n1, n2 = n0 * inverse, n1 * inverse, n2 * inverse
        w0 = s0 * v[a, 0, lane] + s1 * v[b, 0, lane] + s2 * v[c, 0, lane] + s3 * v[d, 0, lane] - c0
        w1 = s0 * v[a, 1, lane] + s1 * v[b, 1, lane] + s2 * v[c, 1, lane] + s3 * v[d, 1, lane] - c1
        w2 = s0 * v[a, 2, lane] + s1 * v[b, 2, lane] + s2 * v[c, 2, lane] + s3 * v[d, 2, lane] - c2
        za, zb, zc, zd = x[a, 2, lane], x[b, 2, lane], x[c, 2, lane], x[d, 2, lane]
        low, high = min(min(za, zb), min(zc, zd)), max(max(za, zb), max(zc, zd))
        wet = wet_fraction(low, high, surface_z)
        normal_speed = n0 * w0 + n1 * w1 + n2 * w2
        t0, t1, t2 = w0 - normal_speed * n0, w1 - normal_speed * n1, w2 - normal_speed * n2
        tangential = np.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
        pushing = max(normal_speed, 0.0)
        along = cross * pushing + (1.0 - cross) * np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
        kappa = kappa_air + (kappa_water - kappa_air) * wet
        normal_force = limited_drag(kappa * area * along, pushing, mass, limit_dt)
        kappa_f = friction_air + (friction_water - friction_air) * wet
        friction = limited_drag(kappa_f * area * tangential, 1.0, mass, limit_dt)
        g[0, lane] = normal_force * n0 + friction * t0
        g[1, lane] = normal_force * n1 + friction * t1
        g[2, lane] = normal_force * n2 + friction * t2
        if surface_z < np.inf:  # the splash (none without a surface: not computed)
            drop = dt * min(w2 + c2, 0.0)  # how far the face goes down in the step
            wetting = wet_fraction(low + drop, high + drop, surface_z) - wet
            g[3, lane] = density * area * np.sqrt(area) * pushing * wetting
        else:
            g[3, lane] = 0.0


@njit(**FAST)
def add_face_forces(x, v, faces, weights, face_mass, water, dt, f, g, splash,
                    one_body=BATCH, limit_dt=-1.0) -> None:
    """Reaction force and skin friction on every face (``faces`` (F, 4), ``weights`` (F, 4)).

    ``limit_dt`` s (default: ``dt``) is the step the drag's limiter assumes
    (:func:`limited_drag`); 0 turns the limiter off (the implicit step puts the drag on its
    left side instead, :mod:`animat.envs.physics.implicit`).

    ``splash`` (L,) accumulates the splash of each body, kg m/s: the impact momentum of the
    faces entering the water, von Karman's slamming model for a plate, the added mass of a
    face (``rho A^(3/2)``) times its speed into the water along its normal (``n.w``, when
    pushing), for the share of the face that goes under the surface in the step. A flat belly
    flop meets the water with its faces' normals along the motion and scores high; a clean
    dive goes in edge-on and scores low.

    A face's area vector is half the cross product of its diagonals (exact for a planar quad
    and for a triangle given as a quad with a repeated corner); its velocity and height are the
    weighted means of its corners'. ``water`` is
    :meth:`animat.envs.physics.system.Water.as_args` (``System.kernel_args.water``). The forces
    go into ``g`` (F, 3, L) work space in SIMD passes over the bodies
    (:func:`_face_forces_into`), then are shared out among each face's corners by
    ``weights``."""
    lanes = lane_count(x, one_body)
    _face_forces_into(x, v, faces, weights, face_mass, water, dt, g, one_body,
                      dt if limit_dt < 0.0 else limit_dt)
    for k in range(faces.shape[0]):
        for lane in range(lanes):
            splash[lane] += g[k, 3, lane]
    for k in range(faces.shape[0]):
        a, b, c, d = faces[k, 0], faces[k, 1], faces[k, 2], faces[k, 3]
        s0, s1, s2, s3 = weights[k, 0], weights[k, 1], weights[k, 2], weights[k, 3]
        for lane in range(lanes):
            g0, g1, g2 = g[k, 0, lane], g[k, 1, lane], g[k, 2, lane]
            f[a, 0, lane] -= s0 * g0
            f[a, 1, lane] -= s0 * g1
            f[a, 2, lane] -= s0 * g2
            f[b, 0, lane] -= s1 * g0
            f[b, 1, lane] -= s1 * g1
            f[b, 2, lane] -= s1 * g2
            f[c, 0, lane] -= s2 * g0
            f[c, 1, lane] -= s2 * g1
            f[c, 2, lane] -= s2 * g2
            f[d, 0, lane] -= s3 * g0
            f[d, 1, lane] -= s3 * g1
            f[d, 2, lane] -= s3 * g2


@njit(cache=True, inline="always")
def compressed(volume: float, depth: float, pressure_head: float) -> float:
    """A gas volume (m^3 at the surface) at ``depth`` m, by Boyle's law: ``V / (1 + d / H)``
    with ``H = p_air / (rho g)`` the pressure head of the air (10.3 m of water)."""
    return volume / (1.0 + max(depth, 0.0) / pressure_head)


@njit(cache=True, inline="always")
def sphere_radius(volume: float) -> float:
    """The radius of a sphere of ``volume`` m^3, m (at least 1e-6 m)."""
    return max((0.75 * volume / np.pi) ** (1.0 / 3.0), 1e-6)


@njit(cache=True)
def sphere_radii(volumes: np.ndarray) -> np.ndarray:
    """(N,) :func:`sphere_radius` of each of ``volumes`` (N,) m^3: the nodes' radii, computed
    once for :func:`add_gravity_buoyancy` rather than in every step (a cube root a node)."""
    radii = np.empty(volumes.shape[0])
    for i in range(volumes.shape[0]):
        radii[i] = sphere_radius(volumes[i])
    return radii


@njit(**FAST)
def add_gravity_buoyancy(x, masses, volumes, radii, lungs, density, gravity, surface_z,
                         air_pressure, f, one_body=BATCH) -> None:
    """Weight ``-m g`` on every node and buoyancy ``rho g V`` on the submerged share of every
    node's volume (a sphere of that volume about the node: :func:`sphere_submerged`; ``radii``
    (N,) the spheres' radii, :func:`sphere_radii` of ``volumes``), along z. A node's lung volume
    ``lungs`` (m^3 at the surface) adds to its volume, compressed with depth
    (:func:`compressed`), and to its sphere; without a surface there is no depth and lungs keep
    their surface volume."""
    head = air_pressure / max(density * gravity, 1e-300)
    lanes = lane_count(x, one_body)
    for i in range(x.shape[0]):
        weight, lift = gravity * masses[i], gravity * density * volumes[i]
        if surface_z == np.inf:  # no surface: all under (no cube root per step; as it always was)
            for b in range(lanes):
                f[i, 2, b] += (lift + gravity * density * lungs[i]) * submerged(
                    x[i, 2, b], surface_z) - weight
            continue
        if lungs[i] == 0.0:
            radius = radii[i]
            for b in range(lanes):
                f[i, 2, b] += lift * sphere_submerged(x[i, 2, b], radius, surface_z) - weight
            continue
        for b in range(lanes):
            gas = compressed(lungs[i], surface_z - x[i, 2, b], head)
            radius = sphere_radius(volumes[i] + gas)
            f[i, 2, b] += gravity * density * (volumes[i] + gas) * sphere_submerged(
                x[i, 2, b], radius, surface_z) - weight
