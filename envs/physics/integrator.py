"""Symplectic (semi-implicit) Euler for a batch of mass-spring bodies.

One step of size h, with every force evaluated at the start of the step::

    v' = v + h M^-1 f(x, v, t),    x' = x + h v'.

In reactive water (:mod:`animat.envs.physics.reactive`) M is the nodes' mass plus the added
mass of the water their cross-sections carry, taken at the start of the step.

Why this scheme is the default (the implicit step, :mod:`animat.envs.physics.implicit`, is an
option; ``docs/integrators.md`` compares them): for forces that are central and
equal-and-opposite (the Voigt elements), it conserves linear and angular momentum exactly,
whatever the step and the actuation — ``L' = sum m x' x v' = sum m x x v' = L + h sum x x f(x) =
L`` — where backward Euler changes L by ``-h^2 sum v' x f(x')`` every step unless corrected; it
does not damp the stroke the muscles drive; it is symplectic, so with the dampers off the energy
of the elastic body oscillates but does not drift; and it is explicit, so a step is a few
thousand flops with no solve. It is stable for ``h`` below ``2 / omega_max`` (the body's
stiffest mode, :func:`animat.envs.physics.system.stable_step`); the default step sits well
inside that bound, where the figures a researcher reads are converged
(``tests/envs/physics/test_convergence.py``).

``step_batch`` runs every body of a batch (B = 1 is a batch of one) through ``substeps`` steps,
with muscle activations ramped linearly from ``u_start`` to ``u_end`` (a first-order hold:
actions are piecewise linear in time, like the paper's tent-basis controllers) and the fin
angles held.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import njit, prange

from .ball import ball_substep
from .fins import add_fin_forces
from .forces import (
    BATCH,
    FAST,
    ONE_BODY,
    add_element_forces,
    add_face_forces,
    add_gravity_buoyancy,
    lane_count,
    sphere_radii,
)
from .implicit import implicit_step
from .reactive import MEAN_ROWS, SECTION_ROWS, add_reactive_forces, solve_added_mass
from .system import AIR_PRESSURE, DENSITY, GRAVITY, REACTIVE, SURFACE_Z


@njit(**FAST)
def ramp_rest_lengths(rest_lengths, actuator, max_contraction, u_start, u_end, ramp, rest,
                      one_body=BATCH):
    """rest (E, L): muscle e of body b at ``l0 (1 - max_contraction u)``, u ramped a fraction
    ``ramp`` from u_start to u_end (L, A); passive elements are left as they are."""
    lanes = lane_count(rest, one_body)
    for e in range(rest_lengths.shape[0]):
        a = actuator[e]
        if a < 0:
            continue
        for b in range(lanes):
            u = u_start[b, a] + ramp * (u_end[b, a] - u_start[b, a])
            rest[e, b] = rest_lengths[e] * (1.0 - max_contraction * u)


@njit(**FAST)
def kick_drift(x, v, f, masses, dt, one_body=BATCH) -> None:
    """v += dt f / m, then x += dt v (x, v, f (N, 3, L))."""
    lanes = lane_count(x, one_body)
    for i in range(x.shape[0]):
        scale = dt / masses[i]
        for a in range(3):
            for b in range(lanes):
                v[i, a, b] += scale * f[i, a, b]
                x[i, a, b] += dt * v[i, a, b]


@njit(cache=True)
def step_chunk(x, v, u_start, u_end, fin_angles, substeps, c, splash, ball, touch, ball_args,
               face_parts, one_body=BATCH):
    """Advance a chunk of L bodies, x, v (L, N, 3), in place by ``substeps`` steps, with
    activations ramped from u_start to u_end (L, A) and fin angles (L, P) held; ``c`` is
    :attr:`animat.envs.physics.system.System.kernel_args`; ``splash`` (L,) accumulates each
    body's splash, kg m/s (:func:`animat.envs.physics.forces.add_face_forces`). With
    ``ball_args`` not empty, each body has a beach ball (``ball`` (L, 6), ``touch`` (L, 3);
    :func:`animat.envs.physics.ball.ball_substep`) stepped after it. ``one_body`` ONE_BODY
    (L = 1) runs the kernels compiled for one body
    (:func:`animat.envs.physics.forces.lane_count`): the same numbers, faster."""
    lanes, n = (x.shape[0] if one_body is None else 1), x.shape[1]
    xl, vl, fl = np.empty((n, 3, lanes)), np.empty((n, 3, lanes)), np.empty((n, 3, lanes))
    for b in range(lanes):
        for i in range(n):
            for a in range(3):
                xl[i, a, b], vl[i, a, b] = x[b, i, a], v[b, i, a]
    rest = np.empty((c.rest_lengths.shape[0], lanes))
    for e in range(rest.shape[0]):
        for b in range(lanes):
            rest[e, b] = c.rest_lengths[e]
    sin_cos = np.empty((fin_angles.shape[1], 2, lanes))
    for b in range(lanes):
        for p in range(fin_angles.shape[1]):
            sin_cos[p, 0, b], sin_cos[p, 1, b] = np.sin(fin_angles[b, p]), np.cos(fin_angles[b, p])
    face_scratch = np.empty((c.faces.shape[0], 4, lanes))
    splash_lanes = np.zeros(lanes)
    fin_scratch = np.empty((16, lanes))
    frame_nodes = (c.frame_front, c.frame_back, c.frame_up, c.frame_down)
    reactive = c.water[REACTIVE] > 0.0 and c.section_nodes.shape[0] > 0
    sections = np.empty((c.section_nodes.shape[0], SECTION_ROWS, lanes))
    section_means = np.empty((c.section_nodes.shape[0], MEAN_ROWS, lanes))
    up_scratch = np.empty((3, lanes))
    # the nodes' buoyancy spheres: read only with a water surface
    radii = sphere_radii(c.volumes) if c.water[SURFACE_Z] < np.inf else c.volumes[:0]
    implicit = c.implicit_band > 0
    band = np.empty((3 * n if implicit else 0, c.implicit_band + 1, lanes))
    rhs = np.empty((2, 3 * n if implicit else 0, lanes))
    xp, fe = np.empty((n if implicit else 0, 3, lanes)), np.empty((n if implicit else 0, 3, lanes))
    blocks = np.empty((c.elements.shape[0] if implicit else 0, 5, lanes))
    terms = np.empty((c.faces.shape[0] if implicit else 0, 4, lanes))
    # the faces' drag is limited in the explicit step; the implicit one has it on its left side
    limit_dt = 0.0 if implicit else c.dt
    for s in range(substeps):
        # the implicit step takes the muscles' rest lengths at t + theta h
        ramp_rest_lengths(c.rest_lengths, c.actuator, c.max_contraction, u_start, u_end,
                          (s + c.theta) / substeps if implicit else s / substeps, rest, one_body)
        for i in range(n):
            for a in range(3):
                for b in range(lanes):
                    fl[i, a, b] = 0.0
        if not implicit:
            add_element_forces(xl, vl, c.elements, c.stiffness, c.damping, rest, fl, one_body)
        add_face_forces(xl, vl, c.faces, c.face_weights, c.face_mass, c.water, c.dt, fl,
                        face_scratch, splash_lanes, one_body, limit_dt)
        add_fin_forces(xl, vl, frame_nodes, c.fin_nodes, c.fin_areas, c.fin_mass, sin_cos,
                       c.water, c.dt, fl, fin_scratch, one_body)
        add_gravity_buoyancy(xl, c.masses, c.volumes, radii, c.lungs, c.water[DENSITY],
                             c.water[GRAVITY], c.water[SURFACE_Z], c.water[AIR_PRESSURE], fl,
                             one_body)
        if reactive:
            add_reactive_forces(xl, vl, c.section_up, c.section_down, c.section_nodes,
                                c.section_weights, c.section_lengths, c.section_areas, c.water,
                                c.dt, fl, sections, section_means, up_scratch, c.masses,
                                one_body)
            if not implicit:
                solve_added_mass(fl, c.masses, c.section_nodes, c.section_weights, sections,
                                 one_body)
        if implicit:
            implicit_step(xl, vl, fl, c.elements, c.stiffness, c.damping, rest, c.masses,
                          c.section_nodes, c.section_weights,
                          sections if reactive else sections[:0], c.faces, c.face_weights,
                          c.water, c.dt, c.theta, band, rhs, xp, fe, blocks, terms, one_body)
        else:
            kick_drift(xl, vl, fl, c.masses, c.dt, one_body)
        if ball_args.shape[0] > 0:
            ball_substep(xl.transpose(2, 0, 1), vl.transpose(2, 0, 1), c.masses, c.faces,
                         face_parts, ball, touch, ball_args, c.water, c.dt)
    for b in range(lanes):
        splash[b] += splash_lanes[b]
        for i in range(n):
            for a in range(3):
                x[b, i, a], v[b, i, a] = xl[i, a, b], vl[i, a, b]


CHUNK = 32  # the narrowest chunk width (a batch's last chunk may hold fewer bodies)
MAX_CHUNK = 128  # the most: wider chunks spend less on each lane loop's set-up per body
# (animat bench --breakdown times chunks of CHUNK and MAX_CHUNK)
SIMD_LANES = 8  # chunk widths are multiples of it (doubles in an AVX-512 register)


def chunk_width(batch: int, threads: int) -> int:
    """Lanes per chunk for a batch of ``batch`` bodies on ``threads`` threads: the batch split
    evenly over the threads, rounded up to a multiple of ``SIMD_LANES``, within [CHUNK,
    MAX_CHUNK]: wide chunks spend less on each lane loop's set-up, and every thread gets one."""
    per_thread = -(-batch // max(threads, 1))
    return min(max(-(-per_thread // SIMD_LANES) * SIMD_LANES, CHUNK), MAX_CHUNK)


@njit(cache=True)
def _step_serial(x, v, u_start, u_end, fin_angles, substeps, constants, splash, ball, touch,
                 ball_args, face_parts, chunk):
    for c in range(0, x.shape[0], chunk):
        e = min(c + chunk, x.shape[0])
        step_chunk(x[c:e], v[c:e], u_start[c:e], u_end[c:e], fin_angles[c:e], substeps,
                   constants, splash[c:e], ball[c:e], touch[c:e], ball_args, face_parts)


@njit(cache=True, parallel=True)
def _step_parallel(x, v, u_start, u_end, fin_angles, substeps, constants, splash, ball, touch,
                   ball_args, face_parts, chunk):
    for k in prange((x.shape[0] + chunk - 1) // chunk):
        c = k * chunk
        e = min(c + chunk, x.shape[0])
        step_chunk(x[c:e], v[c:e], u_start[c:e], u_end[c:e], fin_angles[c:e], substeps,
                   constants, splash[c:e], ball[c:e], touch[c:e], ball_args, face_parts)


@njit(cache=True)
def _step_one(x, v, u_start, u_end, fin_angles, substeps, constants, splash, ball, touch,
              ball_args, face_parts):
    step_chunk(x, v, u_start, u_end, fin_angles, substeps, constants, splash, ball, touch,
               ball_args, face_parts, ONE_BODY)


PARALLEL_MIN_BATCH = 2 * CHUNK
NO_BALL = (np.zeros((0, 6)), np.zeros((0, 3)), np.zeros(0), np.zeros(0, np.int64))


def step_batch(x: np.ndarray, v: np.ndarray, u_start: np.ndarray, u_end: np.ndarray,
               fin_angles: np.ndarray, substeps: int, kernel_args,
               splash: np.ndarray | None = None, ball=None) -> None:
    """Advance a batch in place: x, v (B, N, 3); u_start, u_end (B, A); fin_angles (B, P) rad;
    ``splash`` (B,), if given, accumulates each body's splash (kg m/s). ``ball``: None, or
    (ball (B, 6), touch (B, 3), ball_args, face_parts) for a beach ball per body
    (:mod:`animat.envs.physics.ball`), stepped with the bodies at every step.

    ``kernel_args`` is :attr:`animat.envs.physics.system.System.kernel_args`. Bodies are
    independent and go through the integrator in chunks (SIMD across bodies) of
    :func:`chunk_width` lanes, split over Numba's threads when B >= ``PARALLEL_MIN_BATCH``; a
    batch of one runs the kernels compiled for one body (``ONE_BODY``). Every body's arithmetic
    is the same whatever B is: a batch of one gives bit for bit the numbers of its row in a
    batch.
    """
    if splash is None:
        splash = np.zeros(x.shape[0])
    if ball is None:
        ball = NO_BALL
    batch = x.shape[0]
    if batch == 1:
        _step_one(x, v, u_start, u_end, fin_angles, int(substeps), kernel_args, splash, *ball)
    elif batch >= PARALLEL_MIN_BATCH:
        _step_parallel(x, v, u_start, u_end, fin_angles, int(substeps), kernel_args, splash,
                       *ball, chunk_width(batch, numba.get_num_threads()))
    else:
        _step_serial(x, v, u_start, u_end, fin_angles, int(substeps), kernel_args, splash,
                     *ball, chunk_width(batch, 1))
