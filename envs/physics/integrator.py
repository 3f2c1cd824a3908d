"""Implicit (backward) Euler for a batch of mass-spring bodies, solved by local/global sweeps.

One step of size h minimises, over the new positions x (Liu et al., "Fast simulation of
mass-spring systems", 2013; Bouaziz et al., "Projective dynamics", 2014):

    1/(2h^2) |x - y|_M^2 + sum_e c_e/2 |r_e - d_e|^2 + sum_e gamma_e/(2h) |r_e - r0_e - p_e|^2,

with ``y = x0 + h v0 + h^2 M^-1 f_ext``, ``r_e = x_j - x_i``, ``d_e`` the spring vector of rest
length ``l_e`` along ``r_e`` (spring energy ``c/2 (|r| - l)^2``) and ``p_e`` the part of
``r_e - r0_e`` across the element at the start of the step (so the last term is the Voigt
damper ``gamma (de/dt)`` along the element, taken implicitly). Each sweep fixes d, p (local
step, per element) and solves the linear system, whose matrix ``M/h^2 + L_c + L_gamma/h`` is
constant: its inverse is precomputed once in :class:`~envs.physics.system.System`. Muscles
change only rest lengths, never the matrix. The scheme is unconditionally stable (each sweep
lowers the objective) and conserves linear momentum exactly when external forces vanish.

``step_batch`` runs every body of a batch (B = 1 is a batch of one) through ``substeps`` steps,
with muscle activations ramped linearly from ``u_start`` to ``u_end`` (a first-order hold:
actions are piecewise linear in time, like the paper's tent-basis controllers).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from envs.physics.forces import (
    add_face_forces,
    add_fin_forces,
    add_gravity_buoyancy,
    body_frame_into,
    muscle_rest_lengths,
)


@njit(cache=True, inline="always")
def chebyshev_weight(iteration: int, omega: float, rho: float) -> float:
    """Chebyshev semi-iterative weight (Wang 2015) for sweep ``iteration`` (0-based); ``rho``
    estimates the spectral radius of the plain sweeps (0 turns acceleration off)."""
    if iteration == 0:
        return 1.0
    if iteration == 1:
        return 2.0 / (2.0 - rho * rho)
    return 4.0 / (4.0 - rho * rho * omega)


@njit(cache=True)
def apply_inverse(inverse, rhs, out) -> None:
    """out (N, W) = inverse (N, N) @ rhs (N, W), each sum taken in the order k = 0 .. N-1.

    Every loop order below does the same arithmetic (no fast-math, so no reassociation): for a
    single body (W = 3) two rows at a time with six independent running sums, so the sums'
    latencies overlap; for wide batches the W columns run in SIMD."""
    n, width = rhs.shape
    if width == 3:
        for i in range(0, n - 1, 2):
            a0 = a1 = a2 = b0 = b1 = b2 = 0.0
            for k in range(n):
                p, q = inverse[i, k], inverse[i + 1, k]
                r0, r1, r2 = rhs[k, 0], rhs[k, 1], rhs[k, 2]
                a0 += p * r0
                a1 += p * r1
                a2 += p * r2
                b0 += q * r0
                b1 += q * r1
                b2 += q * r2
            out[i, 0], out[i, 1], out[i, 2] = a0, a1, a2
            out[i + 1, 0], out[i + 1, 1], out[i + 1, 2] = b0, b1, b2
        if n % 2:
            a0 = a1 = a2 = 0.0
            for k in range(n):
                p = inverse[n - 1, k]
                a0 += p * rhs[k, 0]
                a1 += p * rhs[k, 1]
                a2 += p * rhs[k, 2]
            out[n - 1, 0], out[n - 1, 1], out[n - 1, 2] = a0, a1, a2
        return
    out[:] = 0.0
    for i in range(n):
        for k in range(n):
            weight = inverse[i, k]
            for m in range(width):
                out[i, m] += weight * rhs[k, m]


FAST = {"cache": True, "fastmath": {"contract"}, "error_model": "numpy"}


@njit(**FAST)
def workspace(n: int, n_el: int, lanes: int):
    """Scratch arrays for :func:`implicit_step` (allocated once per chunk, reused every step)."""
    return (np.empty((n, 3, lanes)), np.empty((n, 3, lanes)), np.empty((3, n_el, lanes)),
            np.empty((3, n_el, lanes)), np.empty((n_el, lanes)), np.empty((n_el, lanes)),
            np.empty((3, n_el, lanes)), np.empty((3, n_el, lanes)), np.empty((n, 3, lanes)),
            np.empty((n, 3, lanes)), np.empty((n, 3 * lanes)))


@njit(**FAST)
def implicit_step(x, v, f_ext, masses, elements, stiffness, damping, rest, inverse_matrix, dt,
                  iterations, rho, work):
    """One implicit-Euler step of a chunk of L bodies, in place.

    x, v, f_ext: (N, 3, L) positions (m), velocities (m/s), external forces (N) in lane layout
    (bodies innermost, so the loops run over bodies in SIMD and each body's arithmetic is the
    same whatever L is); rest: (E, L) element rest lengths, m; ``work``: :func:`workspace`.
    Element quantities are kept component-first, (3, E, L), so the per-element arithmetic is one
    flat loop over E * L.
    """
    n, n_el, lanes = x.shape[0], elements.shape[0], x.shape[2]
    h2 = dt * dt
    inertial, xk, r0, direction, spring_rest, damper, r, w, rhs, x_before, x_hat = work
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                y = x[i, a, b] + dt * v[i, a, b] + h2 * f_ext[i, a, b] / masses[i]
                xk[i, a, b] = y
                inertial[i, a, b] = y * masses[i] / h2
    element_vectors(x, elements, r0)
    for e in range(n_el):
        for b in range(lanes):
            norm = np.sqrt(r0[0, e, b] ** 2 + r0[1, e, b] ** 2 + r0[2, e, b] ** 2)
            for a in range(3):
                direction[a, e, b] = r0[a, e, b] / norm
            spring_rest[e, b] = stiffness[e] * rest[e, b]
            damper[e, b] = damping[e] / dt
    x_before[:] = xk
    # Flat (N, 3L) views: the dense solve and the updates run over 3L contiguous numbers.
    width = 3 * lanes
    flat_rhs, flat_xk, flat_before = (rhs.reshape(n, width), xk.reshape(n, width),
                                      x_before.reshape(n, width))
    flat_inertial = inertial.reshape(n, width)
    omega = 1.0
    for it in range(iterations):
        element_vectors(xk, elements, r)
        projections(r, r0, direction, spring_rest, damper, w)
        flat_rhs[:] = flat_inertial
        scatter_elements(elements, w, rhs)
        apply_inverse(inverse_matrix, flat_rhs, x_hat)
        omega = chebyshev_weight(it, omega, rho)
        for i in range(n):
            for m in range(width):
                x_next = omega * (x_hat[i, m] - flat_before[i, m]) + flat_before[i, m]
                flat_before[i, m] = flat_xk[i, m]
                flat_xk[i, m] = x_next
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                v[i, a, b] = (xk[i, a, b] - x[i, a, b]) / dt
                x[i, a, b] = xk[i, a, b]


@njit(**FAST)
def element_vectors(x, elements, out) -> None:
    """out (3, E, L) = x_j - x_i for every element (i, j); x (N, 3, L)."""
    if out.shape[2] == 1:  # a batch of one: plain loops (same arithmetic)
        for e in range(elements.shape[0]):
            i, j = elements[e, 0], elements[e, 1]
            for a in range(3):
                out[a, e, 0] = x[j, a, 0] - x[i, a, 0]
        return
    for e in range(elements.shape[0]):
        i, j = elements[e, 0], elements[e, 1]
        for a in range(3):
            xi, xj, o = x[i, a], x[j, a], out[a, e]
            for b in range(o.shape[0]):
                o[b] = xj[b] - xi[b]


@njit(**FAST)
def projections(r, r0, direction, spring_rest, damper, w) -> None:
    """The local step: w (3, E, L) = c l r/|r| + (gamma/h) (r - d (d . (r - r0))).

    The first term is c times the spring vector of rest length l along the current element
    r; the second is gamma/h times the Voigt damper's target, the start-of-step element r0
    plus the change across the start direction d (``spring_rest`` = c l and ``damper`` =
    gamma/h, each (E, L))."""
    size = spring_rest.size
    r_x, r_y, r_z = r[0].reshape(size), r[1].reshape(size), r[2].reshape(size)
    p_x, p_y, p_z = r0[0].reshape(size), r0[1].reshape(size), r0[2].reshape(size)
    d_x, d_y, d_z = (direction[0].reshape(size), direction[1].reshape(size),
                     direction[2].reshape(size))
    w_x, w_y, w_z = w[0].reshape(size), w[1].reshape(size), w[2].reshape(size)
    cl, g = spring_rest.reshape(size), damper.reshape(size)
    for q in range(size):
        spring = cl[q] / np.sqrt(r_x[q] * r_x[q] + r_y[q] * r_y[q] + r_z[q] * r_z[q])
        axial = ((r_x[q] - p_x[q]) * d_x[q] + (r_y[q] - p_y[q]) * d_y[q]
                 + (r_z[q] - p_z[q]) * d_z[q])
        w_x[q] = spring * r_x[q] + g[q] * (r_x[q] - d_x[q] * axial)
        w_y[q] = spring * r_y[q] + g[q] * (r_y[q] - d_y[q] * axial)
        w_z[q] = spring * r_z[q] + g[q] * (r_z[q] - d_z[q] * axial)


@njit(**FAST)
def scatter_elements(elements, w, rhs) -> None:
    """rhs (N, 3, L) += G' w: element e adds w_e to node j and subtracts it from node i."""
    if w.shape[2] == 1:  # a batch of one: plain loops (same arithmetic)
        for e in range(elements.shape[0]):
            i, j = elements[e, 0], elements[e, 1]
            for a in range(3):
                rhs[j, a, 0] += w[a, e, 0]
                rhs[i, a, 0] -= w[a, e, 0]
        return
    for e in range(elements.shape[0]):
        i, j = elements[e, 0], elements[e, 1]
        for a in range(3):
            we, ri, rj = w[a, e], rhs[i, a], rhs[j, a]
            for b in range(we.shape[0]):
                rj[b] += we[b]
                ri[b] -= we[b]


@njit(cache=True)
def external_forces_into(x, v, fin_angles, masses, volumes, faces, face_weights, face_mass,
                         fin_nodes, fin_areas, fin_mass, frame_front, frame_back, frame_up,
                         frame_down, kappa_water, kappa_air, density, gravity, surface_z,
                         current, dt, f, frame):
    """Write into ``f`` (N, 3) the hydrodynamic, fin, gravity and buoyancy forces on one body, N
    (``frame`` (3, 3) is scratch space for the body frame)."""
    f[:] = 0.0
    add_face_forces(x, v, faces, face_weights, face_mass, kappa_water, kappa_air, surface_z,
                    current, dt, f)
    body_frame_into(x, frame_front, frame_back, frame_up, frame_down, frame)
    add_fin_forces(x, v, frame, fin_nodes, fin_areas, fin_mass, fin_angles, kappa_water,
                   kappa_air, surface_z, current, dt, f)
    add_gravity_buoyancy(x, masses, volumes, density, gravity, surface_z, f)


@njit(cache=True)
def step_chunk(x, v, u_start, u_end, fin_angles, substeps, masses, volumes, elements,
               stiffness, damping, rest_lengths, actuator, max_contraction, faces, face_weights,
               face_mass, fin_nodes, fin_areas, fin_mass, frame_front, frame_back, frame_up,
               frame_down, inverse_matrix, kappa_water, kappa_air, density, gravity, surface_z,
               current, dt, iterations, rho):
    """Advance a chunk of L bodies, x, v (L, N, 3), in place by ``substeps`` steps, with
    activations ramped from u_start to u_end (L, A) and fin angles (L, P) held."""
    lanes, n = x.shape[0], x.shape[1]
    xl, vl, fl = np.empty((n, 3, lanes)), np.empty((n, 3, lanes)), np.empty((n, 3, lanes))
    f, frame = np.empty((n, 3)), np.empty((3, 3))
    rest = np.empty((rest_lengths.shape[0], lanes))
    rest_one = np.empty_like(rest_lengths)
    activation = np.empty(u_start.shape[1])
    work = workspace(n, elements.shape[0], lanes)
    for s in range(substeps):
        ramp = (s + 1.0) / substeps
        for b in range(lanes):
            for k in range(activation.shape[0]):
                activation[k] = u_start[b, k] + ramp * (u_end[b, k] - u_start[b, k])
            muscle_rest_lengths(rest_lengths, actuator, max_contraction, activation, rest_one)
            rest[:, b] = rest_one
            external_forces_into(x[b], v[b], fin_angles[b], masses, volumes, faces,
                                 face_weights, face_mass, fin_nodes, fin_areas, fin_mass,
                                 frame_front, frame_back, frame_up, frame_down, kappa_water,
                                 kappa_air, density, gravity, surface_z, current, dt, f, frame)
            for i in range(n):
                for a in range(3):
                    xl[i, a, b], vl[i, a, b], fl[i, a, b] = x[b, i, a], v[b, i, a], f[i, a]
        implicit_step(xl, vl, fl, masses, elements, stiffness, damping, rest, inverse_matrix,
                      dt, iterations, rho, work)
        for b in range(lanes):
            for i in range(n):
                for a in range(3):
                    x[b, i, a], v[b, i, a] = xl[i, a, b], vl[i, a, b]


CHUNK = 32


@njit(cache=True)
def _step_serial(x, v, u_start, u_end, fin_angles, substeps, *constants):
    for c in range(0, x.shape[0], CHUNK):
        e = min(c + CHUNK, x.shape[0])
        step_chunk(x[c:e], v[c:e], u_start[c:e], u_end[c:e], fin_angles[c:e], substeps,
                   *constants)


@njit(cache=True, parallel=True)
def _step_parallel(x, v, u_start, u_end, fin_angles, substeps, *constants):
    for k in prange((x.shape[0] + CHUNK - 1) // CHUNK):
        c = k * CHUNK
        e = min(c + CHUNK, x.shape[0])
        step_chunk(x[c:e], v[c:e], u_start[c:e], u_end[c:e], fin_angles[c:e], substeps,
                   *constants)


PARALLEL_MIN_BATCH = 2 * CHUNK


def step_batch(x: np.ndarray, v: np.ndarray, u_start: np.ndarray, u_end: np.ndarray,
               fin_angles: np.ndarray, substeps: int, kernel_args: tuple) -> None:
    """Advance a batch in place: x, v (B, N, 3); u_start, u_end (B, A); fin_angles (B, P) rad.

    ``kernel_args`` is :attr:`envs.physics.system.System.kernel_args`. Bodies are independent
    and go through the solver in chunks of ``CHUNK`` (SIMD across bodies), chunks split over
    threads when B >= ``PARALLEL_MIN_BATCH``. Every body's arithmetic is the same whatever B is:
    a batch of one gives bit for bit the numbers of its row in a batch.
    """
    kernel = _step_parallel if x.shape[0] >= PARALLEL_MIN_BATCH else _step_serial
    kernel(x, v, u_start, u_end, fin_angles, int(substeps), *kernel_args)
