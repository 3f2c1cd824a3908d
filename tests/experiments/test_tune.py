"""``animat tune``: Optuna over a config's tune.space, every trial a run folder, resumable."""

import json

import yaml

from animat.experiments.config import load_config
from tests.experiments.test_cli import TINY, animat, write_config

SPACE = {"learner.params.cooling": {"low": 0.5, "high": 0.99},
         "learner.params.step_size": {"low": 0.05, "high": 0.8, "log": True},
         "learner.params.nodes": {"choices": [4, 1]}}  # 1 node per actuator cannot work


def _config(tmp_path, space=SPACE):
    data = {**json.loads(json.dumps(TINY)), "tune": {"space": space},
            "logging": {"tensorboard": False, "csv": True, "progress": False}}
    return write_config(tmp_path / "tune.yaml", data)


def test_tune_runs_trials_as_run_folders_and_writes_the_best_config(tmp_path):
    config, out = _config(tmp_path), tmp_path / "study"
    result = animat("tune", config, "--trials", "6", "--out", out)
    summary = json.loads((out / "tune.json").read_text())
    states = [t["state"] for t in summary["trials"]]
    assert len(states) == 6 and states.count("COMPLETE") >= 3 and "FAIL" in states
    for row in summary["trials"]:
        folder = out / f"trial{row['trial']:03d}"
        if row["params"]["learner.params.nodes"] == 1:  # refused before a folder existed
            assert row["state"] == "FAIL" and "nodes must be >= 2" in row["error"]
            assert not folder.exists()
            continue
        status = json.loads((folder / "result.json").read_text())["status"]
        assert status == {"COMPLETE": "done", "PRUNED": "pruned"}[row["state"]]
    best = load_config(out / "best.yaml")  # the tuned config is a valid config
    chosen = summary["best"]["params"]
    assert best.learner.params["cooling"] == chosen["learner.params.cooling"]
    values = [t["value"] for t in summary["trials"] if t["state"] == "COMPLETE"]
    assert summary["best"]["value"] == max(values)
    assert "best: trial" in result.stdout.splitlines()[-1]
    again = animat("tune", config, "--trials", "8", "--out", out)  # continues the study
    assert len(json.loads((out / "tune.json").read_text())["trials"]) == 8
    assert again.returncode == 0


def test_tune_without_a_space_says_so_in_one_line(tmp_path):
    config = write_config(tmp_path / "plain.yaml", TINY)
    result = animat("tune", config, "--trials", "2", "--out", tmp_path / "s", check=False)
    assert result.returncode == 2 and "no tune.space" in result.stderr
    bad = yaml.safe_load(_config(tmp_path).read_text())
    bad["tune"]["space"]["learner.params.cooling"] = {"low": 2, "high": 1}
    result = animat("tune", write_config(tmp_path / "bad.yaml", bad), "--trials", "1",
                    check=False)
    assert result.returncode == 2 and "tune.space.learner.params.cooling" in result.stderr
    assert "need low < high" in result.stderr
    bad["tune"]["space"]["learner.params.cooling"] = {"low": 0.5, "high": 0.9, "log": True,
                                                      "step": 0.1}
    result = animat("tune", write_config(tmp_path / "bad2.yaml", bad), "--trials", "1",
                    check=False)
    assert result.returncode == 2 and "give log or step, not both" in result.stderr


def test_a_restarted_tune_never_repeats_a_sample_and_the_journal_is_shared_storage(tmp_path):
    space = {"learner.params.cooling": {"low": 0.5, "high": 0.99},
             "learner.params.step_size": {"low": 0.05, "high": 0.8, "log": True}}
    config, out = _config(tmp_path, space), tmp_path / "study"
    for trials in (2, 3, 5):  # three starts of one study, as after kills
        animat("tune", config, "--trials", str(trials), "--out", out)
    rows = json.loads((out / "tune.json").read_text())["trials"]
    samples = [tuple(sorted(r["params"].items())) for r in rows]
    assert len(samples) == 5 and len(set(samples)) == 5
    assert (out / "journal.log").exists() and not (out / "study.db").exists()
    elsewhere = tmp_path / "db"
    animat("tune", config, "--trials", "2", "--out", elsewhere, "--storage",
           f"sqlite:///{tmp_path / 'shared.db'}")
    assert (tmp_path / "shared.db").exists() and not (elsewhere / "journal.log").exists()
