"""A beach ball on a support: a light sphere with contact against the body's faces (compiled).

The ball is a rigid sphere (radius R, mass m) under gravity, buoyancy on its submerged cap
(:func:`animat.envs.physics.forces.sphere_submerged`), quadratic drag (``0.5 rho C_d pi R^2
|v| v``, ``rho`` blended between air and water by the submerged share), the added mass of
its submerged share (``0.5 rho V``: a light ball in water is not a light ball in air), and,
floating, a linear damping of its bobbing for the waves it radiates (damping ratio
:data:`HEAVE_DAMPING` of the waterline's stiffness ``rho g pi R^2``). It
starts at rest on a support, a flat disc whose top holds it up by a penalty contact.

Ball and body meet by penalty contact at one point: of all the body's faces, each split into
two triangles, the surface point nearest the ball's centre; where the ball goes into it by
``d``, the force ``k d + c max(-v_n, 0)`` pushes the ball out along the normal and, equal and
opposite, that triangle's corners in, shared by the barycentric weights of the contact point
(so that momentum is conserved). Contact is
frictionless. Each contact's impulse is added to the part of the body the face belongs to
(``face_parts``: 0 body, 1 nose, 2 tail), so that which part touched the ball is known.

Arrays: ``x, v`` (B, N, 3) the bodies' nodes; ``ball`` (B, 6) position and velocity;
``touch`` (B, 3) contact impulse per part, N s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from ..checks import check_vector
from .forces import sphere_submerged
from .system import DENSITY, GRAVITY, SURFACE_Z

HEAVE_DAMPING = 0.3  # damping ratio of a floating ball's bobbing (wave radiation), 1
PART_NAMES = ("body", "nose", "tail")


@dataclass(frozen=True)
class BallParams:
    """A beach ball and its support, SI units.

    Attributes:
        radius: m (a large beach ball: 0.3). mass: kg.
        drag_coefficient: C_d of a sphere (0.47).
        support: (3,) the centre of the support's top disc, world frame, m; the ball starts
            resting on it. support_radius: the disc's radius, m.
        stiffness: contact spring, N/m; damping: contact damper, N s/m (on approach).
    """

    radius: float = 0.3
    mass: float = 0.5
    drag_coefficient: float = 0.47
    support: tuple[float, float, float] = (6.0, 0.0, 1.2)
    support_radius: float = 0.1
    stiffness: float = 2e4
    damping: float = 40.0

    def __post_init__(self) -> None:
        for name in ("radius", "mass", "support_radius", "stiffness"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and np.isfinite(value) and value > 0):
                raise ValueError(f"ball.{name} must be a number > 0, got {value!r}")
        support = check_vector("ball.support (x, y, z)", self.support, 3, -1e4, 1e4, "m")
        object.__setattr__(self, "support", support)

    @property
    def rest(self) -> np.ndarray:
        """(3,) the ball's centre resting on its support (the weight's sag left out), m."""
        return np.array(self.support) + np.array([0.0, 0.0, self.radius])

    def as_args(self) -> np.ndarray:
        """(10,) radius, mass, C_d, support x, y, z, support radius, stiffness, damping, and
        the ball's volume, for :func:`ball_substep`."""
        return np.array([self.radius, self.mass, self.drag_coefficient, *self.support,
                         self.support_radius, self.stiffness, self.damping,
                         4.0 / 3.0 * np.pi * self.radius**3])


@njit(cache=True, inline="always")
def _dot3(a, b) -> float:
    """a . b of two (3,) vectors, written out: Numba's ``@`` calls BLAS (SciPy's), and for three
    numbers the call costs more than the sum."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, inline="always")
def _closest_on_triangle(p, a, b, c):
    """Barycentric weights (wa, wb, wc) of the point of triangle abc closest to p (Ericson,
    Real-Time Collision Detection, 5.1.5)."""
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = _dot3(ab, ap), _dot3(ac, ap)
    if d1 <= 0.0 and d2 <= 0.0:
        return 1.0, 0.0, 0.0
    bp = p - b
    d3, d4 = _dot3(ab, bp), _dot3(ac, bp)
    if d3 >= 0.0 and d4 <= d3:
        return 0.0, 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        return 1.0 - t, t, 0.0
    cp = p - c
    d5, d6 = _dot3(ab, cp), _dot3(ac, cp)
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        return 1.0 - t, 0.0, t
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 0.0, 1.0 - t, t
    denominator = 1.0 / (va + vb + vc)
    wb, wc = vb * denominator, vc * denominator
    return 1.0 - wb - wc, wb, wc


@njit(cache=True)
def _deepest_contact(x, faces, centre, radius):
    """The body's one contact with the ball (x (N, 3) its nodes): the face, its triangle's
    corners (3,) and their barycentric weights (3,) of the surface point nearest the ball's
    centre, over every triangle of every face; face -1 if the ball touches none. One
    contact, so that a ball pressing on an edge or a corner shared by several triangles
    meets one spring, not one per triangle."""
    best, best_face = radius, -1
    corners, best_corners = np.empty(3, dtype=np.int64), np.zeros(3, dtype=np.int64)
    best_weights = np.zeros(3)
    for k in range(faces.shape[0]):
        for half in range(2):
            corners[0], corners[1], corners[2] = faces[k, 0], faces[k, 1 + half], faces[k, 2 + half]
            if corners[0] == corners[1] or corners[1] == corners[2] or corners[0] == corners[2]:
                continue  # the repeated corner of a triangle face
            wa, wb, wc = _closest_on_triangle(centre, x[corners[0]], x[corners[1]],
                                              x[corners[2]])
            gap = centre - (wa * x[corners[0]] + wb * x[corners[1]] + wc * x[corners[2]])
            distance = np.sqrt(_dot3(gap, gap))
            if 1e-9 < distance < best:
                best, best_face = distance, k
                best_corners[:] = corners
                best_weights[0], best_weights[1], best_weights[2] = wa, wb, wc
    return best_face, best_corners, best_weights


@njit(cache=True)
def _contact_force(x, v, masses, corners, weights, centre, velocity, radius, stiffness,
                   damping, dt):
    """Penalty force (3,) N on the ball (centre, velocity (3,)) from its contact point on
    triangle ``corners`` with barycentric ``weights``; the corners' velocities (v (N, 3))
    take the reaction, shared by the weights, so that momentum is conserved."""
    wa, wb, wc = weights[0], weights[1], weights[2]
    point = wa * x[corners[0]] + wb * x[corners[1]] + wc * x[corners[2]]
    gap = centre - point
    distance = np.sqrt(_dot3(gap, gap))
    normal = gap / distance
    surface_velocity = wa * v[corners[0]] + wb * v[corners[1]] + wc * v[corners[2]]
    approach = -_dot3(velocity - surface_velocity, normal)
    magnitude = stiffness * (radius - distance) + damping * max(approach, 0.0)
    force = magnitude * normal
    for corner, weight in ((corners[0], wa), (corners[1], wb), (corners[2], wc)):
        v[corner] -= dt * weight * force / masses[corner]
    return force


@njit(cache=True, error_model="numpy")
def ball_substep(x, v, masses, faces, face_parts, ball, touch, params, water, dt) -> None:
    """One step of ``dt`` s for the ball of every body of the batch, after the bodies' own
    step: contact with the body's faces (``faces`` (F, 4), ``face_parts`` (F,)) and with the
    support, then the ball's own forces, then symplectic Euler for the ball. ``params`` is
    :meth:`BallParams.as_args`, ``water`` :meth:`~envs.physics.system.Water.as_args` (read by
    its slot constants)."""
    radius, mass, cd = params[0], params[1], params[2]
    sx, sy, sz, support_radius = params[3], params[4], params[5], params[6]
    stiffness, damping, volume = params[7], params[8], params[9]
    surface_z, density, gravity = water[SURFACE_Z], water[DENSITY], water[GRAVITY]
    for b in range(x.shape[0]):
        centre, velocity = ball[b, :3].copy(), ball[b, 3:].copy()
        total = np.zeros(3)
        reach, gap = 0.0, 0.0  # broad phase: every face lies within ``reach`` of node 0
        for i in range(x.shape[1]):
            d0, d1, d2 = x[b, i, 0] - x[b, 0, 0], x[b, i, 1] - x[b, 0, 1], x[b, i, 2] - x[b, 0, 2]
            reach = max(reach, d0 * d0 + d1 * d1 + d2 * d2)
        for a in range(3):
            gap += (centre[a] - x[b, 0, a]) ** 2
        if np.sqrt(gap) < np.sqrt(reach) + radius:
            face, corners, weights = _deepest_contact(x[b], faces, centre, radius)
            if face >= 0:
                force = _contact_force(x[b], v[b], masses, corners, weights, centre,
                                       velocity, radius, stiffness, damping, dt)
                total += force
                touch[b, face_parts[face]] += dt * np.sqrt(_dot3(force, force))
        horizontal = np.hypot(centre[0] - sx, centre[1] - sy)
        sink = sz + radius - centre[2]
        if horizontal < support_radius and 0.0 < sink < radius:
            total[2] += stiffness * sink + damping * max(-velocity[2], 0.0)
        wet = sphere_submerged(centre[2], radius, surface_z)
        rho = 1.2 + (density - 1.2) * wet
        speed = np.sqrt(_dot3(velocity, velocity))
        drag = 0.5 * rho * cd * np.pi * radius * radius * speed
        effective = mass + 0.5 * density * volume * wet
        total[2] += gravity * (density * volume * wet - mass)
        if 0.0 < wet < 1.0:  # the waves a bobbing ball makes carry its heave away
            heave = gravity * density * np.pi * radius * radius  # N/m at the waterline
            total[2] -= 2.0 * HEAVE_DAMPING * np.sqrt(heave * effective) * velocity[2]
        velocity = (velocity + dt * total / effective) / (1.0 + dt * drag / effective)
        ball[b, 3:] = velocity
        ball[b, :3] = centre + dt * velocity
