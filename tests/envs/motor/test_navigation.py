"""The navigator: a swim whose speed changes keeps its tail beat's phase."""

import numpy as np

from animat.envs.motor.fish import SwimParams, swim_mc, to_action
from animat.envs.motor.navigation import Navigator

DT = 0.05  # s, an env step


def _actuations(speeds: np.ndarray) -> np.ndarray:
    """(T, 6) the navigator's actuations for one fish swimming at ``speeds`` (T,), no turn."""
    navigator = Navigator(1)
    commands = [np.array([[speed, 0.0, 0.0]]) for speed in speeds]
    return np.array([navigator.actions(c, (k + 1) * DT)[0, :6]
                     for k, c in enumerate(commands)])


def test_a_steady_swim_is_the_swim_mc_at_the_time_since_it_began():
    u = _actuations(np.full(200, 0.6))
    t = np.arange(1, 201) * DT
    assert np.array_equal(u, to_action(swim_mc(0.6, t, SwimParams())).astype(np.float32))


def test_a_change_of_speed_keeps_the_phase_of_the_tail_beat():
    """At 10 s a change of speed by 0.01 (0.02 Hz) would jump the phase of the swim-MC played at
    the time since the swim began by 0.2 cycles; the navigator's actuations move no more at the
    change than between any two steps of the steady swim."""
    speeds = np.where(np.arange(400) < 200, 0.6, 0.61)
    u = _actuations(speeds)
    steady = np.abs(np.diff(u[100:200], axis=0)).max()
    assert np.abs(u[200] - u[199]).max() <= 1.05 * steady
    jumped = to_action(swim_mc(0.61, 201 * DT)) - to_action(swim_mc(0.6, 200 * DT))
    assert np.abs(jumped).max() > 2.0 * steady  # what the change did before
    beats = np.diff(np.sign(u[:, 1] - u[:, 4]))  # the middle segment's left minus right
    assert np.count_nonzero(beats) >= 2 * (0.6 * 2.0 + 1.0) * 19  # no beat lost: ~2.2 Hz x 20 s
