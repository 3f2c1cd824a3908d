"""Each part of an integration step timed in a compiled loop, so that no Python call overhead
(0.4-1 us a call, more than most parts cost for one body) is counted: ``animat bench
--breakdown``'s table (:func:`animat.experiments.bench.physics.breakdown`).

Every loop runs one part ``n`` times on the same arrays, as the fused step
(:func:`animat.envs.physics.integrator.step_chunk`) calls it once a substep: x, v, f (N, 3, L),
``c`` the system's kernel arguments, ``one_body`` BATCH or ONE_BODY
(:func:`animat.envs.physics.forces.lane_count`).
"""

from __future__ import annotations

from numba import njit

from animat.envs.physics import fins, forces, implicit, reactive
from animat.envs.physics.integrator import kick_drift, ramp_rest_lengths
from animat.envs.physics.system import AIR_PRESSURE, DENSITY, GRAVITY, SURFACE_Z


@njit(cache=True)
def rest_lengths_loop(n, c, u, rest, one_body):
    for _ in range(n):
        ramp_rest_lengths(c.rest_lengths, c.actuator, c.max_contraction, u, u, 0.5, rest, one_body)


@njit(cache=True)
def elements_loop(n, c, x, v, rest, f, one_body):
    for _ in range(n):
        forces.add_element_forces(x, v, c.elements, c.stiffness, c.damping, rest, f, one_body)


@njit(cache=True)
def faces_loop(n, c, x, v, f, scratch, splash, one_body):
    for _ in range(n):
        forces.add_face_forces(x, v, c.faces, c.face_weights, c.face_mass, c.water, c.dt, f,
                               scratch, splash, one_body)


@njit(cache=True)
def fins_loop(n, c, x, v, frames, sin_cos, f, scratch, one_body):
    for _ in range(n):
        fins.add_fin_forces(x, v, frames, c.fin_nodes, c.fin_areas, c.fin_mass, sin_cos,
                            c.water, c.dt, f, scratch, one_body)


@njit(cache=True)
def gravity_loop(n, c, x, f, one_body):
    radii = forces.sphere_radii(c.volumes)
    for _ in range(n):
        forces.add_gravity_buoyancy(x, c.masses, c.volumes, radii, c.lungs, c.water[DENSITY],
                                    c.water[GRAVITY], c.water[SURFACE_Z], c.water[AIR_PRESSURE],
                                    f, one_body)


@njit(cache=True)
def sections_loop(n, c, x, v, f, sections, means, up, one_body):
    for _ in range(n):
        reactive.add_reactive_forces(x, v, c.section_up, c.section_down, c.section_nodes,
                                     c.section_weights, c.section_lengths, c.section_areas,
                                     c.water, c.dt, f, sections, means, up, c.masses, one_body)


@njit(cache=True)
def added_mass_loop(n, c, f, sections, one_body):
    for _ in range(n):
        reactive.solve_added_mass(f, c.masses, c.section_nodes, c.section_weights, sections,
                                  one_body)


@njit(cache=True)
def kick_drift_loop(n, c, x, v, f, one_body):
    for _ in range(n):
        kick_drift(x, v, f, c.masses, 0.0, one_body)


@njit(cache=True)
def implicit_matrix_loop(n, c, x, v, rest, f, band, blocks, terms, one_body):
    """The implicit step's matrix: the elements' forces and Jacobians, the faces' drag on the
    left side and the masses (:mod:`animat.envs.physics.implicit`)."""
    for _ in range(n):
        band[:] = 0.0
        implicit.assemble_elements(x, v, c.elements, c.stiffness, c.damping, rest, c.dt,
                                   c.dt * c.dt, f, band, blocks, one_body)
        implicit.add_face_damping(x, v, c.faces, c.face_weights, c.water, c.dt, band, terms,
                                  one_body)
        implicit.add_masses(c.masses, c.section_nodes, c.section_weights,
                            terms[:0], band, one_body)


@njit(cache=True)
def implicit_factor_loop(n, band, factored, one_body):
    """The banded Cholesky factor of the implicit step's matrix (from a copy each time)."""
    for _ in range(n):
        factored[:] = band
        implicit.cholesky_band(factored, one_body)


@njit(cache=True)
def implicit_solve_loop(n, factored, rhs, one_body):
    """The implicit step's two solves with the factor."""
    for _ in range(n):
        implicit.solve_band(factored, rhs[0], one_body)
        implicit.solve_band(factored, rhs[1], one_body)
