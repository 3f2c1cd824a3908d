"""Hand-designed motor controllers driving the fish env, each calibrated for its water (the
default reactive water and the paper's resistive one): the figures of the issue."""

import numpy as np
import pytest

from animat.envs.core.env import BodyEnv
from animat.envs.motor.fish import (
    FinParams,
    calibrated,
    fin_mc,
    swim_mc,
    to_action,
    turn_duration,
    turn_mc,
)
from animat.envs.physics.system import WATER_MODELS

waters = pytest.mark.parametrize("model", WATER_MODELS)


def _env(task: str, model: str, **kwargs) -> BodyEnv:
    """The task's env from rest (the point start): the MCs' calibration."""
    return BodyEnv(task, water={"model": model}, start_spread="point", **kwargs)


def _run(env, actuation, seconds, fins=None):
    """Play ``actuation``; with ``fins`` (2,) rad, in an env made with ``fins=True``, hold those
    fin angles through the action space."""
    env.reset(seed=0)
    infos = []
    for k in range(int(round(seconds / env.dt))):
        action = to_action(actuation((k + 1) * env.dt))
        if fins is not None:
            action = np.append(action, fins / FinParams().max_angle).astype(np.float32)
        infos.append(env.step(action)[4])
    return infos


@waters
def test_swim_mc_swims_head_first_and_holds_heading(model):
    env, swim = _env("swim", model, duration=10.0), calibrated(model)[0]
    infos = _run(env, lambda t: swim_mc(1.0, t, swim), 10.0)
    com = np.array([i["com"] for i in infos])
    per_second = int(round(1.0 / env.dt))
    travel = np.diff(np.concatenate([[com[0]], com[per_second - 1::per_second]]), axis=0)
    direction = np.degrees(np.arctan2(travel[:, 1], travel[:, 0]))  # heading of each second
    speed = np.linalg.norm(com[-1, :2] - com[2 * per_second, :2]) / 8.0 / env.body_length
    assert speed >= 0.5, speed
    assert infos[-1]["forward"] @ (com[-1] - com[0]) > 0  # head first
    # once under way (the ease-in takes 1.25 s, and the first second's few mm go where the
    # first strokes push), every second's travel is within 3 deg of +x
    assert np.all(np.abs(direction[1:]) < 3.0), direction


@waters
def test_swim_speed_grows_with_the_speed_parameter(model):
    speeds, swim = [], calibrated(model)[0]
    for s in (0.3, 0.6, 1.0):
        infos = _run(_env("swim", model, duration=6.0), lambda t, s=s: swim_mc(s, t, swim), 6.0)
        speeds.append(infos[-1]["distance_bl"])
    assert speeds[0] < speeds[1] < speeds[2]


@waters
@pytest.mark.parametrize("left", [True, False])
def test_turn_mc_ends_within_10_degrees_of_90_and_holds_it(model, left):
    sign, turn = (1.0 if left else -1.0), calibrated(model)[1]
    infos = _run(_env("turn", model, duration=6.0),
                 lambda t: turn_mc(np.pi / 2, t, left, turn), 6.0)
    headings = sign * np.array([i["heading_deg"] for i in infos])
    end = int(round(turn_duration(np.pi / 2, turn) / 0.05)) - 1
    assert abs(headings[end] - 90.0) <= 10.0, headings[end]
    assert headings[end:].max() - headings[-1] <= 10.0  # no glide back of more than 10 deg


@waters
@pytest.mark.parametrize("left", [True, False])
def test_turn_angle_grows_with_the_parameter(model, left):
    sign, reached, turn = (1.0 if left else -1.0), [], calibrated(model)[1]
    for degrees in (30.0, 60.0, 90.0, 120.0):
        angle = np.radians(degrees)
        infos = _run(_env("turn", model, duration=5.0),
                     lambda t, a=angle: turn_mc(a, t, left, turn), turn_duration(angle, turn))
        reached.append(sign * infos[-1]["heading_deg"])  # when the controller has finished
    assert 0 < reached[0] < reached[1] < reached[2] < reached[3], reached


@waters
@pytest.mark.parametrize("pitch", [1.0, -1.0])
def test_fin_pitch_changes_depth_in_the_commanded_direction(model, pitch):
    env, swim = _env("swim", model, duration=6.0, fins=True), calibrated(model)[0]
    infos = _run(env, lambda t: swim_mc(1.0, t, swim), 6.0, fins=fin_mc(pitch=pitch))
    depth_change = infos[-1]["com"][2] - infos[0]["com"][2]
    assert np.sign(depth_change) == np.sign(pitch)
    assert abs(depth_change) > 0.05 * env.body_length


@waters
@pytest.mark.parametrize("roll", [1.0, -1.0])
def test_fin_roll_rolls_the_fish_to_the_commanded_side(model, roll):
    """The fish leans to the commanded side (positive roll: to the right) before anything else:
    the first lean past 3 deg is that way. Held for 6 s, the resistive water leans it 5 deg; the
    reactive water, where the fish swims three times as fast, rolls it over (49 deg at 2 s)."""
    env, swim = _env("swim", model, duration=6.0, fins=True), calibrated(model)[0]
    env.reset(seed=0)
    leans = []
    for k in range(int(round(6.0 / env.dt))):
        action = np.append(to_action(swim_mc(1.0, (k + 1) * env.dt, swim)),
                           fin_mc(roll=roll) / FinParams().max_angle).astype(np.float32)
        env.step(action)
        forward, _, up = env.core.kinematics().frames[0]  # the body's axes, world frame
        left = np.cross([0.0, 0.0, 1.0], forward)
        leans.append(np.degrees(np.arctan2(-(up @ left) / np.linalg.norm(left), up[2])))
    leans = np.array(leans)
    first = np.flatnonzero(np.abs(leans) > 3.0)
    assert first.size and np.sign(leans[first[0]]) == np.sign(roll), leans[::10]


def test_controllers_reject_out_of_range_parameters():
    with pytest.raises(ValueError, match="swim speed"):
        swim_mc(1.5, 0.0)
    with pytest.raises(ValueError, match="turn angle"):
        turn_mc(-0.1, 0.0)
    with pytest.raises(ValueError, match="fin pitch"):
        fin_mc(pitch=2.0)


def test_the_navigator_takes_the_motor_controllers_calibrated_for_its_water():
    from animat.envs.motor.fish import (
        PAPER_SWIM,
        PAPER_TURN,
        REACTIVE_SWIM,
        REACTIVE_TURN,
        SwimParams,
        TurnParams,
    )
    from animat.envs.motor.navigation import NavigationParams, navigation_for
    from animat.envs.physics.system import Water
    reactive = navigation_for(Water(model="reactive"))
    assert reactive.swim == REACTIVE_SWIM and reactive.turn == REACTIVE_TURN
    assert navigation_for(Water()) == reactive == NavigationParams()  # the default water's
    assert (SwimParams(), TurnParams()) == (REACTIVE_SWIM, REACTIVE_TURN) == calibrated("reactive")
    resistive = navigation_for(Water(model="resistive"))
    assert (resistive.swim, resistive.turn) == (PAPER_SWIM, PAPER_TURN) == calibrated("resistive")
    with pytest.raises(ValueError, match="no motor controllers are calibrated"):
        calibrated("viscous")
