"""The dolphin and its air-water world, by invariants: neutral at its depth, Boyle's lungs
above and below it, free fall with g, a ballistic flight that is a parabola with its angular
momentum kept, floating back up after a plunge, a belly flop that splashes more than a dive,
tissue within limits, and a leap that does not move when the step is halved."""

import numpy as np
import pytest

from animat.envs.bodies.dolphin import ACTUATOR_NAMES, LEFT_TIP, RIGHT_TIP, dolphin_body
from animat.envs.core.batch import BodyBatch
from animat.envs.motor.dolphin import dolphin_calibrated, dolphin_swim_mc, dolphin_turn_mc
from animat.envs.motor.fish import to_action, turn_duration
from animat.envs.physics.integrator import step_batch
from animat.envs.physics.observe import momenta
from animat.envs.physics.system import System, Water, stable_step
from animat.envs.registration import DOLPHIN_KWARGS
from animat.envs.tasks.dolphin import DolphinForwardTask
from animat.envs.tasks.stunts import LeapTask
from animat.experiments.biology import dolphin_cruise

G = 9.81
BODY = dolphin_body()
WATER = DOLPHIN_KWARGS["base_water"]
STEP, SKIP = DOLPHIN_KWARGS["physics_dt"], DOLPHIN_KWARGS["frame_skip"]


def _core(task, num_envs=1, physics_dt=STEP, frame_skip=SKIP, water=None, noise=0.0):
    core = BodyBatch(num_envs, task, body=BODY, water=water or WATER, physics_dt=physics_dt,
                     start_spread="point",
                     frame_skip=frame_skip, duration=120.0, reset_noise_scale=noise)
    core.reset_rows(np.arange(num_envs), [np.random.default_rng(k) for k in range(num_envs)])
    return core


def _heights(core, seconds, actions=None):
    """CoM heights (T, B), m, holding the muscles relaxed (or playing ``actions`` (T, 6))."""
    out = []
    for k in range(int(round(seconds / core.dt))):
        a = -np.ones((core.num_envs, 6)) if actions is None else actions[k][None]
        out.append(core.step(a)[1]["com"][:, 2].copy())
    return np.array(out)


def test_the_dolphin_is_the_fish_topology_with_horizontal_flukes_and_dorsoventral_muscles():
    assert (BODY.num_nodes, BODY.num_elements, BODY.num_muscles) == (23, 91, 12)
    assert BODY.actuator_names == ACTUATOR_NAMES and BODY.length == 2.5
    assert 150.0 < BODY.total_mass < 200.0  # a 2.5 m bottlenose
    tips = BODY.rest_positions[[LEFT_TIP, RIGHT_TIP]]
    assert np.allclose(tips[:, 2], 0.0) and tips[0, 1] == -tips[1, 1] > 0.25  # flukes span y
    for name in ("dorsal_middle", "dorsal_back"):  # dorsal muscles run along the upper side
        nodes = BODY.elements[BODY.actuator == ACTUATOR_NAMES.index(name)]
        assert np.all(BODY.rest_positions[nodes, 2] > 0)
    assert STEP <= 0.75 * stable_step(BODY)


def test_the_dolphin_s_sections_carry_water_for_vertical_motion_each_about_its_own_left():
    """Head to tail: the nose, five rings and the flukes; at rest every section's axis across
    its plane of undulation is the body's left, and so its normal is up."""
    assert BODY.section_nodes.shape[0] == 7
    rest = BODY.rest_positions
    axes = rest[BODY.section_up].mean(axis=1) - rest[BODY.section_down].mean(axis=1)
    assert np.allclose(axes[:, [0, 2]], 0.0) and np.all(axes[:, 1] > 0)
    widest = np.argmax(BODY.section_areas)
    assert widest == 6  # the flukes: their span is the widest extent across the motion


def test_released_at_rest_at_its_depth_the_dolphin_stays_and_boyles_lungs_move_it_elsewhere():
    """Neutral at its tasks' start depth (3 m): after 10 s at rest it has moved less than a
    millimetre; 1.5 m higher its lungs are bigger and it rises, 1.5 m deeper it sinks."""
    moved = {}
    for depth in (1.5, 3.0, 4.5):
        z = _heights(_core(LeapTask(start_depth=depth)), 10.0)
        moved[depth] = z[-1, 0] + depth
    assert abs(moved[3.0]) < 1e-3
    assert moved[1.5] > 0.2 and moved[4.5] < -0.2


@pytest.mark.parametrize("model", ["reactive", "resistive"])
def test_dropped_from_above_the_dolphin_falls_with_g_and_plunges(model):
    """In either water it falls with g and plunges. In the paper's water it floats back up to
    the surface; in the reactive one the water it carries pitches it nose down on entry and it
    glides off forward and down, past the depth where it is neutral (measured: 0.6 m/s
    forward at -19 degrees 2 s in, 4.1 m down after 20 s), so it is not held to float."""
    core = _core(LeapTask(start_depth=-1.0), water={**WATER, "model": model})  # CoM 1 m up
    z = _heights(core, 40.0 if model == "resistive" else 2.0)[:, 0]
    t = core.dt * np.arange(1, 7)  # the first 0.3 s, all of it in the air
    fall = np.polyfit(t, z[:6], 2)[0] * 2.0
    assert abs(fall + G) < 0.01 * G, fall
    assert z.min() < -1.0  # it plunged
    if model == "resistive":
        assert z[-1] > z.min() + 1.0 and z[-1] > -0.45  # back at the surface, floating
        assert abs(z[-1] - z[-100]) < 0.05  # settled


def test_a_dolphin_in_ballistic_flight_follows_a_parabola_and_keeps_its_angular_momentum():
    """Thrown spinning, well above the water, with air drag off: the centre of mass follows
    the scheme's discrete parabola to round-off, and the angular momentum about it is kept."""
    system = System(BODY, Water(surface_z=-50.0, air_coefficient=0.0,
                                air_friction_coefficient=0.0, model="resistive"), dt=STEP)
    x = BODY.rest_positions[None].copy()
    com0 = BODY.masses @ x[0] / BODY.total_mass
    spin = np.array([0.0, -6.0, 0.0])  # rad/s: a somersault, nose up
    v = (np.array([2.0, 0.0, 5.0]) + np.cross(spin, x[0] - com0))[None]
    l0 = momenta(x, v, BODY.masses, com0[None])[1][0]
    steps = int(round(0.8 / STEP))
    step_batch(x, v, np.zeros((1, 6)), np.zeros((1, 6)), np.zeros((1, 2)), steps,
               system.kernel_args)
    com = BODY.masses @ x[0] / BODY.total_mass
    t = steps * STEP
    rise = 5.0 * t - 0.5 * G * STEP**2 * steps * (steps + 1)
    assert abs(com[0] - com0[0] - 2.0 * t) < 1e-9 and abs(com[2] - com0[2] - rise) < 1e-9
    l1 = momenta(x, v, BODY.masses, com[None])[1][0]
    assert np.abs(l1 - l0).max() < 1e-9 * np.abs(l0).max()


def _splash(pitch_deg: float) -> float:
    """Re-entry impulse (N s) of the relaxed dolphin dropped from 1.5 m, pitched as given."""
    core = _core(LeapTask(start_depth=-1.5, start_pitch_deg=pitch_deg))
    total = 0.0
    for _ in range(40):
        core.step(-np.ones((1, 6)))
        total += core.state.splash[0]
    return total


def test_a_belly_flop_splashes_more_than_a_clean_dive():
    flop, dive = _splash(0.0), _splash(-85.0)
    assert flop > 3.0 * dive > 0.0, (flop, dive)


def test_the_fluke_stroke_drives_the_dolphin_fast_within_tissue_limits():
    """The hand swim-MC's strokes at full speed: over 1.5 BL/s along the start heading; under
    200 random actions on 8 bodies every passive element stays within 0.6-1.4 of its rest
    length."""
    t = 0.05 * np.arange(1, 81)
    core = _core(DolphinForwardTask())
    speeds = [core.step(to_action(dolphin_swim_mc(1.0, s))[None].astype(float))[1][
        "speed_bl_per_s"][0] for s in t]
    assert np.mean(speeds[-20:]) > 1.5
    random_core = _core(DolphinForwardTask(), num_envs=8, noise=0.005)
    passive = BODY.actuator < 0
    rng, low, high = np.random.default_rng(0), np.inf, 0.0
    for _ in range(200):
        random_core.step(rng.uniform(-1, 1, (8, 6)))
        x = random_core.state.x
        assert np.isfinite(x).all(), "a body blew up"  # min/max would pass over a NaN
        r = x[:, BODY.elements[passive, 1]] - x[:, BODY.elements[passive, 0]]
        strain = np.linalg.norm(r, axis=2) / BODY.rest_lengths[passive]
        low, high = min(low, strain.min()), max(high, strain.max())
    assert 0.6 <= low and high <= 1.4, (low, high)


def _figures(refine: int, model: str) -> dict[str, float]:
    """The dolphin's hand MCs (calibrated for the water) at the default step over ``refine``:
    the stroke's speed (BL/s over 3-6 s) and depth change (BL over 6 s), a 90-degree pitch
    down when its strokes end, a 90-degree steer left when it ends."""
    core = _core(DolphinForwardTask(), num_envs=3, physics_dt=STEP / refine,
                 frame_skip=SKIP * refine, water={**WATER, "model": model})
    calibration = dolphin_calibrated(model)
    pitch_end = turn_duration(np.pi / 2, calibration.turn)
    steer_end = calibration.steer_delay + np.pi / 2 / calibration.steer_rate
    coms, pitches, yaws = [], [], []
    for k in range(120):
        t = (k + 1) * 0.05
        actions = [dolphin_swim_mc(1.0, t, calibration.swim),
                   dolphin_turn_mc("down", np.pi / 2, t, calibration),
                   dolphin_turn_mc("left", np.pi / 2, t, calibration)]
        _, info, kinematics = core.step(to_action(np.stack(actions)).astype(float))
        coms.append(info["com"].copy())
        heading = kinematics.frames[:, 0]
        pitches.append(np.degrees(np.arcsin(heading[1, 2])))
        yaws.append(np.degrees(np.arctan2(heading[2, 1], heading[2, 0])))
    com = np.array(coms) / BODY.length
    return {"swim speed BL/s": np.linalg.norm(com[-1, 0] - com[59, 0]) / 3.0,
            "swim depth change BL": com[-1, 0, 2] - com[0, 0, 2],
            "pitch down deg": -pitches[int(round(pitch_end / 0.05)) - 1],
            "steer left deg": yaws[int(round(steer_end / 0.05)) - 1]}


@pytest.mark.parametrize("model", ["reactive", "resistive"])
def test_the_dolphin_s_default_step_is_within_five_percent_of_a_step_four_times_smaller(model):
    """Measured: reactive within 1.1% (2.87 BL/s, -2.03 BL, 80.6 and 90.2 deg), resistive
    within 4.1% (2.20 BL/s, -2.09 BL, 70.3 and 64.2 deg)."""
    default, fine = _figures(1, model), _figures(4, model)
    for name in default:
        assert abs(default[name] - fine[name]) <= 0.05 * abs(fine[name]), (name, default, fine)


def test_the_fluke_stroke_swims_like_a_dolphin_in_the_reactive_water():
    """The calibrated cruise: St within 0.2-0.4 and at least 0.5 BL per beat (dolphins: St
    0.2-0.3, 0.8-1 BL per beat; the paper's water St 1.02, 0.44 BL per beat)."""
    figures = dolphin_cruise({"model": "reactive"}, dolphin_calibrated("reactive").swim)
    assert 0.2 <= figures["St"] <= 0.4 and figures["stride"] >= 0.5, figures
    paper = dolphin_cruise({"model": "resistive"}, dolphin_calibrated("resistive").swim)
    assert paper["St"] > 0.8, paper  # the paper's water cannot


def test_a_leaps_apex_is_converged_in_the_step(refine=2):
    """The hand swim-MC from 3 m down, pitched 80 deg up: the apex of the centre of mass
    changes by under 5% when the physics step is halved (measured in the default water with its
    stroke 0.590 -> 0.587 BL; the paper's water 0.673 -> 0.69)."""
    apexes = []
    for factor in (1, refine):
        core = _core(LeapTask(start_pitch_deg=80.0), physics_dt=STEP / factor,
                     frame_skip=SKIP * factor)
        for s in 0.05 * np.arange(1, 61):
            info = core.step(to_action(dolphin_swim_mc(1.0, s))[None].astype(float))[1]
        apexes.append(info["apex_height_bl"][0])
    assert apexes[0] > 0.5
    assert abs(apexes[1] - apexes[0]) < 0.05 * apexes[1], apexes


def test_a_users_water_changes_fields_of_the_pool_and_does_not_replace_it():
    import gymnasium as gym

    env = gym.make("Animat/DolphinLeap-v0", water={"gravity": 9.81})
    water = env.unwrapped.core.system.water
    assert water.surface_z == 0.0 and water.friction_coefficient == 1.4 and water.gravity == 9.81
    with pytest.raises(ValueError, match="water must be a dict of Water fields"):
        gym.make("Animat/DolphinLeap-v0", water=3)
