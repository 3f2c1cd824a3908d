"""The implicit integrator (``System(integrator="implicit")``): its matrix is the elements'
Jacobian, its solve the dense one, it keeps momentum and angular momentum in a vacuum, a rotated
start gives the rotated trajectory, a batch row is the batch of one, and bad settings are
refused (its stability under legal drives: tests/experiments/bench/test_stability.py)."""

import gymnasium as gym
import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.physics.forces import add_element_forces
from animat.envs.physics.implicit import assemble_elements, cholesky_band, solve_band
from animat.envs.physics.integrator import step_batch
from animat.envs.physics.observe import momenta
from animat.envs.physics.system import System, Water, half_bandwidth, vacuum

ENV_DT = 0.05


def _dense(band: np.ndarray) -> np.ndarray:
    """The symmetric matrix of one lane's lower band (n, W + 1)."""
    n, width = band.shape[0], band.shape[1] - 1
    matrix = np.zeros((n, n))
    for row in range(n):
        for k in range(min(width, row) + 1):
            matrix[row, row - k] = matrix[row - k, row] = band[row, k]
    return matrix


def test_the_matrix_is_the_elements_jacobian_in_tension():
    """hd D + hk K, with K = -df/dx by central differences (at rest velocity: no damper
    position term) and D = -df/dv, every element stretched."""
    body, rng = fish_body(), np.random.default_rng(0)
    x = (body.rest_positions + 3e-4 * rng.normal(size=body.rest_positions.shape))[:, :, None]
    rest = 0.9 * body.rest_lengths[:, None]
    n, width = 3 * body.num_nodes, half_bandwidth(body.elements, body.faces)

    def force(x, v):
        f = np.zeros_like(x)
        add_element_forces(x, v, body.elements, body.stiffness, body.damping, rest, f)
        return f.reshape(-1)

    zero, eps = np.zeros_like(x), 1e-7
    stiffness, damping = np.zeros((n, n)), np.zeros((n, n))
    for c in range(n):
        dx = np.zeros(n)
        dx[c] = eps
        dx = dx.reshape(x.shape)
        stiffness[:, c] = -(force(x + dx, zero) - force(x - dx, zero)) / (2 * eps)
        damping[:, c] = -(force(x, dx) - force(x, -dx)) / (2 * eps)
    band, f = np.zeros((n, width + 1, 1)), np.zeros_like(x)
    blocks = np.zeros((len(body.elements), 5, 1))
    assemble_elements(x, zero, body.elements, body.stiffness, body.damping, rest, 0.01, 1e-4,
                      f, band, blocks)
    expected = 0.01 * damping + 1e-4 * stiffness
    assert np.abs(_dense(band[:, :, 0]) - expected).max() <= 1e-8 * np.abs(expected).max()
    assert np.allclose(f.reshape(-1), force(x, zero), rtol=0, atol=1e-12)


def test_the_banded_solve_is_the_dense_solve():
    rng = np.random.default_rng(1)
    n, width = 69, 23
    a = rng.normal(size=(n, n)) * (np.abs(np.subtract.outer(range(n), range(n))) <= width)
    matrix = a @ a.T + n * np.eye(n)
    matrix *= np.abs(np.subtract.outer(range(n), range(n))) <= width
    matrix += n * np.eye(n)
    band = np.zeros((n, width + 1, 1))
    for row in range(n):
        for k in range(min(width, row) + 1):
            band[row, k, 0] = matrix[row, row - k]
    rhs = rng.normal(size=(n, 1))
    expected = np.linalg.solve(matrix, rhs[:, 0])
    cholesky_band(band)
    solve_band(band, rhs)
    assert np.allclose(rhs[:, 0], expected, rtol=1e-10, atol=1e-12)


def _random_run(system: System, x, v, seconds: float, seed: int = 0, substeps: int = 1):
    """x, v (B, N, 3) in place under ``seconds`` of random activations (new each env step)."""
    rng = np.random.default_rng(seed)
    u0 = np.zeros((x.shape[0], system.body.num_actuators))
    for _ in range(int(round(seconds / ENV_DT))):
        u = rng.uniform(0.0, 1.0, u0.shape)
        step_batch(x, v, u0, u, np.zeros((x.shape[0], 2)), substeps, system.kernel_args)
        u0 = u


def _momenta(x, v, masses):
    com = (x * masses[None, :, None]).sum(axis=1) / masses.sum()
    return momenta(x, v, masses, com)


@pytest.mark.parametrize("dt", [0.00625, 0.025, 0.05])
def test_a_vacuum_keeps_momentum_and_angular_momentum(dt):
    body, rng = fish_body(), np.random.default_rng(2)
    x = np.repeat(body.rest_positions[None], 4, 0) + 2e-3 * rng.normal(size=(4, 23, 3))
    v = 0.05 * rng.normal(size=x.shape)
    before = _momenta(x, v, body.masses)
    _random_run(System(body, vacuum(), dt=dt, integrator="implicit"), x, v, 5.0,
                substeps=int(round(ENV_DT / dt)))
    after = _momenta(x, v, body.masses)
    for start, end in zip(before, after):
        assert np.abs(end - start).max() <= 1e-12 * max(np.abs(start).max(), 1.0)


def test_a_rigidly_rotated_start_follows_the_rotated_trajectory():
    body, rng = fish_body(), np.random.default_rng(3)
    angle, axis = 1.0, np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k
    x = body.rest_positions[None] + 2e-3 * rng.normal(size=(1, 23, 3))
    v = 0.05 * rng.normal(size=x.shape)
    system = System(body, vacuum(), dt=0.025, integrator="implicit")
    turned_x, turned_v = x @ rotation.T, v @ rotation.T
    _random_run(system, x, v, 3.0, substeps=2)
    _random_run(system, turned_x, turned_v, 3.0, substeps=2)
    assert np.abs(x @ rotation.T - turned_x).max() <= 1e-9


def test_a_batch_row_is_the_batch_of_one_bit_for_bit():
    body, rng = fish_body(), np.random.default_rng(5)
    system = System(body, Water(), dt=0.025, integrator="implicit")
    x = np.repeat(body.rest_positions[None], 40, 0) + 2e-3 * rng.normal(size=(40, 23, 3))
    v = 0.05 * rng.normal(size=x.shape)
    one_x, one_v = x[7:8].copy(), v[7:8].copy()
    u0, u1 = rng.uniform(0, 1, (40, 6)), rng.uniform(0, 1, (40, 6))
    for _ in range(5):
        step_batch(x, v, u0, u1, np.zeros((40, 2)), 2, system.kernel_args)
        step_batch(one_x, one_v, u0[7:8], u1[7:8], np.zeros((1, 2)), 2, system.kernel_args)
    assert np.array_equal(one_x[0], x[7]) and np.array_equal(one_v[0], v[7])


@pytest.mark.parametrize("arguments, message", [
    ({"integrator": "rk4"}, "System.integrator must be one of"),
    ({"integrator": "implicit", "dt": 0.2}, "implicit integrator's largest step"),
    ({"integrator": "implicit", "theta": 0.3}, "System.theta"),
    ({"integrator": "implicit", "theta": float("nan")}, "System.theta"),
])
def test_bad_settings_are_refused_in_one_line(arguments, message):
    with pytest.raises(ValueError, match=message) as error:
        System(fish_body(), **arguments)
    assert "\n" not in str(error.value)


def test_an_env_takes_the_integrator_and_names_a_bad_one():
    env = gym.make("Animat/FishSwim-v0", integrator="implicit", physics_dt=0.025, frame_skip=2)
    env.reset(seed=0)
    for _ in range(5):
        obs, reward, *_ = env.step(env.action_space.sample())
    assert np.isfinite(obs).all() and np.isfinite(reward)
    assert env.unwrapped.core.system.integrator == "implicit"
    with pytest.raises(ValueError, match="integrator"):
        gym.make("Animat/FishSwim-v0", integrator="euler")

