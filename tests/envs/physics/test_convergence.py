"""The default step is converged: what a researcher reads does not change when it is refined.

Swim speed (hand swim-MC, full speed, net displacement along the start heading over 5-10 s),
the 90-degree turn-MC's heading when it ends, and the fin-MC's depth change, at the default step
and at a step 4x smaller, agree within 5%, in both waters (the MCs calibrated for each).
"""

import numpy as np
import pytest

from animat.envs.core.batch import DEFAULT_FRAME_SKIP, BodyBatch
from animat.envs.motor.fish import (
    FinParams,
    calibrated,
    fin_mc,
    swim_mc,
    to_action,
    turn_duration,
    turn_mc,
)
from animat.envs.physics.system import DEFAULT_DT, WATER_MODELS
from animat.envs.tasks.locomotion import SwimTask


def _figures(refine: int, model: str) -> dict[str, float]:
    """The three figures at the default step divided by ``refine``, in water ``model``."""
    core = BodyBatch(3, SwimTask(), physics_dt=DEFAULT_DT / refine, water={"model": model},
                     frame_skip=DEFAULT_FRAME_SKIP * refine, duration=100.0, fins=True)
    swim_params, turn_params = calibrated(model)
    core.reset_rows(np.arange(3), [np.random.default_rng(0) for _ in range(3)])
    fins = np.zeros((3, 2))
    fins[2] = fin_mc(pitch=1.0) / FinParams().max_angle  # row 2 pitches up
    dt, turn_end = core.dt, turn_duration(np.pi / 2, turn_params)
    coms, headings = [], []
    for k in range(200):
        t = (k + 1) * dt
        swim = to_action(swim_mc(1.0, t, swim_params))
        actions = np.stack([swim, to_action(turn_mc(np.pi / 2, t, True, turn_params)), swim])
        actions = np.concatenate([actions, fins], axis=1)
        _, info, _ = core.step(actions.astype(np.float64))
        coms.append(info["com"].copy())
        headings.append(info["heading_deg"][1])
    com = np.array(coms) / core.body.length
    return {"swim speed BL/s": (com[-1, 0, 0] - com[99, 0, 0]) / 5.0,
            "turn heading deg": headings[int(round(turn_end / dt)) - 1],
            "fin depth change BL": com[119, 2, 2] - com[0, 2, 2]}


@pytest.fixture(scope="module", params=WATER_MODELS)
def figures(request):
    """(the default step's figures, the 4x smaller step's) in each water."""
    return _figures(1, request.param), _figures(4, request.param)


@pytest.mark.parametrize("name", ["swim speed BL/s", "turn heading deg", "fin depth change BL"])
def test_default_step_is_within_five_percent_of_a_step_four_times_smaller(figures, name):
    default, fine = figures
    assert abs(default[name] - fine[name]) <= 0.05 * abs(fine[name]), (default, fine)
