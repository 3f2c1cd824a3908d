"""Tent controllers, FFT abstraction and blended concatenation."""

import json

import numpy as np
import pytest

from animat.learners.controllers.abstraction import AbstractController, abstract
from animat.learners.controllers.concatenation import concatenate, schedule
from animat.learners.controllers.tent import TentController

A = 6  # channels of the test controllers (any number; controllers are body-agnostic)

def test_tent_basis_interpolates_its_nodes():
    rng = np.random.default_rng(0)
    controller = TentController(rng.uniform(0, 1, (A, 9)), 0.0, 2.0)
    np.testing.assert_allclose(controller(controller.node_times), controller.nodes.T)
    midpoint = 0.5 * (controller.node_times[3] + controller.node_times[4])
    np.testing.assert_allclose(controller(midpoint), controller.nodes[:, 3:5].mean(axis=1))


def test_control_energy_of_a_constant_controller_is_zero():
    controller = TentController(np.full((A, 11), 0.4), 0.0, 5.0)
    assert controller.control_energy(nu1=1.0, nu2=0.01) == 0.0
    np.testing.assert_array_equal(controller.derivative(np.linspace(0, 5, 7)), 0.0)


def test_actions_follow_the_controller_at_step_ends():
    controller = TentController(np.linspace(0, 1, 11)[None].repeat(A, 0), 0.0, 1.0)
    actions = controller.actions(dt=0.1, steps=10)
    np.testing.assert_allclose(actions[:, 0], 2 * np.linspace(0.1, 1.0, 10) - 1, atol=1e-6)


def _sinusoid(harmonic=3, period=2.0, nodes=65):
    t = np.linspace(0, period, nodes)
    values = [0.5 + 0.3 * np.sin(2 * np.pi * harmonic * t / period + phase)
              for phase in np.linspace(0, np.pi, A)]
    return TentController(np.array(values), 0.0, period)


def test_abstraction_of_a_sinusoid_keeps_one_coefficient_per_actuator_and_reconstructs():
    controller = _sinusoid()
    abstracted = abstract(controller, threshold=0.1)
    assert [len(h) for h in abstracted.harmonics] == [1] * A
    assert all(h[0] == 3 for h in abstracted.harmonics)
    nodes = controller.node_times
    np.testing.assert_allclose(abstracted(nodes), controller(nodes), atol=1e-12)
    t = np.linspace(0, 2.0, 200)  # between nodes the tent controller is the sine's chord
    np.testing.assert_allclose(abstracted(t), controller(t), atol=5e-3)
    later = abstracted(t + 2.0)  # periodic: playable at any duration
    np.testing.assert_allclose(later, abstracted(t), atol=1e-9)


def test_abstraction_round_trips_through_json():
    abstracted = abstract(_sinusoid(), threshold=0.05)
    again = AbstractController.from_dict(json.loads(json.dumps(abstracted.to_dict())))
    t = np.linspace(0, 5, 50)
    np.testing.assert_allclose(again(t), abstracted(t))
    assert again.num_parameters == abstracted.num_parameters == A + 2 * A


def test_frequency_parameters_round_trip_and_name_a_wrong_length():
    abstracted = abstract(_sinusoid(), threshold=0.05)
    vector = abstracted.frequency_parameters()
    assert vector.shape == (abstracted.num_parameters,)
    assert np.all((vector >= 0) & (vector <= 1))
    t = np.linspace(0, 3, 70)
    np.testing.assert_allclose(abstracted.with_frequency_parameters(vector)(t), abstracted(t),
                               atol=1e-12)
    moved = abstracted.with_frequency_parameters(np.where(np.arange(vector.size) < A, vector,
                                                          0.5))  # every harmonic zeroed
    np.testing.assert_allclose(moved(t), np.broadcast_to(abstracted.mean, (70, A)), atol=1e-12)
    with pytest.raises(ValueError, match="expected 18 frequency parameters"):
        abstracted.with_frequency_parameters(vector[:-1])


def test_full_abstraction_of_a_periodic_controller_has_its_parameter_count():
    values = np.random.default_rng(0).uniform(0, 1, (A, 20))  # Nyquist content included
    tent = TentController(np.concatenate([values, values[:, :1]], axis=1), 0.0, 1.0)
    whole = abstract(tent, threshold=0.0)
    assert whole.nyquist == 10 and whole.num_parameters == 120  # the 120 nodal values
    nodes = tent.node_times
    np.testing.assert_allclose(whole(nodes), tent(nodes), atol=1e-12)
    vector = whole.frequency_parameters()
    assert vector.shape == (120,)
    t = np.linspace(0, 3, 77)
    np.testing.assert_allclose(whole.with_frequency_parameters(vector)(t), whole(t), atol=1e-12)


@pytest.mark.parametrize("budget", [6, 7, 13, 25, 30, 119, 120])
def test_an_abstraction_within_a_parameter_budget_keeps_the_largest_harmonics_that_fit(budget):
    values = np.random.default_rng(0).uniform(0, 1, (A, 20))
    tent = TentController(np.concatenate([values, values[:, :1]], axis=1), 0.0, 1.0)
    within = abstract(tent, threshold=0.0, max_parameters=budget)
    assert within.num_parameters <= budget and within.num_parameters >= budget - 1
    whole = abstract(tent, threshold=0.0)
    amplitude = {(i, int(k)): abs(c) for i, (hs, cs) in enumerate(zip(whole.harmonics,
                                                                        whole.coefficients))
                 for k, c in zip(hs, cs)}
    kept = {(i, int(k)) for i, hs in enumerate(within.harmonics) for k in hs}
    dropped = set(amplitude) - kept
    if kept and dropped:  # none dropped is larger than a kept one of the same cost
        complex_kept = [amplitude[key] for key in kept if key[1] != 10]
        complex_dropped = [amplitude[key] for key in dropped if key[1] != 10]
        if complex_kept and complex_dropped:
            assert min(complex_kept) >= max(complex_dropped)


def test_a_mirrored_abstraction_of_a_turn_plays_it_exactly_and_holds_a_ramp_in_few_harmonics():
    """A controller that is not periodic (a turn over its window): with every harmonic the
    mirrored series plays the tent exactly where a player reads it (each env step's end); a
    ramp, whose end does not meet its start, needs far fewer harmonics mirrored than as a
    periodic series for the same error."""
    rng = np.random.default_rng(1)
    steps, t = 80, 0.05 * (np.arange(80) + 1)
    tent = TentController(rng.uniform(0, 1, (A, 21)), 0.0, 4.0)
    whole = abstract(tent, threshold=0.0, samples=steps, mirror=True)
    assert whole.period == 8.0
    np.testing.assert_allclose(whole(t), tent(t), atol=1e-12)
    ramp = TentController(np.tile(np.linspace(0.1, 0.9, 21), (A, 1)), 0.0, 4.0)
    errors = {}
    for mirror in (False, True):
        few = abstract(ramp, threshold=0.0, samples=steps, max_parameters=A + 2 * A * 3,
                       mirror=mirror)  # three harmonics an actuator
        errors[mirror] = np.abs(few(t) - ramp(t)).max()
    assert errors[True] < 0.03 < 0.3 < errors[False], errors  # measured: 0.027, 0.365


def test_abstraction_rejects_bad_threshold():
    with pytest.raises(ValueError, match="threshold"):
        abstract(_sinusoid(), threshold=1.5)


def test_schedule_overlaps_five_percent():
    starts, blends = schedule([2.0, 4.0, 1.0])
    np.testing.assert_allclose(blends, [0.1, 0.05])
    np.testing.assert_allclose(starts, [0.0, 1.9, 5.85])


def _swim_like(hz, phase, period=1.0, nodes=129):
    t = np.linspace(0, period, nodes)
    row = 0.5 + 0.5 * np.sin(2 * np.pi * hz * t + phase)
    return abstract(TentController(np.repeat(row[None], A, axis=0), 0.0, period))


def test_concatenation_seam_has_no_jump_larger_than_the_controllers_own_steps():
    dt = 0.05
    first = _swim_like(3.0, -np.pi / 2)  # ends at its trough (0) after 4 s
    second = _swim_like(2.0, np.pi / 2)  # starts at its peak (1)
    blended, total = concatenate([first, second], [4.0, 4.0])  # blend: 0.2 s = 4 steps
    t = np.arange(0, total, dt)
    jumps = np.abs(np.diff(blended(t), axis=0)).max()
    own = max(np.abs(np.diff(c(np.arange(0, 4, dt)), axis=0)).max() for c in (first, second))
    assert jumps <= own + 1e-9
    unblended = np.where(t[:, None] < 4.0, first(t), second(t - 4.0))
    assert np.abs(np.diff(unblended, axis=0)).max() > own  # without blending there is a jump
