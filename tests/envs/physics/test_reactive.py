"""The reactive water (``Water(model="reactive")``, :mod:`animat.envs.physics.reactive`): the
solver's invariants, and a fish that swims like a fish in it.

Invariants, for the fish and the dolphin: in a vacuum it is the resistive step bit for bit; in an
ideal fluid (no drag, no gravity) it creates no energy (the body's and the carried water's kinetic
energy plus the elastic energy); a rotated start gives the rotated trajectory; the tissue holds
(passive elements within 0.7-1.3 of rest). Biology (the hand controllers recalibrated for it,
:data:`animat.envs.motor.fish.REACTIVE_SWIM` and ``REACTIVE_TURN``): the cruise's Strouhal number,
stride and amplitude in the ranges of real fish, a C-start of at least 60 degrees within 1 s. The
default step's convergence (within 5% of a step 4x smaller) and the 90-degree turn (within 10
degrees, no glide back) are held for both waters by ``tests/envs/physics/test_convergence.py`` and
``tests/envs/motor/test_motor.py``.
"""

import json
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

import animat  # noqa: F401  (registers Animat/*)
from animat.envs.bodies.dolphin import dolphin_body
from animat.envs.bodies.fish import fish_body
from animat.envs.motor.fish import (
    REACTIVE_SWIM,
    REACTIVE_TURN,
    CStartParams,
    SwimParams,
    cstart_mc,
    swim_mc,
    to_action,
    turn_mc,
    wave_mc,
)
from animat.envs.physics.integrator import step_batch
from animat.envs.physics.reactive import water_energy
from animat.envs.physics.system import System, Water, vacuum
from animat.experiments.biology import c_start, fish_cruise, gait_grid
from tests.support.tissue import passive_strain_range

REACTIVE = {"model": "reactive"}
IDEAL = Water(model="reactive", fluid_coefficient=0.0, air_coefficient=0.0,
              friction_coefficient=0.0, air_friction_coefficient=0.0, gravity=0.0)


def _start(body, count, seed):
    rng = np.random.default_rng(seed)
    x = np.repeat(body.rest_positions[None], count, axis=0) + rng.normal(0, 1e-3, (count, 23, 3))
    return x, rng.normal(0.0, 0.05, x.shape)


BODIES = {"fish": (fish_body(), 0.05 / 40), "dolphin": (dolphin_body(), 0.05 / 80)}  # body, dt


@pytest.mark.parametrize("name", BODIES)
def test_in_a_vacuum_the_reactive_step_is_the_resistive_one_bit_for_bit(name):
    body, dt = BODIES[name]
    resistive = System(body, vacuum(), dt=dt)
    reactive = System(body, Water(**{**vars(vacuum()), "model": "reactive"}), dt=dt)
    rng = np.random.default_rng(1)
    actions = rng.uniform(0, 1, (40, 3, 6))
    runs = []
    for system in (resistive, reactive):
        x, v = _start(body, 3, 0)
        u_prev = np.zeros((3, 6))
        for u in actions:
            step_batch(x, v, u_prev, u, np.zeros((3, 2)), int(round(0.05 / dt)),
                       system.kernel_args)
            u_prev = u
        runs.append((x, v))
    assert np.array_equal(runs[0][0], runs[1][0]) and np.array_equal(runs[0][1], runs[1][1])


def _total_energy(body, x, v):
    r = x[:, body.elements[:, 1]] - x[:, body.elements[:, 0]]
    stretch = np.linalg.norm(r, axis=2) - body.rest_lengths
    return (0.5 * np.einsum("n,bnk->b", body.masses, v**2) + water_energy(x, v, body, IDEAL)
            + 0.5 * np.einsum("e,be->b", body.stiffness, stretch**2))


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("name", BODIES)
def test_an_ideal_fluid_creates_no_energy(name, seed):
    """A passive body set moving and vibrating (random node velocities, 0.05 m/s for the fish,
    scaled by length for the dolphin) in water with no drag and no gravity: its energy with
    the water's it carries never rises more than 1% above the start over 10 s, read every
    0.05 s (the dampers and the wake take it)."""
    body, dt = BODIES[name]
    system = System(body, IDEAL, dt=dt)
    x, v = _start(body, 1, seed)
    v *= body.length / 0.30
    zeros = np.zeros((1, 6))
    energies = [_total_energy(body, x, v)[0]]
    for _ in range(200):
        step_batch(x, v, zeros, zeros, np.zeros((1, 2)), int(round(0.05 / dt)),
                   system.kernel_args)
        energies.append(_total_energy(body, x, v)[0])
    energies = np.array(energies)
    assert energies.max() <= 1.01 * energies[0], energies.max() / energies[0]
    assert energies[-1] < energies[0]


@pytest.mark.parametrize("name", BODIES)
def test_a_rigidly_rotated_state_follows_the_rotated_trajectory_in_reactive_water(name):
    body, dt = BODIES[name]
    system = System(body, Water(model="reactive", gravity=0.0), dt=dt)
    a, b = 0.7, -0.4
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    rotation = rz @ ry
    x, v = _start(body, 1, 3)
    xr, vr = x @ rotation.T, v @ rotation.T
    actions = np.random.default_rng(4).uniform(0, 1, (40, 1, 6))
    for states in ((x, v), (xr, vr)):
        u_prev = np.zeros((1, 6))
        for u in actions:
            step_batch(*states, u_prev, u, np.zeros((1, 2)), int(round(0.05 / dt)),
                       system.kernel_args)
            u_prev = u
    scale = np.abs(x).max()
    assert np.abs(x @ rotation.T - xr).max() < 1e-9 * scale
    assert np.abs(x[0, :, 0] - _start(body, 1, 3)[0][0, :, 0]).max() > 0.05 * body.length / 0.3


def _strain_range(actions: np.ndarray) -> tuple[float, float]:
    """Min and max passive strain in reactive water over actions (T, B, 6), seeded starts."""
    return passive_strain_range(actions, REACTIVE)


def test_the_recalibrated_controllers_keep_the_tissue_within_limits_in_reactive_water():
    t = 0.05 * np.arange(1, 161)
    plays = [swim_mc(s, t, REACTIVE_SWIM) for s in (0.3, 1.0)]
    plays += [turn_mc(np.pi / 2, t, left, REACTIVE_TURN) for left in (True, False)]
    plays += [cstart_mc(t, left) for left in (True, False)]
    low, high = _strain_range(to_action(np.stack(plays, axis=1)).astype(np.float64))
    assert 0.7 <= low and high <= 1.3, (low, high)


def test_random_actions_keep_the_tissue_within_limits_in_reactive_water():
    """Random full-range actions at 20 Hz, 16 bodies for 25 s: no NaN, tissue within limits
    (0.83-1.20 of rest measured, the resistive water 0.80-1.23; with the fin's -l m w de/dt
    term kept, 0.75-1.46 and a NaN at 20 s)."""
    low, high = _strain_range(np.random.default_rng(0).uniform(-1, 1, (500, 16, 6)))
    assert 0.7 <= low and high <= 1.3, (low, high)


@pytest.mark.xfail(strict=True, reason="open (issue 24): the swim-MC's full activation at 5 Hz "
                   "strains the tail stock (ring 13-16 to ring 17-20) to 1.36 of rest; the "
                   "other strokes hold 0.77-1.19, the resistive water 0.83-1.15")
def test_full_activation_strokes_keep_the_tissue_within_limits_in_reactive_water():
    """The swim-MC at full activation at 1-5 Hz and full waves of contraction (2 and 4 Hz; lags
    0, 1 and -1 rad) for 30 s."""
    t = 0.05 * np.arange(1, 601)
    plays = [swim_mc(1.0, t, SwimParams(max_hz=hz, max_amplitude=1.0))
             for hz in (1.0, 2.0, 3.0, 5.0)]
    plays += [wave_mc(hz, lag, 1.0, t) for hz in (2.0, 4.0) for lag in (0.0, 1.0, -1.0)]
    low, high = _strain_range(to_action(np.stack(plays, axis=1)).astype(np.float64))
    assert 0.7 <= low and high <= 1.3, (low, high)


def test_the_cruise_swims_like_a_fish():
    """St 0.2-0.5, a stride of at least 0.5 BL per beat, a peak-to-peak tail amplitude of
    0.1-0.25 BL, a slip U/V of the body's wave within 0.05 of real fish's 0.6-0.8 (the
    resistive water's: St 1.19, 0.28 BL per beat, slip 0.30)."""
    figures = fish_cruise(REACTIVE, REACTIVE_SWIM)
    assert 0.2 <= figures["St"] <= 0.5, figures
    assert figures["stride"] >= 0.5, figures
    assert 0.1 <= figures["A"] <= 0.25, figures
    assert 0.55 <= figures["slip"] <= 0.85, figures


GRID = ([2.0, 3.0, 4.0], [0.0, 0.5, 1.0, 1.5, 2.0])  # the demo's: Hz, rad per segment


def test_a_body_wave_that_runs_tail_to_head_swims_at_most_a_third_as_fast():
    """Of the grid's muscle waves (both ways, the flaps left out), those that make the body's
    rear wave run tail to head swim forward (along the start heading) at most a third of the
    fastest wave's speed (measured: 0.14 BL/s, 5%)."""
    speeds, waves = gait_grid(REACTIVE, *GRID)
    backward = waves[:, 1:] < 0.0
    assert backward.any()  # measured: 5 of 24 (their bodies barely sway)
    assert speeds[:, 1:][backward].max() <= speeds.max() / 3.0, (speeds, waves)


@pytest.mark.xfail(strict=True, reason="open (issue 24): a muscle wave run tail to head still "
                   "makes the body's rear wave run head to tail (the passive rear third lags "
                   "under the water's added mass), and the fastest keeps 100% of its speed")
def test_the_fastest_muscle_wave_reversed_keeps_at_most_a_third_of_its_speed():
    speeds, _ = gait_grid(REACTIVE, *GRID)
    f, k = np.unravel_index(np.argmax(speeds[..., 0]), speeds[..., 0].shape)
    assert speeds[f, k, 1] <= speeds[f, k, 0] / 3.0, speeds


def test_a_c_start_turns_at_least_60_degrees_within_a_second():
    headings = c_start(REACTIVE, CStartParams())
    assert headings.max() >= 60.0, headings.max()
    resistive = c_start({"model": "resistive"}, CStartParams())
    assert resistive.max() < 30.0  # the paper's water cannot (23 degrees at most)


_DIVERGING = Path(__file__).parent / "data" / "diverging_swim_actions.json"


@pytest.mark.xfail(strict=True, reason="open: at the default physics step (1.25 ms) the reactive "
                   "water diverges under this CMA-ES swim candidate (actions changing by 0.57 a "
                   "step on average); half the step and the resistive water stay finite")
def test_a_jittery_cmaes_candidate_stays_finite_in_reactive_water():
    """The candidate that stopped two of the reactive swim comparison's CMA-ES runs (a NaN
    return at 793,600 env steps): replayed from its start, every observation stays finite."""
    case = json.loads(_DIVERGING.read_text())
    env = gym.make(case["env_id"], **case["env_kwargs"])
    obs, _ = env.reset(seed=case["start_seed"])
    finite = True
    actions = np.tile(np.asarray(case["period_actions"], dtype=np.float32), (case["periods"], 1))
    for action in actions:
        obs, reward, _, _, _ = env.step(action)
        finite = finite and bool(np.isfinite(reward)) and bool(np.all(np.isfinite(obs)))
    assert finite
