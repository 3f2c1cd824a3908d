"""Every learner param is checked before the run folder exists: a bad one is one line naming
the field and the value, exit status 2, and no folder; sizes (nodes, slots, a network's
widths) are bounded by the memory they would take."""

import json
from pathlib import Path

import gymnasium as gym
import pytest

from animat.learners.controllers.repertoire import Repertoire
from tests.support.cli import ROOT, TINY, animat, write_config

FISH = json.loads((ROOT / "repertoires" / "fish.json").read_text())
REACH = {"env": {"id": "Animat/FishReach-v0", "kwargs": {"duration": 0.5}},
         "learner": {"name": "macro", "params": {"slots": 2, "chains": 8}},
         "budget": {"env_steps": 3200}}
PPO = {"env": {"id": "Animat/FishSwim-v0", "kwargs": {"duration": 0.5}},
       "learner": {"name": "ppo", "params": {"n_envs": 2, "n_steps": 16, "batch_size": 32}},
       "budget": {"env_steps": 64}}


class Overflowing(gym.Env):
    """An env whose constructor fails as a float overflow does, not with a ValueError."""

    def __init__(self, length: float = 1.0) -> None:
        int(length)


gym.register("Test/Overflowing-v0", entry_point=Overflowing)

REPERTOIRES = {  # file text -> what the one line says
    "": "not a repertoire file: not valid JSON",
    "[]": "not a repertoire file",
    json.dumps({"format": FISH["format"]}): "skills must be a non-empty list, got None",
    json.dumps({**FISH, "skills": []}): "skills must be a non-empty list, got []",
    json.dumps({**FISH, "skills": {}}): "skills must be a non-empty list, got {}",
    json.dumps({**FISH, "skills": FISH["skills"] + FISH["skills"][:1]}):
        f"skill {FISH['skills'][0]['name']!r} appears twice",
    json.dumps({**FISH, "skills": [{"name": "x", "metadata": {}}]}):
        "skill 'x' cannot be read (KeyError: 'controller')",
}


@pytest.mark.parametrize("text, message", REPERTOIRES.items(), ids=range(len(REPERTOIRES)))
def test_a_repertoire_file_that_is_not_one_is_named_in_one_line(tmp_path, text, message):
    path = tmp_path / "r.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"^{path}: ") as refused:
        Repertoire.load(path)
    assert message in str(refused.value) and "\n" not in str(refused.value)


def _with(base: dict, **params) -> dict:
    data = json.loads(json.dumps(base))
    data["learner"]["params"].update(params)
    return data


def _regimen(*names: str) -> list[dict]:
    return [{"name": n, "env_id": "Animat/FishSwim-v0", "env_kwargs": {"duration": 0.5},
             "params": {"chains": 4, "nodes": 4, "period": 0.5}} for n in names]


BASIC = {"env": {"id": "Animat/FishSwim-v0"}, "budget": {"env_steps": 3200},
         "learner": {"name": "basic_training", "params": {}}}
CASES = [  # (config, where, what the line says)
    (_with(TINY, nodes=10**10), "learner.params",  # sizes far beyond any machine's memory
     "nodes 10000000000 x 6 actuators (60,000,000,000 genes) for 8 candidates would take"),
    ({**TINY, "learner": {"name": "cmaes", "params": {"nodes": 100_000, "popsize": 8}}},
     "learner.params", "nodes 100000 x 6 actuators (600,000 genes)"),
    (_with(REACH, slots=10**12), "learner.params", "slots 1000000000000 x 2"),
    (_with(REACH, skills=[]), "learner.params", "skills must be a non-empty list"),
    (_with(REACH, skills=["swim_fast", "swim_fast"]), "learner.params", "distinct skill names"),
    (_with(PPO, policy="FooPolicy"), "learner.params", "unknown policy 'FooPolicy'"),
    (_with(PPO, policy_kwargs="dict(foo=1)"), "learner.params", "MlpPolicy takes no ['foo']"),
    (_with(PPO, policy_kwargs={"net_arch": [0]}), "learner.params",
     "net_arch must be layer widths (integers >= 1)"),
    (_with(PPO, policy_kwargs="dict(net_arch=[10000000, 10000000])"), "learner.params",
     "net_arch [10000000, 10000000] (its weights"),
    ({**_with(PPO, n_steps=10**12), "budget": {"env_steps": 10**13}}, "learner.params",
     "a rollout of n_envs 2 x n_steps 1000000000000 observations of 150 entries would take"),
    (_with(PPO, learning_rate=float("nan")), "learner.params", "Input should be a finite"),
    (_with(PPO, learning_rate="lin_nan"), "learner.params", "use a number or lin_<x>"),
    (_with(PPO, ent_coef=float("nan")), "learner.params", "ent_coef: Input should be a finite"),
    (_with(PPO, n_envs=100_000), "learner.params", "n_envs: Input should be less than or equal"),
    (_with(TINY, period=0.0), "learner.params", "period must be a finite number of seconds"),
    (_with(TINY, period=float("nan")), "learner.params", "period must be a finite number"),
    (_with(BASIC, regimen=[{**_regimen("a")[0], "params": [1]}]), "learner.params",
     "regimen skill 'a': params must be a mapping"),
    ({**_with(PPO, policy="MlpPolicy"), "env": {"id": "Animat/FishPursuit-v0"}},
     "learner.params", "policy MlpPolicy cannot take Animat/FishPursuit-v0's Dict "
     "observations: use MultiInputPolicy"),
    (_with(PPO, policy="MultiInputPolicy"), "learner.params",
     "policy MultiInputPolicy cannot take Animat/FishSwim-v0's Box observations"),
    (_with(BASIC, regimen=[]), "learner.params", "regimen must name at least one skill"),
    (_with(BASIC, regimen=_regimen("a", "a")), "learner.params", "names skill 'a' twice"),
]


@pytest.mark.parametrize("config, where, message", CASES, ids=range(len(CASES)))
def test_a_bad_param_stops_before_the_run_folder_exists(tmp_path, config, where, message):
    if config["learner"]["name"] == "macro" and "repertoire" not in config["learner"]["params"]:
        config["learner"]["params"]["repertoire"] = str(ROOT / "repertoires" / "fish.json")
    path = write_config(tmp_path / "bad.yaml", config)
    refused = animat("run", path, "--out", tmp_path / "run", check=False)
    lines = refused.stderr.strip().splitlines()
    assert refused.returncode == 2 and len(lines) == 1, refused.stderr
    assert f"{path}: {where}: " in lines[0] and message in lines[0], lines[0]
    assert not (tmp_path / "run").exists()


def test_an_env_error_the_code_did_not_word_is_said_with_its_type(tmp_path, monkeypatch):
    """An env constructor's error that is not a ValueError is said as ``Type: message`` under
    env.kwargs (the test's env, which annealing is let drive here)."""
    from animat.learners import validation

    envs, what = validation.DRIVES["annealing"]
    monkeypatch.setitem(validation.DRIVES, "annealing", ((*envs, "Test/Overflowing-v0"), what))
    config = {**TINY, "env": {"id": "Test/Overflowing-v0", "kwargs": {"length": float("inf")}}}
    path = write_config(tmp_path / "bad.yaml", config)
    refused = animat("run", path, "--out", tmp_path / "run", check=False)
    lines = refused.stderr.strip().splitlines()
    assert refused.returncode == 2 and len(lines) == 1, refused.stderr
    assert f"{path}: env.kwargs: OverflowError: cannot convert float infinity to integer" \
        in lines[0]
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("text", ["", "[]", json.dumps({**FISH, "skills": []}),
                                  json.dumps({**FISH, "skills": FISH["skills"] * 2})])
def test_a_macro_run_refuses_a_bad_repertoire_file_before_its_folder(tmp_path, text):
    (tmp_path / "r.json").write_text(text)
    path = write_config(tmp_path / "bad.yaml", _with(REACH, repertoire="r.json"))
    refused = animat("run", path, "--out", tmp_path / "run", check=False)
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert f"learner.params: {tmp_path / 'r.json'}: " in refused.stderr
    assert not (tmp_path / "run").exists()


def test_the_memory_bound_refuses_absurd_sizes_only(tmp_path):
    """Sizes a machine holds are taken: 400 nodes per actuator run, a network of two 512-wide
    layers validates; 10^10 nodes per actuator do not."""
    from animat.experiments.launch.config import ConfigError, load_config

    with pytest.raises(ConfigError, match="GiB of memory"):
        load_config(write_config(tmp_path / "big.yaml", _with(TINY, nodes=10**10)))
    path = write_config(tmp_path / "ok.yaml", _with(TINY, nodes=400))
    animat("run", path, "--out", tmp_path / "run", "--quiet")
    assert json.loads(Path(tmp_path / "run" / "result.json").read_text())["status"] == "done"
    ppo = _with(PPO, policy_kwargs="dict(net_arch=[512, 512])")
    assert load_config(write_config(tmp_path / "ppo.yaml", ppo)).learner.name == "ppo"
