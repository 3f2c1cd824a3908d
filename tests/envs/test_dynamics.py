"""Physics: rest, equilibrium, energy, momentum, robustness."""

import numpy as np

from envs.fish import fish_body
from envs.physics.integrator import implicit_step, step_batch, workspace
from envs.physics.observe import body_state
from envs.physics.system import System, Water


def _batch(body, count=1):
    x = np.repeat(body.rest_positions[None], count, axis=0).copy()
    return x, np.zeros_like(x)


def _com(system, x, v):
    b = system.body
    return body_state(x, v, b.masses, b.frame_front, b.frame_back, b.frame_up,
                      b.frame_down)[0]


def test_spring_at_rest_length_exerts_no_force():
    body = fish_body()
    system = System(body)
    lanes = body.rest_positions[:, :, None].copy()  # (N, 3, 1): lane layout, one body
    v = np.zeros_like(lanes)
    implicit_step(lanes, v, np.zeros_like(lanes), body.masses, body.elements, body.stiffness,
                  body.damping, body.rest_lengths[:, None].copy(), system.inverse_matrix,
                  system.dt, system.iterations, system.chebyshev_rho,
                  workspace(body.num_nodes, body.num_elements, 1))
    np.testing.assert_allclose(lanes[:, :, 0], body.rest_positions, atol=1e-12)
    np.testing.assert_allclose(v, 0.0, atol=1e-10)


def test_relaxed_fish_stays_put_for_ten_seconds():
    system = System(fish_body())
    x, v = _batch(system.body)
    start = _com(system, x, v)
    zeros = np.zeros((1, 6))
    step_batch(x, v, zeros, zeros, np.zeros((1, 2)), 400, system.kernel_args)  # 10 s
    moved = np.linalg.norm(_com(system, x, v) - start)
    assert moved < 0.01 * system.body.length


def _kinetic(system, v):
    return 0.5 * np.sum(system.body.masses[:, None] * v[0] ** 2)


def test_kinetic_energy_decays_after_actuation_stops():
    system = System(fish_body())
    x, v = _batch(system.body)
    rng = np.random.default_rng(0)
    u_prev = np.zeros((1, 6))
    for _ in range(40):
        u = rng.uniform(0, 1, (1, 6))
        step_batch(x, v, u_prev, u, np.zeros((1, 2)), 2, system.kernel_args)
        u_prev = u
    zeros = np.zeros((1, 6))
    step_batch(x, v, u_prev, zeros, np.zeros((1, 2)), 2, system.kernel_args)
    energies = []
    for _ in range(60):
        step_batch(x, v, zeros, zeros, np.zeros((1, 2)), 4, system.kernel_args)
        energies.append(_kinetic(system, v))
    assert energies[0] > 1e-5
    assert energies[-1] < 0.5 * energies[0]  # a gliding body under quadratic drag: ~1/t^2
    tail = energies[10:]  # after the released muscles' elastic energy has come out
    assert all(b <= a * 1.05 for a, b in zip(tail, tail[1:]))


def test_momentum_is_conserved_without_fluid():
    water = Water(fluid_coefficient=0.0, air_coefficient=0.0, gravity=0.0)
    system = System(fish_body(), water)
    x, v = _batch(system.body)
    v[0] += np.array([0.2, -0.1, 0.05])
    masses = system.body.masses[:, None]
    before = (masses * v[0]).sum(axis=0)
    rng = np.random.default_rng(1)
    u_prev = np.zeros((1, 6))
    for _ in range(50):
        u = rng.uniform(0, 1, (1, 6))
        step_batch(x, v, u_prev, u, rng.uniform(-0.5, 0.5, (1, 2)), 2, system.kernel_args)
        u_prev = u
    np.testing.assert_allclose((masses * v[0]).sum(axis=0), before, atol=1e-9)


def test_random_fin_angles_keep_the_batch_finite():
    """Fin angles are not part of the env actions; drive them at random here."""
    system = System(fish_body())
    x, v = _batch(system.body, 64)
    rng = np.random.default_rng(2)
    u_prev = np.zeros((64, 6))
    for _ in range(200):
        u = rng.uniform(0, 1, (64, 6))
        fins = rng.uniform(-np.pi / 2, np.pi / 2, (64, 2))
        step_batch(x, v, u_prev, u, fins, 2, system.kernel_args)
        u_prev = u
    assert np.isfinite(x).all() and np.isfinite(v).all()


def test_a_batch_row_matches_a_batch_of_one_bit_for_bit():
    system = System(fish_body())
    x, v = _batch(system.body, 40)
    rng = np.random.default_rng(3)
    x += rng.normal(0, 1e-3, x.shape)
    one_x, one_v = x[7:8].copy(), v[7:8].copy()
    u_prev = np.zeros((40, 6))
    for _ in range(20):
        u = rng.uniform(0, 1, (40, 6))
        step_batch(x, v, u_prev, u, np.zeros((40, 2)), 2, system.kernel_args)
        step_batch(one_x, one_v, u_prev[7:8], u[7:8], np.zeros((1, 2)), 2, system.kernel_args)
        u_prev = u
    assert np.array_equal(x[7], one_x[0]) and np.array_equal(v[7], one_v[0])


def test_system_rejects_bad_parameters():
    import pytest
    with pytest.raises(ValueError, match="dt"):
        System(fish_body(), dt=-1.0)
    with pytest.raises(ValueError, match="fluid_coefficient"):
        Water(fluid_coefficient=float("nan"))


def test_above_the_surface_a_body_falls_ballistically():
    """The water-surface hook: above ``surface_z`` there is no buoyancy and only air drag."""
    water = Water(surface_z=-1.0)  # the fish starts 1 m above the water
    system = System(fish_body(), water)
    x, v = _batch(system.body)
    start = _com(system, x, v)[0]
    zeros = np.zeros((1, 6))
    step_batch(x, v, zeros, zeros, np.zeros((1, 2)), 8, system.kernel_args)  # 0.2 s
    drop = start[2] - _com(system, x, v)[0, 2]
    steps, h = 8, system.dt
    free_fall = 0.5 * water.gravity * h**2 * steps * (steps + 1)  # backward Euler's free fall
    assert 0.95 * free_fall < drop <= free_fall * (1 + 1e-9)  # air drag may only slow it
