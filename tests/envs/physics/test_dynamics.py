"""Physics invariants: rest, momentum and energy in vacuum, rotation invariance, robustness.

The measure of "conserved": the change of linear momentum relative to ``M * V``, and of angular
momentum (about the centre of mass) relative to ``M * R * V``, where M is the body's mass, R its
length and V the largest node speed seen during the run (the body's own momentum scale).
"""

import numpy as np
import pytest

from animat.envs.bodies.fish import fish_body
from animat.envs.physics.integrator import CHUNK, MAX_CHUNK, SIMD_LANES, chunk_width, step_batch
from animat.envs.physics.observe import body_state, momenta
from animat.envs.physics.system import STABILITY_MARGIN, System, Water, stable_step, vacuum


def _batch(body, count=1):
    x = np.repeat(body.rest_positions[None], count, axis=0).copy()
    return x, np.zeros_like(x)


def _com(system, x, v):
    b = system.body
    return body_state(x, v, b.masses, b.frame_front, b.frame_back, b.frame_up,
                      b.frame_down)[0]


def _momenta(system, x, v):
    return momenta(x, v, system.body.masses, _com(system, x, v))


def _energy(system, x, v, rest=None):
    """Kinetic plus elastic energy (J) of each body, springs at ``rest`` (E,) lengths."""
    b = system.body
    rest = b.rest_lengths if rest is None else rest
    r = x[:, b.elements[:, 1]] - x[:, b.elements[:, 0]]
    stretch = np.linalg.norm(r, axis=2) - rest
    return (0.5 * np.einsum("n,bnk->b", b.masses, v**2)
            + 0.5 * np.einsum("e,be->b", b.stiffness, stretch**2))


def _drive(system, x, v, actions, fins, substeps):
    """Play actuations (T, B, A) in [0, 1] and fin angles (T, B, P); returns the max node
    speed seen."""
    u_prev, top = np.zeros_like(actions[0]), 0.0
    for u, fin in zip(actions, fins):
        step_batch(x, v, u_prev, u, fin, substeps, system.kernel_args)
        u_prev, top = u, max(top, np.abs(v).max())
    return top


def test_spring_at_rest_length_exerts_no_force():
    system = System(fish_body(), vacuum())
    x, v = _batch(system.body)
    zeros = np.zeros((1, 6))
    step_batch(x, v, zeros, zeros, np.zeros((1, 2)), 10, system.kernel_args)
    np.testing.assert_allclose(x[0], system.body.rest_positions, atol=1e-14)
    np.testing.assert_allclose(v, 0.0, atol=1e-12)


def test_relaxed_fish_stays_put_for_ten_seconds():
    system = System(fish_body())
    x, v = _batch(system.body)
    start = _com(system, x, v)
    zeros = np.zeros((1, 6))
    step_batch(x, v, zeros, zeros, np.zeros((1, 2)), int(round(10 / system.dt)),
               system.kernel_args)
    assert np.linalg.norm(_com(system, x, v) - start) < 1e-4 * system.body.length


@pytest.mark.parametrize("kind", ["random", "bang-bang"])
def test_vacuum_conserves_linear_and_angular_momentum_for_ten_seconds(kind):
    """Internal forces only: whatever the muscles do (random or bang-bang, changing every
    env step) and with the fins waving, momentum stays where it started."""
    system = System(fish_body(), vacuum())
    x, v = _batch(system.body, 4)
    rng = np.random.default_rng(0)
    x += rng.normal(0.0, 1e-3, x.shape)
    v += rng.normal(0.0, 0.05, v.shape)  # a drifting, spinning start
    linear0, angular0 = _momenta(system, x, v)
    steps = 200  # 10 s of 0.05 s env steps
    actions = rng.uniform(0.0, 1.0, (steps, 4, 6))
    if kind == "bang-bang":
        actions = np.round(actions)
    fins = rng.uniform(-0.5, 0.5, (steps, 4, 2))
    top = _drive(system, x, v, actions, fins, 30)
    linear, angular = _momenta(system, x, v)
    mass, length = system.body.total_mass, system.body.length
    assert np.abs(linear - linear0).max() / (mass * top) < 1e-9
    assert np.abs(angular - angular0).max() / (mass * length * top) < 1e-9
    assert top > 0.1  # the muscles did move the body


def test_rigid_spin_in_vacuum_keeps_its_angular_momentum():
    system = System(fish_body(), vacuum())
    x, v = _batch(system.body)
    centre = _com(system, x, v)[0]
    omega = np.array([0.3, -0.5, 2.0])  # rad/s
    v[0] = np.cross(omega, x[0] - centre)
    _, angular0 = _momenta(system, x, v)
    zeros = np.zeros((1, 6))
    step_batch(x, v, zeros, zeros, np.zeros((1, 2)), int(round(5 / system.dt)),
               system.kernel_args)
    _, angular = _momenta(system, x, v)
    scale = system.body.total_mass * system.body.length * np.abs(v).max()
    assert np.abs(angular - angular0).max() / scale < 1e-9
    assert np.linalg.norm(angular0) > 1e-4


@pytest.mark.parametrize("seed", [4, 8])
def test_energy_without_damping_has_no_trend_for_eight_minutes(seed):
    """Symplectic: an elastic body set vibrating in vacuum neither gains nor loses energy. The
    energy read at a step oscillates (symplectic Euler conserves a nearby 'shadow' energy, not
    this one; the stiffest modes run at h omega ~ 1.5), but it has no trend: every 10 s mean
    of 480 s stays within 5% of the first (measured on seeds 4-11: 0.973-1.030). At 85% of the
    linear stability bound (the old 35 steps per env step) it crept up and blew up after about
    370 s on seed 8, which is why :data:`STABILITY_MARGIN` is 0.75."""
    import dataclasses

    body = fish_body()
    body = dataclasses.replace(body, damping=np.zeros_like(body.damping))
    system = System(body, vacuum())  # the default step
    x, v = _batch(body)
    x += np.random.default_rng(seed).normal(0.0, 2e-3, x.shape)
    start = _energy(system, x, v)[0]
    zeros, energies = np.zeros((1, 6)), []
    slice_steps = int(round(0.1 / system.dt))
    for _ in range(4800):  # 480 s in 0.1 s slices
        step_batch(x, v, zeros, zeros, np.zeros((1, 2)), slice_steps, system.kernel_args)
        energies.append(_energy(system, x, v)[0])
    energies = np.array(energies)
    assert energies.max() < 1.5 * start and energies.min() > 0.5 * start
    means = energies.reshape(48, 100).mean(axis=1) / energies[:100].mean()
    assert np.all(np.abs(means - 1.0) < 0.05), means.round(3)


def test_dampers_only_remove_energy():
    system = System(fish_body(), vacuum())
    x, v = _batch(system.body)
    x += np.random.default_rng(5).normal(0.0, 2e-3, x.shape)
    zeros, energies = np.zeros((1, 6)), [_energy(system, x, v)[0]]
    for _ in range(40):
        step_batch(x, v, zeros, zeros, np.zeros((1, 2)), 30, system.kernel_args)
        energies.append(_energy(system, x, v)[0])
    assert energies[-1] < 0.5 * energies[0]
    # over each 0.05 s the (oscillating) total falls; it never gains more than the
    # integrator's bounded energy error
    assert all(b < a * 1.01 for a, b in zip(energies, energies[1:]))


def _rotation(angles):
    a, b, c = angles
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rx = np.array([[1, 0, 0], [0, np.cos(c), -np.sin(c)], [0, np.sin(c), np.cos(c)]])
    return rz @ ry @ rx


def test_a_rigidly_rotated_state_follows_the_rotated_trajectory():
    """In still water with no gravity (so nothing picks a direction), rotating the whole start
    state rotates the whole trajectory: swimming, fins and all."""
    system = System(fish_body(), Water(gravity=0.0))
    rotation = _rotation((0.7, -0.4, 1.1))
    x, v = _batch(system.body, 1)
    rng = np.random.default_rng(6)
    x += rng.normal(0.0, 1e-3, x.shape)
    v += rng.normal(0.0, 0.02, v.shape)
    xr, vr = x @ rotation.T, v @ rotation.T
    actions = rng.uniform(0.0, 1.0, (60, 1, 6))
    fins = rng.uniform(-0.4, 0.4, (60, 1, 2))
    _drive(system, x, v, actions, fins, 30)
    _drive(system, xr, vr, actions, fins, 30)
    scale = system.body.length
    assert np.abs(xr - x @ rotation.T).max() / scale < 1e-9
    assert np.abs(x[0] - system.body.rest_positions).max() > 0.05 * scale  # it did move


def test_system_refuses_a_step_beyond_the_stability_bound():
    body = fish_body()
    with pytest.raises(ValueError, match="stability bound"):
        System(body, dt=stable_step(body))
    with pytest.raises(ValueError, match="stability bound"):
        System(body, dt=0.05 / 35)  # 85% of the bound: undamped, it blows up after minutes
    System(body, dt=0.99 * STABILITY_MARGIN * stable_step(body))
    with pytest.raises(ValueError, match="dt"):
        System(body, dt=-1.0)
    with pytest.raises(ValueError, match="fluid_coefficient"):
        Water(fluid_coefficient=float("nan"))
    with pytest.raises(ValueError, match="reaction"):
        Water(reaction="magic")
    with pytest.raises(ValueError, match="unknown field"):
        Water.from_dict({"gravty": 0})


@pytest.mark.parametrize("water", [Water(), Water(model="reactive")],
                         ids=["resistive", "reactive"])
def test_random_fin_angles_keep_the_batch_finite(water):
    system = System(fish_body(), water)
    x, v = _batch(system.body, 64)
    rng = np.random.default_rng(2)
    u_prev = np.zeros((64, 6))
    for _ in range(200):
        u = rng.uniform(0, 1, (64, 6))
        fins = rng.uniform(-np.pi / 2, np.pi / 2, (64, 2))
        step_batch(x, v, u_prev, u, fins, 30, system.kernel_args)
        u_prev = u
    assert np.isfinite(x).all() and np.isfinite(v).all()


@pytest.mark.parametrize("water", [Water(), Water(model="reactive"),
                                   Water(model="reactive", surface_z=0.05)],
                         ids=["resistive", "reactive", "reactive-surface"])
def test_a_batch_row_matches_a_batch_of_one_bit_for_bit(water):
    """A batch of one runs the kernels compiled for one body (ONE_BODY), a batch of 70 the lane
    kernels over threads (on 2 threads, chunks of 40 and 30: rows 7 and 69 each in one, 69
    among the lanes past the last full SIMD vector): every term, fins and the surface
    included, gives the same numbers."""
    system = System(fish_body(), water)
    x, v = _batch(system.body, 70)
    rng = np.random.default_rng(3)
    x += rng.normal(0, 1e-3, x.shape)
    rows = (7, 69)
    ones = [(x[r:r + 1].copy(), v[r:r + 1].copy(), np.zeros(1)) for r in rows]
    splash = np.zeros(70)
    u_prev = np.zeros((70, 6))
    for _ in range(20):
        u = rng.uniform(0, 1, (70, 6))
        fins = rng.uniform(-0.5, 0.5, (70, 2))
        step_batch(x, v, u_prev, u, fins, 30, system.kernel_args, splash)
        for r, (one_x, one_v, one_splash) in zip(rows, ones):
            step_batch(one_x, one_v, u_prev[r:r + 1], u[r:r + 1], fins[r:r + 1], 30,
                       system.kernel_args, one_splash)
        u_prev = u
    for r, (one_x, one_v, one_splash) in zip(rows, ones):
        assert np.array_equal(x[r], one_x[0]) and np.array_equal(v[r], one_v[0])
        assert splash[r] == one_splash[0]
    assert np.isfinite(x).all()


@pytest.mark.parametrize("batch", [2, 33, 64, 70, 256, 1000])
@pytest.mark.parametrize("threads", [1, 2, 8])
def test_chunks_are_simd_multiples_within_bounds_and_every_thread_gets_one(batch, threads):
    """A batch splits into chunks of a multiple of SIMD_LANES lanes in [CHUNK, MAX_CHUNK],
    few enough that no thread has two while another has none, and as few as that allows."""
    width = chunk_width(batch, threads)
    chunks = -(-batch // width)
    assert width % SIMD_LANES == 0 and CHUNK <= width <= MAX_CHUNK
    assert chunks <= max(threads, -(-batch // MAX_CHUNK))
    assert width == CHUNK or chunks >= min(threads, -(-batch // SIMD_LANES))


def test_above_the_surface_a_body_falls_ballistically():
    """The water-surface hook: above ``surface_z`` there is no buoyancy and only air drag."""
    water = Water(surface_z=-1.0)  # the fish starts 1 m above the water
    system = System(fish_body(), water)
    x, v = _batch(system.body)
    start = _com(system, x, v)[0]
    zeros = np.zeros((1, 6))
    steps = int(round(0.2 / system.dt))
    step_batch(x, v, zeros, zeros, np.zeros((1, 2)), steps, system.kernel_args)
    drop = start[2] - _com(system, x, v)[0, 2]
    h = system.dt
    free_fall = 0.5 * water.gravity * h**2 * steps * (steps + 1)  # symplectic Euler's free fall
    assert 0.95 * free_fall < drop <= free_fall * (1 + 1e-9)  # air drag may only slow it
