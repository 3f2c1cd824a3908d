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


def _scalar_actions(navigator, commands, time, forward):
    """One fish's actions from its state, by the scalar motor controllers (the reference the
    batched navigator must equal): the turn over, a new turn, else the swim."""
    from animat.envs.motor.fish import FinParams, fin_mc, turn_duration, turn_mc

    speed, turn, pitch = (min(max(float(c), low), 1.0) for c, low in zip(commands, (0, -1, -1)))
    n, p = navigator, navigator.params
    if n.kind[0] != 0 and time - n.start[0] >= turn_duration(float(n.angle[0]), p.turn):
        n.kind[0], n.start[0], n.speed[0] = 0, time, np.nan
    if n.kind[0] == 0 and abs(turn) > p.turn_threshold:
        n.kind[0], n.start[0] = (1 if turn > 0 else -1), time
        n.angle[0], n.speed[0], n.turn_from[0] = abs(turn) * p.max_turn, np.nan, forward
    if n.kind[0] == 0:
        if n.speed[0] != speed:
            if np.isnan(n.speed[0]):
                n.beats[0], n.since[0] = 0.0, n.start[0]
            else:
                n.beats[0] += n._hz(float(n.speed[0])) * (time - n.since[0])
                n.since[0] = time
            n.speed[0] = speed
        played = n.beats[0] / n._hz(speed) + (time - n.since[0])
        u = swim_mc(speed, played, p.swim)
    else:
        u = turn_mc(float(n.angle[0]), time - n.start[0], bool(n.kind[0] > 0), p.turn,
                    float(n.turn_from[0]))
    return np.concatenate([to_action(u), fin_mc(pitch=pitch) / FinParams().max_angle])


def test_the_batched_navigator_is_each_fish_by_the_scalar_motor_controllers():
    rng = np.random.default_rng(4)
    fish, batch = 12, Navigator(12)
    alone = [Navigator(1) for _ in range(fish)]
    for step in range(300):
        time = step * 0.05
        commands = rng.uniform([-0.2, -1.2, -1.2], [1.2, 1.2, 1.2], (fish, 3))
        commands[:, 1] *= rng.random(fish) < 0.1  # a turn now and then, swims between
        forward = rng.uniform(-1, 3, fish)
        got = batch.actions(commands, time, forward=forward)
        want = [_scalar_actions(alone[k], commands[k], time, forward[k]) for k in range(fish)]
        assert np.array_equal(got, np.array(want, np.float32)), step
    assert (batch.kind != 0).any() and (batch.kind == 0).any()


def test_a_command_that_is_not_a_number_is_refused_before_any_fish_changes():
    navigator = Navigator(3)
    navigator.actions(np.full((3, 3), 0.5), 0.0)
    before = [a.copy() for a in (navigator.kind, navigator.start, navigator.speed)]
    commands = np.full((3, 3), 0.5)
    commands[2, 0] = np.nan
    try:
        navigator.actions(commands, 0.05)
    except ValueError as error:
        assert "must be finite" in str(error)
    else:
        raise AssertionError("a NaN command was taken")
    assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(
        before, (navigator.kind, navigator.start, navigator.speed)))
