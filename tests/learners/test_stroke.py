"""The exit-stroke learner: the stroke it plays (the prefix untouched before t0, no
co-contraction, the pose after), its config errors, and a run whose agent plays back what it
learned."""

from pathlib import Path

import numpy as np
import pytest

from animat.learners.controllers.repertoire import Repertoire
from animat.learners.macro import MacroSequence
from animat.learners.registry import make_learner
from animat.learners.rollout import BatchEvaluator
from animat.learners.stroke import ExitStroke, StrokeParameters

ROOT = Path(__file__).resolve().parents[2]
REPERTOIRE = str(ROOT / "repertoires" / "dolphin.json")
PREFIX = [{"skill": "turn_up", "duration": 0.5}, {"skill": "move_forward", "duration": 1.0}]
ENV, KWARGS = "Animat/DolphinSomersault-v0", {"duration": 2.0, "start_depth": 0.6}


def _stroke(**changes) -> StrokeParameters:
    values = {"t0": 1.0, "hold": 0.5, "frequency": 4.0, "phase": 0.1, "amplitude": 0.8,
              "bias_middle": -0.3, "bias_back": 0.2, "lag": 0.25,
              "pose": (0.1, 0.2, 0.3, 0.4, 0.5, 0.6), **changes}
    return StrokeParameters(**values)


def test_the_stroke_follows_the_prefix_beats_without_co_contraction_then_holds_its_pose():
    repertoire = Repertoire.load(REPERTOIRE)
    prefix = MacroSequence(repertoire, [(s["skill"], s["duration"]) for s in PREFIX], 0.05)
    stroke = _stroke()
    t = np.linspace(0.0, 2.0, 801)
    u = ExitStroke(prefix, stroke)(t)
    before, beating, after = t < 1.0, (t >= 1.0) & (t < 1.5), t >= 1.5
    np.testing.assert_array_equal(u[before], prefix(t[before]))
    np.testing.assert_array_equal(u[after], np.tile(stroke.pose, (after.sum(), 1)))
    for dorsal, ventral in ((0, 2), (1, 3)):  # middle, back segments
        assert np.all(np.minimum(u[beating, dorsal], u[beating, ventral]) == 0.0)
        assert u[beating, dorsal].max() > 0.5 and u[beating, ventral].max() > 0.5
    assert np.all(u[beating][:, 4:] == 0.0)  # the front muscles rest while it beats
    bend = u[beating, 0] - u[beating, 2]  # the middle segment's: 4 Hz for 0.5 s
    assert np.count_nonzero(np.diff(np.sign(bend[bend != 0])) != 0) in (3, 4, 5)
    assert np.all((u >= 0.0) & (u <= 1.0))
    assert np.array_equal(ExitStroke(prefix, stroke)(1.2), u[np.searchsorted(t, 1.2)])


def test_config_errors_name_the_field():
    def make(**params):
        return make_learner("stroke", ENV, KWARGS, {"repertoire": REPERTOIRE,
                                                    "prefix": PREFIX, **params})
    with pytest.raises(ValueError, match="learner 'stroke': prefix: no skill 'backflip'"):
        make(prefix=[{"skill": "backflip", "duration": 1.0}])
    with pytest.raises(ValueError, match="prefix: the duration of 'turn_up' must be > 0"):
        make(prefix=[{"skill": "turn_up", "duration": -1.0}])
    with pytest.raises(ValueError, match="start_window"):
        make(start_window=[1.0, 0.5])
    with pytest.raises(ValueError, match="ends after the episode"):
        make(start_window=[1.0, 3.0])
    with pytest.raises(ValueError, match="learner 'stroke': prefix: no skill"):
        make(prefix=[{"skill": ["turn_up"], "duration": 1.0}])
    with pytest.raises(ValueError, match="above what the env step"):
        make(max_frequency=20.0)
    with pytest.raises(ValueError, match="finite"):
        make(max_frequency=float("inf"))
    with pytest.raises(ValueError, match="overlap must be in"):
        make(overlap=0.9)
    with pytest.raises(ValueError, match=r"\['lower'\] cannot be set"):
        make(lower=-1.0)
    with pytest.raises(ValueError, match="needs params.repertoire"):
        make_learner("stroke", ENV, KWARGS, {"repertoire": REPERTOIRE})
    with pytest.raises(ValueError, match="drives the dolphin's actuators"):
        make_learner("stroke", "Animat/FishSwim-v0", {}, {"repertoire": REPERTOIRE,
                                                          "prefix": PREFIX})
    with pytest.raises(ValueError, match=r"does not take parameter\(s\) \[.slots.\]"):
        make(slots=3)


@pytest.mark.parametrize("name", ["stroke", "stroke_cmaes"])
def test_a_run_keeps_a_stroke_within_its_bounds_that_plays_back_as_scored(name, tmp_path):
    size = {"chains": 8} if name == "stroke" else {"popsize": 8}
    learner = make_learner(name, ENV, KWARGS, {"repertoire": REPERTOIRE, "prefix": PREFIX,
                                               "start_window": [1.0, 1.8], "max_hold": 0.6,
                                               "start_states": 2, **size}, 0)
    result = learner.learn(8 * 40 * 2 * 3, tmp_path)  # 3 rounds of 8 candidates
    stroke = result.artefacts["stroke"]
    assert 1.0 <= stroke["t0"] <= 1.8 and 0.05 <= stroke["hold"] <= 0.6
    assert 1.0 <= stroke["frequency"] <= 6.0 and all(0 <= u <= 1 for u in stroke["pose"])
    assert result.artefacts["prefix"] == PREFIX
    assert (tmp_path / "repertoire.json").exists()  # the run composes from its own copy
    evaluator = BatchEvaluator(ENV, KWARGS, num_envs=2, seed=0, num_starts=2)
    returns, metrics = evaluator.evaluate(learner.agent(result.artefacts, tmp_path).actions[None])
    assert returns[0] == pytest.approx(result.metrics["eval/return"], rel=1e-9)
    assert metrics["flight_rotation_deg"][0] == pytest.approx(
        result.metrics["eval/flight_rotation_deg"], rel=1e-9)


def test_the_learner_reads_the_dolphins_body_and_clock_without_building_the_env(monkeypatch):
    import gymnasium as gym

    monkeypatch.setattr(gym, "make", lambda *a, **k: pytest.fail(f"built {a} {k}"))
    learner = make_learner("stroke", ENV, KWARGS, {"repertoire": REPERTOIRE, "prefix": PREFIX})
    assert learner.window == (0.0, 2.0) and learner.max_hold <= 2.0
    with pytest.raises(ValueError, match="drives the dolphin's actuators"):
        make_learner("stroke", "Animat/FishSwim-v0", {}, {"repertoire": REPERTOIRE,
                                                          "prefix": PREFIX})
