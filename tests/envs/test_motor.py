"""Hand-designed motor controllers driving the fish env: the figures of the issue."""

import numpy as np
import pytest

from envs.fish_env import FishEnv
from envs.motor import fin_mc, swim_mc, to_action, turn_mc


def _run(env, actuation, seconds, fins=None):
    env.reset(seed=0)
    infos = []
    for k in range(int(round(seconds / env.dt))):
        if fins is not None:
            env.core.fins[0] = fins
        infos.append(env.step(to_action(actuation((k + 1) * env.dt)))[4])
    return infos


def test_swim_mc_swims_head_first_and_holds_heading():
    env = FishEnv("swim", duration=10.0)
    infos = _run(env, lambda t: swim_mc(1.0, t), 10.0)
    com = np.array([i["com"] for i in infos])
    per_second = int(round(1.0 / env.dt))
    travel = com[2 * per_second:, :2][::per_second]
    steps = np.diff(travel, axis=0)
    speed = np.linalg.norm(travel[-1] - travel[0]) / (len(steps)) / env.body_length
    direction = np.degrees(np.arctan2(steps[:, 1], steps[:, 0]))
    forward = infos[-1]["forward"]
    assert speed >= 0.5, speed
    assert forward @ (com[-1] - com[0]) > 0  # head first
    assert np.ptp(direction) < 5.0, direction  # heading held once under way


def test_swim_speed_grows_with_the_speed_parameter():
    speeds = []
    for s in (0.3, 0.6, 1.0):
        infos = _run(FishEnv("swim", duration=6.0), lambda t, s=s: swim_mc(s, t), 6.0)
        speeds.append(infos[-1]["distance_bl"])
    assert speeds[0] < speeds[1] < speeds[2]


@pytest.mark.parametrize("left", [True, False])
def test_turn_mc_turns_to_the_commanded_side_more_for_larger_angles(left):
    headings = []
    for angle in (90.0, 135.0):
        infos = _run(FishEnv("turn", duration=5.0),
                     lambda t, a=angle: turn_mc(np.radians(a), t, left), 5.0)
        headings.append(infos[-1]["heading_deg"] * (1 if left else -1))
    assert 0 < headings[0] < headings[1]


@pytest.mark.parametrize("pitch", [1.0, -1.0])
def test_fin_pitch_changes_depth_in_the_commanded_direction(pitch):
    env = FishEnv("swim", duration=6.0)
    infos = _run(env, lambda t: swim_mc(1.0, t), 6.0, fins=fin_mc(pitch=pitch))
    depth_change = infos[-1]["com"][2] - infos[0]["com"][2]
    assert np.sign(depth_change) == np.sign(pitch)
    assert abs(depth_change) > 0.05 * env.body_length


def test_controllers_reject_out_of_range_parameters():
    with pytest.raises(ValueError, match="swim speed"):
        swim_mc(1.5, 0.0)
    with pytest.raises(ValueError, match="turn angle"):
        turn_mc(-0.1, 0.0)
    with pytest.raises(ValueError, match="fin pitch"):
        fin_mc(pitch=2.0)
