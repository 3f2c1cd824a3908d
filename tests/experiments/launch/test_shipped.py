"""Shipped data, reached from anywhere: a shipped config runs by name from any directory, a
config's relative paths are relative to its own folder, ``animat list`` names every registered
env and every shipped config, nothing a run does overwrites a file it did not make, and a
failure while working is one line with the traceback kept in the run folder."""

import hashlib
import json
import shutil
from pathlib import Path

import gymnasium as gym
import pytest
import yaml

from animat.experiments import cli
from animat.experiments.launch.config import load_config
from animat.experiments.launch.shipped import CONFIGS, find_config, shipped_configs
from tests.support.cli import TINY, animat, write_config

ROOT = Path(__file__).resolve().parents[3]
# one skill of the fish's regimen, short: basic training in seconds
ONE_SKILL = {
    "env": {"id": "Animat/FishSwim-v0"},
    "learner": {"name": "basic_training", "params": {
        "regimen": [{"name": "swim", "env_id": "Animat/FishSwim-v0",
                     "env_kwargs": {"duration": 0.5}, "params": {"nodes": 4, "period": 0.5}}],
        "annealing": {"chains": 8}}},
    "budget": {"env_steps": 3200},
}


def digest(folder: Path) -> dict[str, str]:
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


def test_shipped_configs_are_found_by_name_or_checkout_path_from_anywhere(tmp_path,
                                                                           monkeypatch):
    monkeypatch.chdir(tmp_path)  # outside the checkout
    names = shipped_configs()
    assert "quickstart" in names and "fish_swim/tune_ppo" in names and "fish_swim/tuned_cmaes" \
        in names and len(names) == len(list((ROOT / "configs").rglob("*.yaml")))
    for name in ("quickstart", "quickstart.yaml", "configs/quickstart.yaml"):
        assert find_config(name) == CONFIGS / "quickstart.yaml"
    assert find_config("fish_swim/tune_ppo") == CONFIGS / "fish_swim" / "tune_ppo.yaml"
    assert find_config("nope") == Path("nope")
    animat("run", "quickstart", "--set", "budget.env_steps=20000", "--out", tmp_path / "q",
           "--quiet", cwd=tmp_path)
    assert json.loads((tmp_path / "q" / "result.json").read_text())["status"] == "done"
    missing = animat("run", "nope", cwd=tmp_path, check=False)
    assert missing.returncode == 2 and "no such file, nor a shipped config" in missing.stderr


def test_relative_paths_are_the_config_folders_and_an_overrides_the_current_directorys(
        tmp_path, monkeypatch):
    (tmp_path / "mine" / "configs").mkdir(parents=True)
    (tmp_path / "mine" / "reps").mkdir()
    shutil.copyfile(ROOT / "repertoires" / "fish.json", tmp_path / "mine" / "reps" / "fish.json")
    data = yaml.safe_load((CONFIGS / "fish_reach" / "macro.yaml").read_text())
    data["learner"]["params"]["repertoire"] = "../reps/fish.json"
    config = write_config(tmp_path / "mine" / "configs" / "reach.yaml", data)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    loaded = load_config(config)
    assert loaded.learner.params["repertoire"] == str(tmp_path / "mine" / "reps" / "fish.json")
    shutil.copyfile(ROOT / "repertoires" / "fish.json", elsewhere / "here.json")
    overridden = load_config(config, ["learner.params.repertoire=here.json"])
    assert overridden.learner.params["repertoire"] == str(elsewhere / "here.json")
    shipped = load_config(CONFIGS / "fish_reach" / "macro.yaml")  # ../../repertoires
    assert shipped.learner.params["repertoire"] == str(ROOT / "repertoires" / "fish_reactive.json")


def test_list_names_every_registered_env_and_every_shipped_config():
    out = animat("list", cwd=Path("/")).stdout
    envs = sorted(k for k in gym.registry if k.startswith("Animat/"))
    assert len(envs) == 14 and f"envs ({len(envs)}):" in out
    assert all(f"  {e}\n" in out for e in envs)
    lines = out.splitlines()
    for name in shipped_configs():  # each with its first line, a one-sentence description
        first = (CONFIGS / f"{name}.yaml").read_text().split("\n", 1)[0]
        assert first.startswith("# ") and first.endswith(".") and len(first) <= 2 + 72, name
        line = next(line for line in lines if line.split()[:1] == [name])
        assert line.split(maxsplit=1)[1] == first[2:], line
    assert "  quickstart " in out and "A small default" in out


def test_basic_training_writes_into_its_run_folder_and_never_over_a_file(tmp_path):
    shipped = digest(ROOT / "repertoires")
    config = write_config(tmp_path / "one.yaml", ONE_SKILL)
    animat("run", config, "--out", tmp_path / "run", "--quiet")
    kept = tmp_path / "run" / "checkpoints" / "repertoire.json"
    assert json.loads(kept.read_text())["skills"][0]["name"] == "swim"
    target = tmp_path / "mine.json"
    target.write_text("mine")
    refused = animat("run", config, "--set", f"learner.params.output={target}", "--out",
                     tmp_path / "refused", check=False)
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert f"output {target} exists" in refused.stderr and "--force" in refused.stderr
    assert target.read_text() == "mine" and not (tmp_path / "refused").exists()
    animat("run", config, "--set", f"learner.params.output={target}", "--force", "--out",
           tmp_path / "forced", "--quiet")
    assert json.loads(target.read_text())["skills"][0]["name"] == "swim"
    needless = animat("run", config, "--force", "--out", tmp_path / "x", check=False)
    assert needless.returncode == 2 and "writes nothing outside its run folder" in \
        needless.stderr
    assert digest(ROOT / "repertoires") == shipped


def test_a_failure_while_running_is_one_line_and_the_run_folder_keeps_the_traceback(
        tmp_path, monkeypatch):
    from animat.learners.blackbox import AnnealingLearner

    def broken(self, budget, checkpoint_dir=None):
        raise RuntimeError("the simulator blew up\nsecond line of detail")

    monkeypatch.setattr(AnnealingLearner, "learn", broken)
    config = write_config(tmp_path / "tiny.yaml", TINY)
    folder = tmp_path / "run"
    failed = animat("run", config, "--out", folder, "--quiet", check=False)
    lines = failed.stderr.strip().splitlines()
    assert failed.returncode == 1 and len(lines) == 1, failed.stderr
    assert lines[0] == (f"animat: error: RuntimeError: the simulator blew up (traceback in "
                        f"{folder / 'error.log'})")
    assert "Traceback" in (folder / "error.log").read_text()
    result = json.loads((folder / "result.json").read_text())
    assert result["status"] == "failed"
    assert result["error"] == "RuntimeError: the simulator blew up"
    with pytest.raises(RuntimeError, match="blew up"):
        cli.main(["--debug", "run", str(config), "--out", str(tmp_path / "debug"), "--quiet"])


def test_a_work_time_file_error_is_a_failure_of_the_run_not_of_the_users_input(
        tmp_path, monkeypatch):
    from animat.learners.blackbox import AnnealingLearner

    def lost(self, budget, checkpoint_dir=None):
        raise FileNotFoundError("a file the learner needs went away")

    monkeypatch.setattr(AnnealingLearner, "learn", lost)
    folder = tmp_path / "run"
    failed = animat("run", write_config(tmp_path / "tiny.yaml", TINY), "--out", folder,
                    "--quiet", check=False)
    assert failed.returncode == 1 and f"(traceback in {folder / 'error.log'})" in failed.stderr
    assert "FileNotFoundError: a file the learner needs went away" in failed.stderr


def test_a_run_folder_that_can_no_longer_build_is_marked_failed_with_the_reason(tmp_path):
    from animat.experiments.launch.folders import create_run

    repertoire = tmp_path / "fish.json"
    shutil.copyfile(ROOT / "repertoires" / "fish.json", repertoire)
    config = load_config(CONFIGS / "fish_reach" / "macro.yaml",
                         [f"learner.params.repertoire={repertoire}", "budget.env_steps=20000"])
    folder = create_run(config, tmp_path / "run", ["test"])
    repertoire.unlink()  # the folder keeps its own copy from the moment it is made
    assert (folder / "checkpoints" / "repertoire.json").read_bytes() == (
        ROOT / "repertoires" / "fish.json").read_bytes()
    text = (folder / "config.yaml").read_text()
    (folder / "config.yaml").write_text(text.replace("slots: ", "slots: -"))  # builds no more
    failed = animat("run", "--resume", folder, check=False)
    assert failed.returncode == 1 and len(failed.stderr.strip().splitlines()) == 1
    result = json.loads((folder / "result.json").read_text())
    assert result["status"] == "failed" and "ConfigError" in result["error"]
    assert (folder / "error.log").exists()


def test_a_sweep_or_a_study_cannot_write_one_output_from_many_runs(tmp_path):
    config = write_config(tmp_path / "one.yaml", ONE_SKILL)
    output = ["--set", f"learner.params.output={tmp_path / 'out.json'}"]
    swept = animat("sweep", config, "--seeds", "0-1", *output, "--out", tmp_path / "sweep",
                   check=False)
    assert swept.returncode == 2 and "the 2 runs of the sweep would all write" in swept.stderr
    tuned = animat("tune", config, "--trials", "3", *output, "--out", tmp_path / "tune",
                   check=False)
    assert tuned.returncode == 2 and "the 3 runs of the study would all write" in tuned.stderr
    assert not (tmp_path / "sweep").exists() and not (tmp_path / "tune").exists()


def test_list_into_a_closed_pipe_says_nothing():
    import subprocess
    import sys

    # the reader (true) is gone long before animat has imported and prints
    done = subprocess.run(f"{sys.executable} -m animat.experiments list | true", shell=True,
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0 and done.stderr == ""
