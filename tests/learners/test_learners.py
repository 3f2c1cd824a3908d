"""Every registered learner on a tiny budget; annealing reproducibility and resume."""

import numpy as np
import pytest

from learners import annealing
from learners.logger import Logger, MemorySink
from learners.registry import LEARNERS, make_learner

ENV = "Animat/FishSwim-v0"
TINY_ENV = {"duration": 0.5}  # 10 env steps per episode
TINY = {
    "annealing": ({"chains": 8, "nodes": 4}, 240),
    "cmaes": ({"popsize": 8, "nodes": 4}, 240),
    "ppo": ({"n_envs": 4, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "eval_every": 64,
             "policy_kwargs": "dict(net_arch=[16])"}, 128),
    "handmc": ({}, 10),
    "basic_training": ({"regimen": [
        {"name": "swim", "env_id": "Animat/FishSwim-v0", "env_kwargs": {"duration": 0.5},
         "params": {"nodes": 4, "period": 0.5}},
        {"name": "turn", "env_id": "Animat/FishTurn-v0", "env_kwargs": {"duration": 0.5},
         "params": {"nodes": 4, "period": None}}], "annealing": {"chains": 8}}, 480),
    "macro": ({"chains": 8, "slots": 2}, 240),
}


@pytest.fixture(scope="module")
def tiny_repertoire(tmp_path_factory):
    """A repertoire learned on a tiny budget (the basic-training learner's own output)."""
    folder = tmp_path_factory.mktemp("repertoire")
    params, budget = TINY["basic_training"]
    make_learner("basic_training", ENV, TINY_ENV, params, seed=0).learn(budget, folder)
    return folder / "repertoire.json"


def test_every_registered_learner_has_a_tiny_setting():
    assert set(TINY) == set(LEARNERS)


@pytest.mark.parametrize("name", sorted(LEARNERS))
def test_learner_runs_on_a_tiny_budget_and_logs_the_shared_tags(name, tmp_path,
                                                                tiny_repertoire):
    params, budget = TINY[name]
    env_id, tags = ENV, ("eval/return", "eval/speed_bl_per_s")
    if name == "macro":
        params = {**params, "repertoire": str(tiny_repertoire)}
        env_id, tags = "Animat/FishReach-v0", ("eval/return", "eval/final_distance_bl")
    if name == "basic_training":
        tags = ("eval/return",)
    sink = MemorySink()
    learner = make_learner(name, env_id, TINY_ENV, params, seed=0, logger=Logger([sink]))
    result = learner.learn(budget, checkpoint_dir=tmp_path)
    assert 0 < result.env_steps <= budget
    for tag in tags:
        assert np.isfinite(result.metrics[tag])
        steps = [step for step, _ in sink.series(tag)]
        assert steps and steps == sorted(steps) and max(steps) <= budget
    assert any(tag == "hparams" for tag, _, _ in sink.texts)


def test_unknown_learner_and_parameter_are_named():
    with pytest.raises(ValueError, match="unknown learner 'nope'"):
        make_learner("nope", ENV)
    with pytest.raises(ValueError, match="temprature"):
        make_learner("annealing", ENV, TINY_ENV, {"temprature": 1.0})


def _anneal(budget, checkpoint_dir=None, seed=3):
    sink = MemorySink()
    learner = make_learner("annealing", ENV, TINY_ENV, {"chains": 8, "nodes": 4,
                                                       "checkpoint_every": 1},
                           seed=seed, logger=Logger([sink]))
    return learner.learn(budget, checkpoint_dir), sink


def test_annealing_is_bit_for_bit_reproducible():
    (a, sink_a), (b, sink_b) = _anneal(800), _anneal(800)
    assert a.metrics == b.metrics
    assert a.artefacts["controller"] == b.artefacts["controller"]
    assert sink_a.records == sink_b.records
    c, _ = _anneal(800, seed=4)
    assert c.artefacts["controller"] != a.artefacts["controller"]


def test_annealing_resumed_from_a_checkpoint_ends_identical(tmp_path):
    whole, _ = _anneal(800)
    _anneal(400, tmp_path)  # interrupted half way (its checkpoint stays)
    resumed, _ = _anneal(800, tmp_path)
    assert resumed.env_steps == whole.env_steps
    assert resumed.metrics == whole.metrics
    assert resumed.artefacts["controller"] == whole.artefacts["controller"]


def test_annealing_accepts_downhill_and_cools():
    params = annealing.AnnealingParams(chains=4, moves_per_temperature=1, cooling=0.5)
    state = annealing.init(params, np.full(3, 0.5), seed=0)
    x, state = annealing.ask(params, state)
    state = annealing.tell(params, state, x, np.ones(4))
    proposals, state = annealing.ask(params, state)
    assert not np.array_equal(proposals, x) and np.all((0 <= proposals) & (proposals <= 1))
    told = annealing.tell(params, state, proposals, np.zeros(4))  # all downhill
    np.testing.assert_array_equal(told.x, proposals)
    assert told.best_energy == 0.0 and told.temperature == pytest.approx(
        0.5 * params.initial_temperature)


def test_ppo_resumes_from_its_checkpoint(tmp_path):
    params, _ = TINY["ppo"]
    params = {**params, "checkpoint_every": 64}
    first = make_learner("ppo", ENV, TINY_ENV, params, seed=0).learn(128, tmp_path)
    assert (tmp_path / "model.zip").exists() and first.env_steps == 128
    resumed = make_learner("ppo", ENV, TINY_ENV, params, seed=0).learn(256, tmp_path)
    assert resumed.env_steps == 256  # continued from 128, not from 0
