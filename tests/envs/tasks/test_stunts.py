"""The dolphin's Gymnasium tasks: the envs' contracts, the stunts' scores, and the beach ball
(stays on its support until touched; knows what touched it). The native vector env's match
with single envs is tested with the fish's (``tests/envs/core/test_envs.py``)."""


import gymnasium as gym
import numpy as np
import pytest

from animat.envs.bodies.spec import NOSE_PART
from animat.envs.motor.dolphin import dolphin_calibrated, dolphin_swim_mc, dolphin_turn_mc
from animat.envs.motor.fish import to_action
from animat.envs.registration import DOLPHIN_ENVS

DOLPHIN_IDS = sorted(DOLPHIN_ENVS)


def _swim(k: int) -> np.ndarray:
    return to_action(dolphin_swim_mc(1.0, (k + 1) * 0.05))


@pytest.mark.parametrize("env_id", DOLPHIN_IDS)
def test_the_dolphin_s_scale_reward_and_pool_view(env_id):
    """(The checkers and the common contract: tests/envs/test_contract.py.)"""
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    assert env.unwrapped.dt == pytest.approx(0.05)
    assert env.unwrapped.body_length == pytest.approx(2.5)
    _, reward, _, _, info = env.step(env.action_space.sample())
    assert info["com"].shape == (3,) and info["forward"].shape == (3,)
    assert reward == pytest.approx(info["reward_ctrl"] + info["reward_task"])
    frame = env.render()
    assert frame.shape == (360, 480, 3)
    sky, water = frame[5].mean(axis=0), frame[-5].mean(axis=0)
    assert sky[2] > 200 and water[2] < sky[2] - 40  # the sky above, the water below


def test_random_actions_on_the_batch_stay_finite():
    vec = gym.make_vec("Animat/DolphinNoseBall-v0", num_envs=32)
    obs, _ = vec.reset(seed=0)
    rng = np.random.default_rng(0)
    for _ in range(200):
        obs, reward, _, _, info = vec.step(rng.uniform(-1, 1, (32, 6)).astype(np.float32))
        assert np.isfinite(obs).all() and np.isfinite(reward).all()
        assert all(np.isfinite(np.asarray(v, float)).all() for v in info.values())


@pytest.mark.parametrize("model", ["reactive", "resistive"])
def test_a_leaps_return_pays_out_its_apex_and_the_metrics_follow_the_flight(model):
    """The hand fluke stroke (calibrated for the water) from 80 degrees up: measured, apex
    0.59 BL and 67 degrees turned in the flight (reactive), 0.67 and 100 (resistive, back in
    nose down; the reactive water's gentler stroke leaves the water with less spin and
    comes back in at +18 degrees)."""
    env = gym.make("Animat/DolphinLeap-v0", start_pitch_deg=80.0, water={"model": model})
    env.reset(seed=0)
    swim = dolphin_calibrated(model).swim
    heights, task = [], 0.0
    for k in range(env.unwrapped.episode_steps):
        _, _, _, _, info = env.step(to_action(dolphin_swim_mc(1.0, (k + 1) * 0.05, swim)))
        heights.append(info["height_bl"])
        task += info["reward_task"]
    assert info["apex_height_bl"] == pytest.approx(max(heights)) and max(heights) > 0.5
    assert task == pytest.approx(max(heights) - heights[0])  # S_T - S_1 (mu2 = 1)
    assert info["airborne"] == 1.0
    if model == "resistive":
        assert info["entry_pitch_deg"] < 0  # back in nose down
    assert -300 < info["rotation_deg"] < -45  # the arc of its flight turned it nose down
    assert info["reentry_splash"] > 0


def test_the_somersault_counts_the_pitch_turned_above_the_surface():
    """A dolphin thrown up spinning, 2 m above the water (its nodes set in motion by hand):
    over the 0.6 s before any of it nears the water, the rotation counted is the spin times
    the time, within the flex of a relaxed body."""
    env = gym.make("Animat/DolphinSomersault-v0", start_depth=-2.0).unwrapped
    env.reset(seed=0)
    core = env.core
    x = core.state.x[0]
    com = core.body.masses @ x / core.body.total_mass
    spin = np.array([0.0, -2.0 * np.pi, 0.0])  # one turn per second, nose up
    core.state.v[0] = np.array([0.0, 0.0, 2.0]) + np.cross(spin, x - com)
    for _ in range(12):
        _, _, _, _, info = env.step(-np.ones(6, np.float32))
        assert core.state.x[0, :, 2].min() > 0.5  # in flight
    assert info["rotation_deg"] == pytest.approx(360.0 * 12 * env.dt, rel=0.02)
    assert info["flight_rotation_deg"] == pytest.approx(info["rotation_deg"])
    assert info["score"] == pytest.approx(info["flight_rotation_deg"] / 360.0)


def test_a_somersault_is_one_flights_turn_not_the_sum_of_several_leaps():
    """Two flights that each turn 0.3 of a circle score 0.3 turns, not 0.6: the memory
    keeps each flight's rotation and the best of them."""
    from animat.envs.bodies import make_body
    from animat.envs.tasks.stunts import ROTATION, SomersaultTask, World

    task, body = SomersaultTask(), make_body("dolphin")
    memory = np.tile(task.initial_memory(), (1, 1))
    turn, steps = 0.3 * 2.0 * np.pi, 10
    flights = [(1.0, turn / steps)] * steps + [(-1.0, 0.0)] * 3 + [(1.0, turn / steps)] * steps
    for height, angle in flights:
        a = np.radians(0.0) + memory[0, ROTATION] + angle  # the heading pitched up by it
        frames = np.array([[[np.cos(a), 0.0, np.sin(a)], [0.0, 1.0, 0.0],
                            [-np.sin(a), 0.0, np.cos(a)]]])
        position = np.array([[0.0, 0.0, height]])
        world = World(com=position, com_vel=np.zeros((1, 3)), frames=frames, targets=None,
                      length=2.5, position=position, x=None, v=None, splash=np.zeros(1),
                      memory=memory, ball=None, touch=None, surface_z=0.0, body=body,
                      dt=0.05, start_yaw=np.zeros(1))
        _, metrics, memory = task.terms(world, np.zeros(1, bool))
    assert metrics["rotation_deg"][0] == pytest.approx(216.0, rel=1e-6)
    assert metrics["flight_rotation_deg"][0] == pytest.approx(108.0, rel=1e-6)
    assert metrics["score"][0] == pytest.approx(0.3, rel=1e-6)


def _flight(task, heights_pitches_rolls):
    """The last step's metrics of ``task`` over a flight given step by step as (height of the
    centre of mass, m; rotation about the lateral axis, nose up, deg, any angle; then roll
    about the forward axis, deg)."""
    from animat.envs.bodies import make_body
    from animat.envs.tasks.stunts import World

    body, memory = make_body("dolphin"), np.tile(task.initial_memory(), (1, 1))
    for height, pitch, roll in heights_pitches_rolls:
        p, r = np.radians(pitch), np.radians(roll)
        forward = np.array([np.cos(p), 0.0, np.sin(p)])
        level_left, level_up = np.array([0.0, 1.0, 0.0]), np.array([-np.sin(p), 0.0, np.cos(p)])
        left = np.cos(r) * level_left + np.sin(r) * level_up  # rolled: the left side up
        up = np.cross(forward, left)
        position = np.array([[0.0, 0.0, height]])
        world = World(com=position, com_vel=np.zeros((1, 3)),
                      frames=np.array([[forward, left, up]]), targets=None, length=2.5,
                      position=position, x=None, v=None, splash=np.zeros(1), memory=memory,
                      ball=None, touch=None, surface_z=0.0, body=body, dt=0.05,
                      start_yaw=np.zeros(1))
        _, metrics, memory = task.terms(world, np.zeros(1, bool))
    return metrics


@pytest.mark.parametrize("apex, pitch, roll, leap, flop", [
    (1.5, 0.0, 0.0, 1, 1), (1.0, 0.0, 0.0, 0, 1), (1.5, -30.0, 0.0, 1, 0),
    (1.5, 15.0, 40.0, 1, 1), (1.5, 0.0, -60.0, 1, 0), (1.5, 0.0, 180.0, 1, 0)])
def test_a_leap_clears_half_a_body_length_and_a_belly_flop_enters_belly_first(
        apex, pitch, roll, leap, flop):
    """is_success of a leap: its apex (m, of a 2.5 m dolphin) at least 0.5 BL; of a belly
    flop: the re-entry within 20 deg of level in pitch and 45 deg in roll, the entry's pitch and
    roll reported (the roll positive with the left side up)."""
    from animat.envs.tasks.stunts import BellyFlopTask, LeapTask

    flight = [(-1.0, 0.0, 0.0), (apex, 0.0, 0.0), (0.2, pitch, roll), (-0.5, pitch, roll)]
    leaped, flopped = _flight(LeapTask(), flight), _flight(BellyFlopTask(), flight)
    assert leaped["is_success"][0] == leap and flopped["is_success"][0] == flop
    assert flopped["entry_pitch_deg"][0] == pytest.approx(pitch, abs=1e-9)
    assert abs(flopped["entry_roll_deg"][0]) == pytest.approx(abs(roll), abs=1e-9)
    assert np.sign(flopped["entry_roll_deg"][0]) == np.sign(roll) or abs(roll) == 180.0


def test_a_flat_weight_takes_the_reentrys_tilt_off_the_belly_flops_score():
    """flat_weight w: S less w (|pitch| / 90 + |roll| / 180) once back in; the largest tilt
    (2) before, so that never re-entering is not flatter."""
    from animat.envs.tasks.stunts import BellyFlopTask

    flight = [(-1.0, 0.0, 0.0), (1.5, 0.0, 0.0), (0.2, -30.0, 60.0), (-0.5, -30.0, 60.0)]
    plain, flat = _flight(BellyFlopTask(), flight), _flight(BellyFlopTask(flat_weight=6.0), flight)
    assert flat["score"][0] == pytest.approx(plain["score"][0] - 6.0 * (30 / 90 + 60 / 180))
    airborne = flight[:2]
    assert _flight(BellyFlopTask(flat_weight=6.0), airborne)["score"][0] == pytest.approx(
        _flight(BellyFlopTask(), airborne)["score"][0] - 6.0 * 2.0)
    with pytest.raises(ValueError, match="flat_weight must be"):
        BellyFlopTask(flat_weight=101.0)


@pytest.mark.parametrize("turned, success", [(350.0, 0), (370.0, 1)])
def test_a_somersault_is_done_when_one_flight_turns_a_full_circle(turned, success):
    from animat.envs.tasks.stunts import SomersaultTask

    steps = 36
    flight = [(-1.0, 0.0, 0.0)] + [(1.0, k * turned / steps, 0.0) for k in range(1, steps + 1)]
    metrics = _flight(SomersaultTask(), flight)  # the frames rotate about the lateral axis
    assert metrics["flight_rotation_deg"][0] == pytest.approx(turned, abs=1e-6)
    assert metrics["is_success"][0] == success


def test_the_ball_stays_on_its_support_until_touched_then_knows_the_nose_hit_it():
    env = gym.make("Animat/DolphinNoseBall-v0", duration=10.0, start_spread="point").unwrapped
    env.reset(seed=0)
    rest = env.core.ball.rest.copy()
    for _ in range(200):  # 10 s with the dolphin relaxed 3 m down
        _, _, _, _, info = env.step(-np.ones(6, np.float32))
    assert np.abs(env.core.state.ball[0, :3] - rest).max() < 1e-3
    assert info["first_touch"] == -1 and info["ball_off"] == 0 and info["ball_hit"] == 0
    env = gym.make("Animat/DolphinNoseBall-v0", start_pitch_deg=80.0, ball_x=1.0, ball_y=0.0,
                   ball_height=1.2, start_spread="point").unwrapped
    env.reset(seed=0)
    for k in range(env.episode_steps):
        _, _, _, _, info = env.step(_swim(k))
    assert info["first_touch"] == NOSE_PART and info["ball_off"] == 1 and info["ball_hit"] == 1
    assert info["ball_rise_bl"] * env.core.body.length >= 0.1 and info["is_success"] == 1
    ball = env.core.state.ball[0]
    assert abs(ball[2] - env.core.ball.radius) < 0.05 and np.abs(ball[3:]).max() < 0.5  # floats


@pytest.mark.parametrize("model", ["reactive", "resistive"])
def test_turn_tasks_measure_pitch_and_yaw_and_the_hand_mcs_turn_the_right_way(model):
    """45 degrees each way by the hand MCs calibrated for the water: the pitch or heading at
    its most over the 4 s episode is on the commanded side (a pitch up rights itself after
    the strokes: the lungs' buoyancy)."""
    calibration = dolphin_calibrated(model)
    for direction, key, sign in (("up", "pitch_deg", 1), ("down", "pitch_deg", -1),
                                 ("left", "heading_deg", 1), ("right", "heading_deg", -1)):
        env = gym.make("Animat/DolphinTurn-v0", direction=direction, water={"model": model})
        env.reset(seed=0)
        turned = []
        for k in range(env.unwrapped.episode_steps):
            _, _, _, _, info = env.step(to_action(dolphin_turn_mc(
                direction, np.radians(45.0), (k + 1) * 0.05, calibration)))
            turned.append(sign * info[key])
        assert max(turned) > 10, (direction, max(turned))
    with pytest.raises(ValueError, match="direction"):
        gym.make("Animat/DolphinTurn-v0", direction="sideways")


def test_a_start_at_speed_glides_along_the_pitched_heading_and_bad_speeds_are_refused():
    env = gym.make("Animat/DolphinArc-v0", start_speed=4.0, start_pitch_deg=30.0,
                   start_spread="point")
    env.reset(seed=0)
    core = env.unwrapped.core
    heading = np.array([np.cos(np.radians(30.0)), 0.0, np.sin(np.radians(30.0))])
    assert np.allclose(core.state.v[0], 4.0 * heading)
    _, _, _, _, info = env.step(-np.ones(6, dtype=np.float32))  # relaxed: a glide
    assert 3.0 < info["linear_momentum"] @ heading / core.body.total_mass < 4.0
    for bad in (-1.0, float("nan")):
        with pytest.raises(ValueError, match="start_speed"):
            gym.make("Animat/DolphinArc-v0", start_speed=bad)


def test_the_arc_pays_the_speed_round_its_circle():
    """E_v = -u_arc: the full speed on the circle's tangent, none moving along the radius,
    and a straight swim from the circle's top makes ever less of its speed."""
    from animat.envs.tasks.base import World
    from animat.envs.tasks.dolphin import DolphinArcTask

    length, radius = 2.5, 2.0 * 2.5
    frames = np.tile(np.eye(3), (3, 1, 1))
    for direction, centre_z in (("down", -radius), ("up", radius)):
        task = DolphinArcTask(direction=direction, radius_bl=2.0)
        angle = np.radians(40.0)  # a point 40 deg round the circle from the start
        sign = -np.sign(centre_z)
        on_circle = np.array([radius * np.sin(angle), 0.0,
                              centre_z + sign * radius * np.cos(angle)])
        tangent = np.array([np.cos(angle), 0.0, -sign * np.sin(angle)])
        com = np.stack([on_circle, on_circle, [3.0 * radius, 0.0, 0.0]])
        vel = np.stack([2.0 * tangent, 2.0 * (on_circle - [0.0, 0.0, centre_z]) / radius,
                        [2.0, 0.0, 0.0]])
        world = World(com=com, com_vel=vel, frames=frames, targets=None, length=length,
                      position=None, x=None, v=None, splash=None, memory=np.zeros((3, 0)),
                      ball=None, touch=None, surface_z=0.0, body=None, dt=0.05,
                      start_yaw=np.zeros(3))
        e_v, metrics, _ = task.terms(world, None)
        assert e_v[0] == pytest.approx(-2.0 / length), direction
        assert e_v[1] == pytest.approx(0.0, abs=1e-12), direction
        assert -2.0 / length < e_v[2] < -0.2 / length, direction  # straight on: a fraction
        assert np.allclose(metrics["arc_speed_bl_per_s"], -e_v)
    with pytest.raises(ValueError, match="radius_bl"):
        DolphinArcTask(radius_bl=0.0)
    with pytest.raises(ValueError, match="direction"):
        DolphinArcTask(direction="left")


def test_the_spin_pays_the_bodys_pitch_rate_whatever_it_moves_along():
    """A body turning rigidly nose-up at w rad/s about its centre of mass, and gliding, has a
    pitch rate of w (signed by the direction asked for); a glide alone has none."""
    from animat.envs.bodies import make_body
    from animat.envs.tasks.dolphin import DolphinSpinTask
    from animat.envs.tasks.stunts import World

    body = make_body("dolphin")
    x = body.rest_positions - body.masses @ body.rest_positions / body.total_mass
    w = 2.0  # rad/s nose up: about -y (forward +x, left +y)
    spin = np.cross(np.array([0.0, -w, 0.0]), x)
    glide = np.array([1.5, 0.0, -0.5])
    v = np.stack([spin + glide, np.broadcast_to(glide, x.shape)])
    world = World(com=None, com_vel=None, frames=np.tile(np.eye(3), (2, 1, 1)), targets=None,
                  length=2.5, position=np.array([[0.0, 0.0, -3.0]] * 2),
                  x=np.stack([x, x]) + [0.0, 0.0, -3.0], v=v,
                  splash=np.zeros(2), memory=np.zeros((2, 0)), ball=None, touch=None,
                  surface_z=0.0, body=body, dt=0.05, start_yaw=np.zeros(2))
    for direction, sign in (("up", 1.0), ("down", -1.0)):
        e_v, metrics, _ = DolphinSpinTask(direction=direction).terms(world, None)
        assert e_v == pytest.approx([-sign * w, 0.0], abs=1e-12)
        assert metrics["spin_deg_per_s"] == pytest.approx([sign * np.degrees(w), 0.0],
                                                          abs=1e-9)
    with pytest.raises(ValueError, match="direction"):
        DolphinSpinTask(direction="left")
