"""A linearised implicit step for a chunk of mass-spring bodies (``System(integrator="implicit")``).

The theta-method (theta = 1, the default, is backward Euler: the spec's "damping and stiffness on
the left side"; Baraff and Witkin, "Large steps in cloth simulation", 1998), one step of size h::

    M_a dv = h (f_E(x_t, v_t) + f_D(v_t) + f_X(x, v)),
    x_t = x + theta h (v + theta dv),   v_t = v + theta dv,
    v' = v + dv,   x' = x + h (v + theta dv),

with M_a the nodes' masses plus the reactive water's added mass (a section node's ``c e e'``,
:mod:`animat.envs.physics.reactive`), f_E the Voigt elements, f_D the faces' normal drag and f_X
the rest (skin friction, fins, gravity and buoyancy, the reactive water's other terms), explicit.
f_E is linearised about the predicted point ``x_p = x + theta h v``, ``v_p = v`` (one Newton
step from there), f_D about (x, v) by its velocity::

    (M_a + theta h (D_E + D_D) + theta^2 h^2 K_E) dv = h (f_E(x_p, v) + f_D(x, v) + f_X),

K_E = -df_E/dx, D_E = -df_E/dv, D_D = -df_D/dv. Why about x_p rather than x: the stiff elements
turn during a step, and a linearisation about where they were pulls every turning element off
by about ``k l (omega h)^2``, which damps the stroke. Why the drag on the left side: the explicit
step's limiter (:func:`animat.envs.physics.forces.limited_drag`) assumes a face's own mass
takes its drag, which at large steps cuts the tail's thrust; here the whole body takes it.
Why theta = 1 by default: a smaller theta damps the stroke less, but leaves the stiff modes
ringing from step to step, and their rotation then blows the body up at large steps
(``docs/integrators.md`` has the measurements).

An element i-j with unit direction r, length l, rest length l0, stiffness k and damping g has
``K_e = k r r' + t (I - r r')`` with ``t = max(k (l - l0) / l, 0)`` (the tension's geometric
stiffness, kept only under tension so that the matrix stays positive definite) and
``D_e = g r r'`` (the damper's dependence on the positions is left out: it is not symmetric).
A face with unit normal n, area A, velocity w into the water has ``D_face = c n n'`` shared
among its corners by their weights, ``c = 2 kappa A (n.w)`` (the cross-flow law's derivative;
the paper's law, ``kappa A (|w| + (n.w)^2 / |w|)``). The muscles' rest lengths are those at
``t + theta h``. The linearisation is not rotation invariant, so the elements' share of dv is
solved apart and held to what central forces do (:func:`keep_angular_momentum`): momentum and
angular momentum are kept to round-off in a vacuum, as the explicit step keeps them.

The matrix is symmetric, positive definite and banded (the nodes' order along the body gives a
half-bandwidth ``3 max|i - j| + 2`` over the elements and faces,
:func:`animat.envs.physics.system.half_bandwidth`: 23 for the fish and the dolphin), so it is
factored by a banded Cholesky (Tu factored it LDL'), every lane of a chunk in the same loops
(bodies innermost, as the force kernels are): about ``3N W^2 / 2`` multiply-adds a step.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .forces import BATCH, FAST, lane_count, wet_fraction
from .system import (
    AIR_COEFFICIENT,
    CROSSFLOW,
    CURRENT_X,
    CURRENT_Y,
    CURRENT_Z,
    FLUID_COEFFICIENT,
    SURFACE_Z,
)


@njit(**FAST)
def assemble_elements(x, v, elements, stiffness, damping, rest, hd, hk, f, band, blocks,
                      one_body=BATCH) -> None:
    """Add each element's force to ``f`` (N, 3, L) and ``hd D_e + hk K_e`` to ``band``
    (3N, W + 1, L; ``band[r, k]`` is the matrix entry (r, r - k), its lower band); ``rest``
    (E, L) the rest lengths, m; ``hd`` s and ``hk`` s^2 the weights (theta h, theta^2 h^2).
    Each element's block ``alpha r r' + beta I`` goes to ``blocks`` (E, 5, L): r (rows 0-2),
    alpha and beta (rows 3, 4), for :func:`keep_angular_momentum`."""
    lanes = lane_count(x, one_body)
    for e in range(elements.shape[0]):
        i, j = min(elements[e, 0], elements[e, 1]), max(elements[e, 0], elements[e, 1])
        k, g = stiffness[e], damping[e]
        for b in range(lanes):
            r0, r1, r2 = x[j, 0, b] - x[i, 0, b], x[j, 1, b] - x[i, 1, b], x[j, 2, b] - x[i, 2, b]
            length = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
            inverse = 1.0 / length
            r0, r1, r2 = r0 * inverse, r1 * inverse, r2 * inverse
            along = ((v[j, 0, b] - v[i, 0, b]) * r0 + (v[j, 1, b] - v[i, 1, b]) * r1
                     + (v[j, 2, b] - v[i, 2, b]) * r2)
            stretch = k * (length - rest[e, b])
            scale = stretch + g * along
            f[i, 0, b] += scale * r0
            f[i, 1, b] += scale * r1
            f[i, 2, b] += scale * r2
            f[j, 0, b] -= scale * r0
            f[j, 1, b] -= scale * r1
            f[j, 2, b] -= scale * r2
            tension = hk * max(stretch * inverse, 0.0)
            alpha = hd * g + hk * k - tension
            blocks[e, 0, b], blocks[e, 1, b], blocks[e, 2, b] = r0, r1, r2
            blocks[e, 3, b], blocks[e, 4, b] = alpha, tension
            _add_pair(band, 3 * i, 3 * j, alpha, r0, r1, r2, tension, b)


@njit(cache=True, inline="always")
def _add_pair(band, ri, rj, alpha, r0, r1, r2, diagonal, b) -> None:
    """Add the block ``B = alpha r r' + diagonal I`` of a pair of nodes (rows ri < rj) to lane
    b of ``band``: +B on both diagonal blocks, -B on the off-diagonal one."""
    r = (r0, r1, r2)
    for p in range(3):
        for q in range(3):
            block = alpha * r[p] * r[q] + (diagonal if p == q else 0.0)
            band[rj + p, rj - ri + p - q, b] -= block
            if q <= p:
                band[ri + p, p - q, b] += block
                band[rj + p, p - q, b] += block


@njit(**FAST)
def add_face_damping(x, v, faces, weights, water, hd, band, terms, one_body=BATCH) -> None:
    """Add ``hd D_face`` of every face (``faces``, ``weights`` (F, 4)) to ``band``: the normal
    drag's derivative by the face's velocity, ``c n n'`` (the module's), shared among the
    corners by ``s_p s_q``; ``water`` :meth:`animat.envs.physics.system.Water.as_args`. Each
    face's n and ``hd c`` (kg) go to ``terms`` (F, 4, L) (rows 0-2 and 3)."""
    lanes = lane_count(x, one_body)
    kappa_water, kappa_air = water[FLUID_COEFFICIENT], water[AIR_COEFFICIENT]
    crossflow, surface_z = water[CROSSFLOW] > 0.0, water[SURFACE_Z]
    c0, c1, c2 = water[CURRENT_X], water[CURRENT_Y], water[CURRENT_Z]
    for k in range(faces.shape[0]):
        a, bb, cc, d = faces[k, 0], faces[k, 1], faces[k, 2], faces[k, 3]
        for lane in range(lanes):
            p0, p1, p2 = (x[cc, 0, lane] - x[a, 0, lane], x[cc, 1, lane] - x[a, 1, lane],
                          x[cc, 2, lane] - x[a, 2, lane])
            q0, q1, q2 = (x[d, 0, lane] - x[bb, 0, lane], x[d, 1, lane] - x[bb, 1, lane],
                          x[d, 2, lane] - x[bb, 2, lane])
            n0 = 0.5 * (p1 * q2 - p2 * q1)
            n1 = 0.5 * (p2 * q0 - p0 * q2)
            n2 = 0.5 * (p0 * q1 - p1 * q0)
            area = np.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
            inverse = 1.0 / max(area, 1e-300)
            n0, n1, n2 = n0 * inverse, n1 * inverse, n2 * inverse
            w0, w1, w2 = -c0, -c1, -c2
            low, high = np.inf, -np.inf
            for m in range(4):
                node, s = faces[k, m], weights[k, m]
                w0 += s * v[node, 0, lane]
                w1 += s * v[node, 1, lane]
                w2 += s * v[node, 2, lane]
                low, high = min(low, x[node, 2, lane]), max(high, x[node, 2, lane])
            kappa = kappa_air + (kappa_water - kappa_air) * wet_fraction(low, high, surface_z)
            pushing = max(n0 * w0 + n1 * w1 + n2 * w2, 0.0)
            if crossflow:
                c = 2.0 * kappa * area * pushing
            else:
                speed = np.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
                c = kappa * area * (speed + pushing * pushing / max(speed, 1e-300))
            terms[k, 0, lane], terms[k, 1, lane], terms[k, 2, lane] = n0, n1, n2
            terms[k, 3, lane] = hd * c
            if c == 0.0:
                continue
            for m in range(4):
                for o in range(4):
                    i, j = faces[k, m], faces[k, o]
                    if i > j:
                        continue
                    weight = hd * c * weights[k, m] * weights[k, o]
                    if weight == 0.0:
                        continue
                    if i == j:
                        _add_own(band, 3 * i, weight, n0, n1, n2, lane)
                    else:
                        _add_cross(band, 3 * i, 3 * j, weight, n0, n1, n2, lane)


@njit(cache=True, inline="always")
def _add_own(band, ri, weight, n0, n1, n2, b) -> None:
    """Add ``weight n n'`` to a node's diagonal block (rows ri..ri+2), lane b."""
    n = (n0, n1, n2)
    for p in range(3):
        for q in range(p + 1):
            band[ri + p, p - q, b] += weight * n[p] * n[q]


@njit(cache=True, inline="always")
def _add_cross(band, ri, rj, weight, n0, n1, n2, b) -> None:
    """Add ``weight n n'`` to the off-diagonal block of nodes ri < rj (and, by symmetry, its
    transpose), lane b."""
    n = (n0, n1, n2)
    for p in range(3):
        for q in range(3):
            band[rj + p, rj - ri + p - q, b] += weight * n[p] * n[q]


@njit(**FAST)
def add_masses(masses, nodes, weights, sections, band, one_body=BATCH) -> None:
    """Add the nodes' masses (N,) kg to ``band``'s diagonal and, with ``sections`` holding
    rows (the reactive water's section terms, :func:`animat.envs.physics.reactive.
    add_reactive_forces`), each section node's share of its section's added mass, ``c e e'``
    with ``c = w l m``, kg."""
    lanes = lane_count(band, one_body)
    for i in range(masses.shape[0]):
        for a in range(3):
            for b in range(lanes):
                band[3 * i + a, 0, b] += masses[i]
    for j in range(sections.shape[0]):
        for m in range(nodes.shape[1]):
            node, share = nodes[j, m], weights[j, m]
            if share == 0.0:
                continue
            for b in range(lanes):
                c = share * sections[j, 3, b]
                for p in range(3):
                    for q in range(p + 1):
                        band[3 * node + p, p - q, b] += c * sections[j, p, b] * sections[j, q, b]


@njit(**FAST)
def cholesky_band(band, one_body=BATCH) -> None:
    """Factor each lane's banded matrix in place into L (``band`` (n, W + 1, L) as
    :func:`assemble_elements` fills it), its diagonal stored inverted (1 / L_jj)."""
    n, width, lanes = band.shape[0], band.shape[1] - 1, lane_count(band, one_body)
    for j in range(n):
        low = max(0, j - width)
        for k in range(low, j):
            for b in range(lanes):
                band[j, 0, b] -= band[j, j - k, b] * band[j, j - k, b]
        for b in range(lanes):
            band[j, 0, b] = 1.0 / np.sqrt(band[j, 0, b])
        for i in range(j + 1, min(n, j + width + 1)):
            for k in range(max(0, i - width), j):
                for b in range(lanes):
                    band[i, i - j, b] -= band[i, i - k, b] * band[j, j - k, b]
            for b in range(lanes):
                band[i, i - j, b] *= band[j, 0, b]


@njit(**FAST)
def solve_band(band, rhs, one_body=BATCH) -> None:
    """Solve L L' z = rhs in place (``rhs`` (n, L)) with :func:`cholesky_band`'s factor."""
    n, width, lanes = band.shape[0], band.shape[1] - 1, lane_count(band, one_body)
    for i in range(n):
        for k in range(max(0, i - width), i):
            for b in range(lanes):
                rhs[i, b] -= band[i, i - k, b] * rhs[k, b]
        for b in range(lanes):
            rhs[i, b] *= band[i, 0, b]
    for i in range(n - 1, -1, -1):
        for b in range(lanes):
            rhs[i, b] *= band[i, 0, b]
        for k in range(max(0, i - width), i):
            for b in range(lanes):
                rhs[k, b] -= band[i, i - k, b] * rhs[i, b]


@njit(**FAST)
def implicit_step(x, v, f_x, elements, stiffness, damping, rest, masses, nodes, weights,
                  sections, faces, face_weights, water, h, theta, band, rhs, xp, fe, blocks,
                  terms, one_body=BATCH) -> None:
    """One step (the module's) of x, v (N, 3, L) in place, with ``f_x`` (N, 3, L) the explicit
    forces at (x, v), N; ``rest`` (E, L) the rest lengths at t + theta h; ``masses`` (N,) kg;
    ``nodes``, ``weights`` (J, K) the sections and ``sections`` (J, >= 4, L) their normals and
    added masses (:func:`add_masses`; no rows: no added mass); ``faces``, ``face_weights``
    (F, 4); ``water`` the packed water; h s; work space ``band`` (3N, W + 1, L), ``rhs``
    (2, 3N, L), ``xp`` and ``fe`` (N, 3, L), ``blocks`` (E, 5, L), ``terms`` (F, 4, L).

    The elements' share of dv and the rest's are solved apart (one factor, two solves), so that
    :func:`keep_angular_momentum` can take the linearisation's torque out of the elements'."""
    lanes, n = lane_count(x, one_body), x.shape[0]
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                xp[i, a, b] = x[i, a, b] + theta * h * v[i, a, b]
                fe[i, a, b] = 0.0
    band[:] = 0.0
    assemble_elements(xp, v, elements, stiffness, damping, rest, theta * h, theta * theta * h * h,
                      fe, band, blocks, one_body)
    add_face_damping(x, v, faces, face_weights, water, theta * h, band, terms, one_body)
    add_masses(masses, nodes, weights, sections, band, one_body)
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                rhs[0, 3 * i + a, b] = h * fe[i, a, b]
                rhs[1, 3 * i + a, b] = h * f_x[i, a, b]
    cholesky_band(band, one_body)
    solve_band(band, rhs[0], one_body)
    solve_band(band, rhs[1], one_body)
    keep_angular_momentum(x, v, fe, masses, nodes, weights, sections, elements, blocks, faces,
                          face_weights, terms, h, theta, rhs[0], xp, one_body)
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                dv = rhs[0, 3 * i + a, b] + rhs[1, 3 * i + a, b]
                x[i, a, b] += h * (v[i, a, b] + theta * dv)
                v[i, a, b] += dv


@njit(**FAST)
def keep_angular_momentum(x, v, fe, masses, nodes, weights, sections, elements, blocks, faces,
                          face_weights, terms, h, theta, dv, scratch, one_body=BATCH) -> None:
    """Take out of the elements' share of the step's velocity change, ``dv`` (3N, L), the
    angular momentum the linearisation gives it, as a rigid motion ``a + omega x r`` of the
    body with the water it carries and the drag on its faces (M_i the node's mass with its
    added mass, ``terms`` the faces' ``theta h c n n'`` as :func:`add_face_damping` left them:
    the drag takes its share of the change, as it does of every change the solve makes;
    r_i = x_i + (1 - theta) h v_i, the lever the step's update gives).

    The solve gives ``M dv = h f_E(x_p) - A_E dv - (the drag's response)``, A_E the elements'
    part of the matrix (``blocks``, as :func:`assemble_elements` left them). Central forces
    have no torque about x_p, so the elements' torque about r is ``h^2 (1 - 2 theta) sum v x
    f_E`` (``fe`` (N, 3, L) their forces) plus that of ``-A_E dv``: both are the
    linearisation's, and go. The drag's response stays. In a vacuum the step then keeps
    momentum and angular momentum to round-off, as the explicit one does. ``scratch`` (N, 3, L)
    work space."""
    lanes, n = lane_count(x, one_body), x.shape[0]
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                scratch[i, a, b] = x[i, a, b] + (1.0 - theta) * h * v[i, a, b]
    system, columns = np.empty((6, 7)), np.empty((3, 7))  # work space, reused node to node
    lever = h * h * (1.0 - 2.0 * theta)
    for b in range(lanes):
        system[:] = 0.0
        for i in range(n):
            r = (scratch[i, 0, b], scratch[i, 1, b], scratch[i, 2, b])
            _add_node_rows(system, columns, r, masses[i], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            v0, v1, v2 = v[i, 0, b], v[i, 1, b], v[i, 2, b]
            f0, f1, f2 = fe[i, 0, b], fe[i, 1, b], fe[i, 2, b]
            system[3, 6] += lever * (v1 * f2 - v2 * f1)
            system[4, 6] += lever * (v2 * f0 - v0 * f2)
            system[5, 6] += lever * (v0 * f1 - v1 * f0)
        for j in range(sections.shape[0]):
            for m in range(nodes.shape[1]):
                node, share = nodes[j, m], weights[j, m]
                if share == 0.0:
                    continue
                r = (scratch[node, 0, b], scratch[node, 1, b], scratch[node, 2, b])
                _add_node_rows(system, columns, r, 0.0, share * sections[j, 3, b],
                               sections[j, 0, b], sections[j, 1, b], sections[j, 2, b], 0.0,
                               0.0, 0.0)
        for k in range(faces.shape[0]):
            if terms[k, 3, b] == 0.0:
                continue
            c0, c1, c2 = 0.0, 0.0, 0.0  # the face's centre by its weights
            for m in range(4):
                node, share = faces[k, m], face_weights[k, m]
                c0 += share * scratch[node, 0, b]
                c1 += share * scratch[node, 1, b]
                c2 += share * scratch[node, 2, b]
            _add_node_rows(system, columns, (c0, c1, c2), 0.0, terms[k, 3, b], terms[k, 0, b],
                           terms[k, 1, b], terms[k, 2, b], 0.0, 0.0, 0.0)
        for e in range(elements.shape[0]):
            i, j = min(elements[e, 0], elements[e, 1]), max(elements[e, 0], elements[e, 1])
            d0 = dv[3 * j, b] - dv[3 * i, b]
            d1 = dv[3 * j + 1, b] - dv[3 * i + 1, b]
            d2 = dv[3 * j + 2, b] - dv[3 * i + 2, b]
            r0, r1, r2 = blocks[e, 0, b], blocks[e, 1, b], blocks[e, 2, b]
            axial = blocks[e, 3, b] * (r0 * d0 + r1 * d1 + r2 * d2)
            p0 = axial * r0 + blocks[e, 4, b] * d0  # -A_E dv on node i; node j gets -p
            p1 = axial * r1 + blocks[e, 4, b] * d1
            p2 = axial * r2 + blocks[e, 4, b] * d2
            l0 = scratch[i, 0, b] - scratch[j, 0, b]
            l1 = scratch[i, 1, b] - scratch[j, 1, b]
            l2 = scratch[i, 2, b] - scratch[j, 2, b]
            system[3, 6] += l1 * p2 - l2 * p1
            system[4, 6] += l2 * p0 - l0 * p2
            system[5, 6] += l0 * p1 - l1 * p0
        _solve6(system)
        for i in range(n):
            r0, r1, r2 = scratch[i, 0, b], scratch[i, 1, b], scratch[i, 2, b]
            w0, w1, w2 = system[3, 6], system[4, 6], system[5, 6]
            dv[3 * i, b] -= system[0, 6] + w1 * r2 - w2 * r1
            dv[3 * i + 1, b] -= system[1, 6] + w2 * r0 - w0 * r2
            dv[3 * i + 2, b] -= system[2, 6] + w0 * r1 - w1 * r0


@njit(cache=True, inline="always")
def _add_node_rows(system, columns, r, mass, added, e0, e1, e2, d0, d1, d2) -> None:
    """Add a node's terms to the 6 x 7 system [J' M J | J' M d] of
    :func:`keep_angular_momentum`, J = [I, -[r]x] (so that J (a, omega) = a + omega x r),
    M = mass I + added e e', d the node's dv; ``columns`` (3, 7) work space."""
    e = (e0, e1, e2)
    # J's six columns and d, each a 3-vector: a's unit vectors, omega's e_k x r
    for a in range(3):
        for k in range(3):
            columns[a, k] = 1.0 if a == k else 0.0
    columns[0, 3], columns[1, 3], columns[2, 3] = 0.0, -r[2], r[1]
    columns[0, 4], columns[1, 4], columns[2, 4] = r[2], 0.0, -r[0]
    columns[0, 5], columns[1, 5], columns[2, 5] = -r[1], r[0], 0.0
    columns[0, 6], columns[1, 6], columns[2, 6] = d0, d1, d2
    for q in range(7):
        along = added * (e[0] * columns[0, q] + e[1] * columns[1, q] + e[2] * columns[2, q])
        for p in range(6):
            total = 0.0
            for a in range(3):
                total += columns[a, p] * (mass * columns[a, q] + along * e[a])
            system[p, q] += total


@njit(cache=True)
def _solve6(system) -> None:
    """Solve the 6 x 6 symmetric positive definite system [A | y] in place by Gaussian
    elimination; the solution in column 6."""
    for k in range(6):
        pivot = system[k, k]
        for i in range(k + 1, 6):
            factor = system[i, k] / pivot
            for j in range(k, 7):
                system[i, j] -= factor * system[k, j]
    for k in range(5, -1, -1):
        total = system[k, 6]
        for j in range(k + 1, 6):
            total -= system[k, j] * system[j, 6]
        system[k, 6] = total / system[k, k]
