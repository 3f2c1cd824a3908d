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
    body_frame,
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


@njit(cache=True, fastmath=True)
def implicit_step(x, v, f_ext, masses, elements, stiffness, damping, rest, inverse_matrix, dt,
                  iterations, rho):
    """One implicit-Euler step of a chunk of L bodies, in place.

    x, v, f_ext: (N, 3, L) positions (m), velocities (m/s), external forces (N) in lane layout
    (bodies innermost, so every loop below runs over bodies in SIMD and each body's arithmetic
    is the same whatever L is); rest: (E, L) element rest lengths, m.
    """
    n, n_el, lanes = x.shape[0], elements.shape[0], x.shape[2]
    h2 = dt * dt
    inertial = np.empty((n, 3, lanes))
    xk = np.empty((n, 3, lanes))
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                y = x[i, a, b] + dt * v[i, a, b] + h2 * f_ext[i, a, b] / masses[i]
                xk[i, a, b] = y
                inertial[i, a, b] = y * masses[i] / h2
    r0_dir = np.empty((n_el, 3, lanes))
    for e in range(n_el):
        i, j = elements[e, 0], elements[e, 1]
        for b in range(lanes):
            r_x = x[j, 0, b] - x[i, 0, b]
            r_y = x[j, 1, b] - x[i, 1, b]
            r_z = x[j, 2, b] - x[i, 2, b]
            norm = np.sqrt(r_x * r_x + r_y * r_y + r_z * r_z)
            r0_dir[e, 0, b], r0_dir[e, 1, b], r0_dir[e, 2, b] = r_x / norm, r_y / norm, r_z / norm
    rhs = np.empty((n, 3, lanes))
    x_hat = np.empty((n, 3, lanes))
    x_before = xk.copy()
    omega = 1.0
    for it in range(iterations):
        rhs[:] = inertial
        local_step(x, xk, elements, stiffness, damping / dt, rest, r0_dir, rhs)
        x_hat[:] = 0.0
        for i in range(n):
            for k in range(n):
                weight = inverse_matrix[i, k]
                for a in range(3):
                    for b in range(lanes):
                        x_hat[i, a, b] += weight * rhs[k, a, b]
        omega = chebyshev_weight(it, omega, rho)
        for i in range(n):
            for a in range(3):
                for b in range(lanes):
                    x_next = omega * (x_hat[i, a, b] - x_before[i, a, b]) + x_before[i, a, b]
                    x_before[i, a, b] = xk[i, a, b]
                    xk[i, a, b] = x_next
    for i in range(n):
        for a in range(3):
            for b in range(lanes):
                v[i, a, b] = (xk[i, a, b] - x[i, a, b]) / dt
                x[i, a, b] = xk[i, a, b]


@njit(cache=True, fastmath=True)
def local_step(x0, xk, elements, stiffness, damper, rest, r0_dir, rhs) -> None:
    """Add each element's projection to ``rhs`` (N, 3, L): the spring vector of rest length
    ``rest`` along the current element, and the Voigt damper's target (start-of-step element
    plus the current change across it), weighted by c and gamma/h (``damper``)."""
    lanes = xk.shape[2]
    for e in range(elements.shape[0]):
        i, j = elements[e, 0], elements[e, 1]
        for b in range(lanes):
            r_x = xk[j, 0, b] - xk[i, 0, b]
            r_y = xk[j, 1, b] - xk[i, 1, b]
            r_z = xk[j, 2, b] - xk[i, 2, b]
            spring = stiffness[e] * rest[e, b] / np.sqrt(r_x * r_x + r_y * r_y + r_z * r_z)
            d_x = r_x - (x0[j, 0, b] - x0[i, 0, b])
            d_y = r_y - (x0[j, 1, b] - x0[i, 1, b])
            d_z = r_z - (x0[j, 2, b] - x0[i, 2, b])
            axial = d_x * r0_dir[e, 0, b] + d_y * r0_dir[e, 1, b] + d_z * r0_dir[e, 2, b]
            w_x = spring * r_x + damper[e] * (r_x - r0_dir[e, 0, b] * axial)
            w_y = spring * r_y + damper[e] * (r_y - r0_dir[e, 1, b] * axial)
            w_z = spring * r_z + damper[e] * (r_z - r0_dir[e, 2, b] * axial)
            rhs[j, 0, b] += w_x
            rhs[j, 1, b] += w_y
            rhs[j, 2, b] += w_z
            rhs[i, 0, b] -= w_x
            rhs[i, 1, b] -= w_y
            rhs[i, 2, b] -= w_z


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
    for s in range(substeps):
        ramp = (s + 1.0) / substeps
        for b in range(lanes):
            activation = u_start[b] + ramp * (u_end[b] - u_start[b])
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
                      dt, iterations, rho)
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


@njit(cache=True)
def observe_batch(x, v, masses, frame_front, frame_back, frame_up, frame_down):
    """Centre of mass (B, 3) m, its velocity (B, 3) m/s, body frames (B, 3, 3) (rows: forward,
    left, up) and node positions and velocities relative to the centre of mass in the body
    frame, (B, N, 3) each."""
    n_bodies, n = x.shape[0], x.shape[1]
    com = np.zeros((n_bodies, 3))
    com_vel = np.zeros((n_bodies, 3))
    frames = np.empty((n_bodies, 3, 3))
    local_x = np.empty_like(x)
    local_v = np.empty_like(v)
    total = masses.sum()
    for b in range(n_bodies):
        for i in range(n):
            com[b] += masses[i] * x[b, i] / total
            com_vel[b] += masses[i] * v[b, i] / total
        frames[b] = body_frame(x[b], frame_front, frame_back, frame_up, frame_down)
        for i in range(n):
            for r in range(3):
                local_x[b, i, r] = 0.0
                local_v[b, i, r] = 0.0
                for a in range(3):
                    local_x[b, i, r] += frames[b, r, a] * (x[b, i, a] - com[b, a])
                    local_v[b, i, r] += frames[b, r, a] * (v[b, i, a] - com_vel[b, a])
    return com, com_vel, frames, local_x, local_v
