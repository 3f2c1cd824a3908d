"""The water's reactive force: Lighthill's elongated-body theory on a mass-spring body (Numba).

A slender body moving through water carries water with it: each cross-section, moving across
itself at ``w`` relative to the water, holds a momentum ``m w`` per unit length, with
``m = rho pi b^2`` the added mass of a section of half-extent b across the motion (Lighthill
1960, "Note on the swimming of slender fish", J. Fluid Mech. 9). The force the water exerts on
the body is the rate of change of that momentum, and the momentum the body sheds into the wake
at its trailing edge is thrust (Lighthill 1971, "Large-amplitude elongated-body theory of fish
locomotion", Proc. R. Soc. B 179; the local form as in Candelier, Boyer & Leroyer 2011, J. Fluid
Mech. 674). The water here adds this force to the resistive terms of
:mod:`animat.envs.physics.forces` (``Water.model = "reactive"``).

Discretisation. The body's cross-sections (``BodySpec.section_*``: the nose, the rings, the
trailing edge, head to tail) each stand for a length ``l_j`` of the body. Section j's velocity
``v_j`` and centre are its nodes' weighted means; ``r_j`` is the line from the section behind to
the one in front (one-sided at the ends), ``t_j = r_j/|r_j|`` its tangent. The force acts in the
body's plane of undulation only (Lighthill's theory is that of one plane): across the section's
normal ``e_j``, ``U x r_j`` normalised, with ``U`` the section's axis across the plane
(``BodySpec.section_up`` less ``section_down``: for the fish its up at every section, the nodes
of :func:`animat.envs.physics.fins.body_frame_into`, so that ``e_j`` is its left). With
``w = e.v`` (v relative to the water), ``u = t.v`` and the added mass per unit length ``m_j = rho
C_m a_j s`` (``a_j`` the section's area, ``C_m`` ``Water.added_mass``, ``s`` the share of the
section under the surface), the water's momentum per unit length is ``p_j = m_j w e_j`` (N s/m) and
the force on the section

    F_j = -e_j d/dt (l_j m_j w_j) - (Phi_{j+1/2} - Phi_{j-1/2}),  Phi_j = u+ p_j - 1/2 m_j w^2 t_j,

with the momentum flux Phi carried toward the tail by the water streaming past the body
(``u+ = max(u, 0)``: the water streams tailward only past a body moving forward), taken at the
half-way points upwind (``Phi_{j+1/2} = Phi_j``, the section in front's), nothing in front of
the nose, and the last section's own at the trailing edge. Summed over the body the flux terms
telescope to Lighthill's trailing-edge force ``-[u m w e - 1/2 m w^2 t]_tail``: the momentum
shed into the wake, whose mean over a tail beat is the thrust ``1/2 m (<h_t^2> - U^2 <h_x^2>)``
of the small-amplitude theory. The trailing edge's force along the body (its thrust) goes to
the nodes of the last two sections by their masses, as the fin's rays carry it to the tail
stock: the caudal fin's two light tips on their soft edges cannot. Measured, on random
actions, the recalibrated motor controllers and random fin angles: with central half-way
fluxes a FishTurn body's caudal fin grew 5% a step and blew up (one of 256 in 400 steps); with
the thrust on the fin's tips alone the C-start's tail folded (0.4 of rest) within 0.35 s of
its release and blew up. Not held: the swim-MC's full activation at 5 Hz strains the tail
stock to 1.36 of rest. Shared by the last four sections (the last three rings and the fin)
that stroke held 1.19, but random fin angles of +-90 degrees blew a body up (one of 64 in
6 s); shared by the whole body the thrust lost its moment (the C-start 59 degrees, not 72).

The water's momentum changes along the section's normal: the force is ``-e_j d/dt(l_j m_j w_j)``,
and the rotation of the momentum with the normal (``-l m w de/dt``, along the body) is left out
together with the position term of the carried water's Lagrangian (``+dT/dx``, whose moment is
Munk's), the two balancing each other's work in an ideal fluid. So the section's force has the power
``-dT/dt`` with ``T = 1/2 l m w^2`` the carried water's kinetic energy (no energy created or
lost by it), and the caudal fin is not driven along the body by its own spin. Measured: with
``-l m w de/dt`` kept, random full-range actions strained the tail's elements to 1.45-1.5 of
rest and blew a body up (NaN) within 20 s (16 bodies, 25 s each), the fin's term alone doing
it; with ``+dT/dx`` as well the fish yawed +-45 degrees at every beat instead of +-12.

The time derivative splits in two. ``-l_j m_j e e' dv_j/dt`` is inertia: it goes to the
left-hand side, lumped onto the section's nodes by their shares, so each node's mass becomes
``m_i I + w_i l_j m_j e e'`` and the integrator solves for its acceleration
(:func:`solve_added_mass`, a Sherman-Morrison update: exact, and stable however large the added
mass is against the node's own, as at the caudal fin, where it is several times the tail's).
The rest, ``-l_j m_j (de/dt . v_j) e`` (the section's normal turning under the water's velocity,
``de/dt`` from the nodes' velocities with U held) and ``-l_j (dm_j/dt) w e`` (water taken on as
the section goes under the surface), is explicit. A section that leaves the water does not get
back the momentum of the water it leaves (the water keeps it).

The dolphin undulates in its vertical plane: its sections carry water for vertical motion
(half widths across it: the rings', the flukes' half span; the flukes carry about 15 times
their nodes' mass), each about its own left (``BodySpec.section_up``, ``section_down``: a
ring's left corners less its right ones, the flukes' left tip less the right). About the front
rings' left, as the fish's sections are about its front's up, a tail bent sideways lined up
with that axis and the tail's normal flipped under random actions, which blew the body up;
about their own axes the tissue stays within its limits (``tests/envs/physics/test_tissue.py``).
A light stroke swims like a dolphin; at full activation the stroke pitches the body over into
loops (the hand MCs are calibrated below it: :mod:`animat.envs.motor.dolphin`; the figures are
in ``docs/physics.md``).

The water's density and added mass are bounded in the reactive water (``Water``: density and
density x added mass at most 1100 kg/m^3): at the default step the caudal fin whips above it
under random actions (a smaller step holds more).

In a vacuum (``density`` 0) every term is zero and the step is the resistive one, bit for bit;
a body without sections feels no reactive force.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .forces import BATCH, FAST, add_nodes, lane_count, wet_fraction
from .system import ADDED_MASS, CURRENT_X, CURRENT_Y, CURRENT_Z, DENSITY, SURFACE_Z

SECTION_ROWS = 10  # rows of the sections' terms per section (add_reactive_forces's ``s``)
MEAN_ROWS = 8  # rows of the sections' means and wet shares (its ``means``)


@njit(cache=True, inline="always")
def _normalised(a0: float, a1: float, a2: float) -> tuple[float, float, float]:
    inverse = 1.0 / max(np.sqrt(a0 * a0 + a1 * a1 + a2 * a2), 1e-300)
    return a0 * inverse, a1 * inverse, a2 * inverse


@njit(inline="always", **FAST)
def _section_means(x, v, nodes, weights, j, means, one_body) -> None:
    """means[j, 0:3] the section's centre (m), means[j, 3:6] its velocity (m/s), every lane."""
    lanes = lane_count(x, one_body)
    for r in range(6):
        for lane in range(lanes):
            means[j, r, lane] = 0.0
    for k in range(nodes.shape[1]):
        node, share = nodes[j, k], weights[j, k]
        for a in range(3):
            for lane in range(lanes):
                means[j, a, lane] += share * x[node, a, lane]
                means[j, 3 + a, lane] += share * v[node, a, lane]


@njit(inline="always", **FAST)
def _body_up(x, up, down, out, one_body) -> None:
    """out (3, L): a section's axis across the plane of undulation (the ``up`` nodes'
    centroid minus the ``down`` nodes', m)."""
    for a in range(3):
        for lane in range(lane_count(out, one_body)):
            out[a, lane] = 0.0
    add_nodes(x, up, 1.0 / up.shape[0], out, one_body)
    add_nodes(x, down, -1.0 / down.shape[0], out, one_body)


@njit(cache=True, inline="always")
def _same_axis(up, down, j) -> bool:
    """Section j's axis nodes are section j - 1's."""
    for k in range(up.shape[1]):
        if up[j, k] != up[j - 1, k] or down[j, k] != down[j - 1, k]:
            return False
    return True


@njit(**FAST)
def add_reactive_forces(x, v, up, down, nodes, weights, lengths, areas, water, dt, f, s, means,
                        frame, masses, one_body=BATCH) -> None:
    """Add each section's reactive force (the module's ``F_j``) to its nodes by their shares.

    ``nodes``, ``weights`` (J, K), ``lengths`` (J,) m and ``areas`` (J,) m^2: the body's
    sections (``BodySpec.section_*``); ``up``, ``down`` (J, K') each section's node lists of
    its axis across the plane of undulation (``BodySpec.section_up``, ``section_down``);
    ``water`` :meth:`Water.as_args`; ``dt`` the step, s; ``f`` (N, 3, L) the force
    accumulator, N; ``masses`` (N,) the nodes' masses, kg. Work space: ``s`` (J, SECTION_ROWS,
    L), ``means`` (J, MEAN_ROWS, L) and ``frame`` (3, L); ``one_body``:
    :func:`animat.envs.physics.forces.lane_count`. On return ``s[j, 0:3]`` holds each
    section's normal e and ``s[j, 3]`` its added mass ``l m`` (kg), for
    :func:`solve_added_mass`. (Inputs and outputs of each lane loop are separate arrays, so
    that the loops run in SIMD.)"""
    count = nodes.shape[0]
    rho = water[DENSITY] * water[ADDED_MASS]
    surface_z = water[SURFACE_Z]
    c0, c1, c2 = water[CURRENT_X], water[CURRENT_Y], water[CURRENT_Z]
    for j in range(count):
        _section_means(x, v, nodes, weights, j, means, one_body)
        if surface_z < np.inf:
            _wet_shares(means, j, np.sqrt(areas[j] / np.pi), surface_z, dt, one_body)
        else:
            for lane in range(lane_count(means, one_body)):
                means[j, 6, lane], means[j, 7, lane] = 1.0, 0.0
    for j in range(count):
        if j == 0 or not _same_axis(up, down, j):  # the fish's sections share one: once
            _body_up(x, up[j], down[j], frame, one_body)
        front, back = means[max(j - 1, 0)], means[min(j + 1, count - 1)]
        if one_body is None:
            _section_terms(front, back, means[j], frame, rho * areas[j], lengths[j], c0, c1,
                           c2, s[j], one_body)
        else:
            _section_terms_inline(front, back, means[j], frame, rho * areas[j], lengths[j],
                                  c0, c1, c2, s[j], one_body)
    _add_section_forces(nodes, weights, f, s, means, masses, one_body)


@njit(inline="always", **FAST)
def _wet_shares(means, j, reach, surface_z, dt, one_body) -> None:
    """means[j, 6] the share of section j under the surface (its centre's height +- ``reach``
    m) and means[j, 7] the rate it goes under, 1/s: the share now less a step ago's (at most
    now's: a section leaving the water gets none of the water's momentum back), over dt."""
    for lane in range(lane_count(means, one_body)):
        height, rise = means[j, 2, lane], means[j, 5, lane]
        wet = wet_fraction(height - reach, height + reach, surface_z)
        was = min(wet_fraction(height - dt * rise - reach, height - dt * rise + reach,
                               surface_z), wet)
        means[j, 6, lane], means[j, 7, lane] = wet, (wet - was) / dt


@njit(cache=True, inline="always")
def _normal_and_rate(r0, r1, r2, q0, q1, q2, u0, u1, u2):
    """A section's unit normal e = U x r / |U x r| and its rate de/dt (1/s, U held), from the
    line r (m) between its neighbours, its rate q (m/s) and the body's up U."""
    b0, b1, b2 = u1 * r2 - u2 * r1, u2 * r0 - u0 * r2, u0 * r1 - u1 * r0
    d0, d1, d2 = u1 * q2 - u2 * q1, u2 * q0 - u0 * q2, u0 * q1 - u1 * q0
    inverse = 1.0 / max(np.sqrt(b0 * b0 + b1 * b1 + b2 * b2), 1e-300)
    e0, e1, e2 = b0 * inverse, b1 * inverse, b2 * inverse
    along = e0 * d0 + e1 * d1 + e2 * d2
    return (e0, e1, e2, (d0 - along * e0) * inverse, (d1 - along * e1) * inverse,
            (d2 - along * e2) * inverse)


@njit(**FAST)
def _section_terms(front, back, own, frame, density_area, length, c0, c1, c2, out,
                   one_body) -> None:
    """:func:`_section_terms_inline`, called: in a batch, inlined into the loop over the
    sections, its lane loops no longer run in SIMD; for one body, inlined is faster (no lane
    loops), so :func:`add_reactive_forces` inlines it there."""
    _section_terms_inline(front, back, own, frame, density_area, length, c0, c1, c2, out,
                          one_body)


@njit(inline="always", **FAST)
def _section_terms_inline(front, back, own, frame, density_area, length, c0, c1, c2, out,
                          one_body) -> None:
    """A section's normal e (out[0:3]), added mass l m (out[3]), momentum flux Phi (out[4:7])
    and the explicit part of -e d/dt(l m w) (out[7:10]), (SECTION_ROWS, L), from its means and wet
    shares ``own`` and those of the sections in ``front`` of it and ``back`` of it
    (MEAN_ROWS, L); ``frame`` (3, L) the section's axis across the plane of undulation
    (:func:`_lane_terms`). In a batch, two lane loops, each writing few rows, so that both run
    in SIMD (each keeps only the terms it writes); for one body, one pass."""
    if one_body is not None:
        terms = _lane_terms(front, back, own, frame, density_area, length, c0, c1, c2, 0)
        out[0, 0], out[1, 0], out[2, 0], out[3, 0], out[4, 0] = terms[:5]
        out[5, 0], out[6, 0], out[7, 0], out[8, 0], out[9, 0] = terms[5:]
        return
    for lane in range(lane_count(out, one_body)):
        e0, e1, e2, added, p0, p1, p2, _, _, _ = _lane_terms(
            front, back, own, frame, density_area, length, c0, c1, c2, lane)
        out[4, lane], out[5, lane], out[6, lane] = p0, p1, p2
        out[0, lane], out[1, lane], out[2, lane] = e0, e1, e2
        out[3, lane] = added
    for lane in range(lane_count(out, one_body)):
        _, _, _, _, _, _, _, q0, q1, q2 = _lane_terms(
            front, back, own, frame, density_area, length, c0, c1, c2, lane)
        out[7, lane], out[8, lane], out[9, lane] = q0, q1, q2


@njit(cache=True, inline="always")
def _lane_terms(front, back, own, frame, density_area, length, c0, c1, c2, lane):
    """Lane ``lane``'s ten section terms, in :func:`_section_terms_inline`'s row order."""
    r0 = front[0, lane] - back[0, lane]
    r1 = front[1, lane] - back[1, lane]
    r2 = front[2, lane] - back[2, lane]
    e0, e1, e2, g0, g1, g2 = _normal_and_rate(
        r0, r1, r2, front[3, lane] - back[3, lane], front[4, lane] - back[4, lane],
        front[5, lane] - back[5, lane], frame[0, lane], frame[1, lane], frame[2, lane])
    t0, t1, t2 = _normalised(r0, r1, r2)
    m = density_area * own[6, lane]
    gain = density_area * own[7, lane]  # water taken on, kg/m/s
    w0, w1, w2 = own[3, lane] - c0, own[4, lane] - c1, own[5, lane] - c2
    side = e0 * w0 + e1 * w1 + e2 * w2  # w, m/s
    forward = max(t0 * w0 + t1 * w1 + t2 * w2, 0.0) * m * side
    energy = 0.5 * m * side * side  # 1/2 m w^2, J/m
    rate = g0 * w0 + g1 * w1 + g2 * w2  # (de/dt).w, m/s^2
    push = -length * (m * rate + gain * side)  # -l d(m w)/dt less m dw/dt (implicit), N
    return (e0, e1, e2, length * m, forward * e0 - energy * t0, forward * e1 - energy * t1,
            forward * e2 - energy * t2, push * e0, push * e1, push * e2)


@njit(**FAST)
def _add_section_forces(nodes, weights, f, s, total, masses, one_body) -> None:
    """f += each section's F_j = s[j, 7:10] - (Phi_{j+1/2} - Phi_{j-1/2}), Phi_j = s[j, 4:7],
    shared among its nodes by their weights (F_j assembled in ``total[j, 0:3]``, which holds
    the sections' centres on entry), except the trailing edge's force along the body: that
    goes to the nodes of the last two sections by their masses (``masses`` (N,), kg)."""
    count, lanes = nodes.shape[0], lane_count(f, one_body)
    along = np.empty((4, lanes))  # the trailing edge's tangent (rows 0:3) and force along it
    for lane in range(lanes):
        along[0, lane], along[1, lane], along[2, lane] = _normalised(
            total[count - 2, 0, lane] - total[count - 1, 0, lane],
            total[count - 2, 1, lane] - total[count - 1, 1, lane],
            total[count - 2, 2, lane] - total[count - 1, 2, lane])
    for j in range(count):
        # the half-way fluxes upwind, Phi_{j+1/2} = Phi_j (the water streams tailward): none
        # in front of the nose, the last section's own at the trailing edge
        front = 1.0 if j > 0 else 0.0
        for a in range(3):
            for lane in range(lanes):
                total[j, a, lane] = (s[j, 7 + a, lane] - s[j, 4 + a, lane]
                                     + front * s[max(j - 1, 0), 4 + a, lane])
    last = count - 1
    for lane in range(lanes):
        along[3, lane] = (total[last, 0, lane] * along[0, lane]
                          + total[last, 1, lane] * along[1, lane]
                          + total[last, 2, lane] * along[2, lane])
        for a in range(3):
            total[last, a, lane] -= along[3, lane] * along[a, lane]
    pool = 0.0
    for j in range(count):
        for k in range(nodes.shape[1]):
            node, share = nodes[j, k], weights[j, k]
            if j >= count - 2 and share > 0.0:
                pool += masses[node]
            for a in range(3):
                for lane in range(lanes):
                    f[node, a, lane] += share * total[j, a, lane]
    for j in range(count - 2, count):
        for k in range(nodes.shape[1]):
            node = nodes[j, k]
            if weights[j, k] > 0.0:
                for a in range(3):
                    for lane in range(lanes):
                        f[node, a, lane] += masses[node] / pool * along[3, lane] * along[a, lane]


@njit(**FAST)
def solve_added_mass(f, masses, nodes, weights, s, one_body=BATCH) -> None:
    """Turn the force on each section node into ``m_i (m_i I + c e e')^-1 f_i``, with
    ``c = w_i l m`` its share of the section's added mass (``s`` as left by
    :func:`add_reactive_forces`), so that the integrator's ``v += dt f / m_i`` solves the
    node's motion with the water it carries (Sherman-Morrison)."""
    lanes = lane_count(f, one_body)
    for j in range(nodes.shape[0]):
        for k in range(nodes.shape[1]):
            node, share = nodes[j, k], weights[j, k]
            if share == 0.0:
                continue
            mass = masses[node]
            for lane in range(lanes):
                f0, f1, f2 = f[node, 0, lane], f[node, 1, lane], f[node, 2, lane]
                e0, e1, e2 = s[j, 0, lane], s[j, 1, lane], s[j, 2, lane]
                c = share * s[j, 3, lane]
                d = c / (mass + c) * (e0 * f0 + e1 * f1 + e2 * f2)
                f[node, 0, lane] = f0 - d * e0
                f[node, 1, lane] = f1 - d * e1
                f[node, 2, lane] = f2 - d * e2


def water_momentum(x: np.ndarray, v: np.ndarray, body, water) -> np.ndarray:
    """(B, 3) the momentum of the water the bodies carry, sum_j l_j p_j, kg m/s (x, v (B, N, 3);
    ``water`` a :class:`~animat.envs.physics.system.Water`); zero for resistive water."""
    return _carried(x, v, body, water)[0]


def water_energy(x: np.ndarray, v: np.ndarray, body, water) -> np.ndarray:
    """(B,) the kinetic energy of the water the bodies carry, sum_j 1/2 l_j m_j w_j^2, J."""
    return _carried(x, v, body, water)[1]


def _carried(x, v, body, water):
    count = body.section_nodes.shape[0]
    if water.model != "reactive" or count == 0:
        return np.zeros((x.shape[0], 3)), np.zeros(x.shape[0])
    xl, vl = np.ascontiguousarray(x.transpose(1, 2, 0)), np.ascontiguousarray(v.transpose(1, 2, 0))
    s, means = np.zeros((count, SECTION_ROWS, x.shape[0])), np.zeros((count, MEAN_ROWS, x.shape[0]))
    add_reactive_forces(xl, vl, body.section_up, body.section_down, body.section_nodes,
                        body.section_weights, body.section_lengths, body.section_areas,
                        water.as_args(), 1.0, np.zeros_like(xl), s, means,
                        np.empty((3, x.shape[0])), body.masses)
    w = means[:, 3:6] - np.asarray(water.current)[None, :, None]
    normal = s[:, 0:3]
    side = np.einsum("jab,jab->jb", normal, w)
    momentum = s[:, 3, None] * side[:, None] * normal
    return momentum.sum(axis=0).T, (0.5 * s[:, 3] * side**2).sum(axis=0)
