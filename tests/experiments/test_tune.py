"""``animat tune``: Optuna over a config's tune.space, every trial a run folder, resumable."""

import json

import pytest
import yaml

from animat.experiments.launch.config import load_config
from tests.support.cli import TINY, animat, write_config

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


def _space_config(tmp_path):
    return _config(tmp_path, {"learner.params.cooling": {"low": 0.5, "high": 0.99}})


def test_best_yaml_comes_from_the_study_not_from_this_machines_trial_folders(tmp_path):
    """Two workers share an RDB study (the same command, so the same study by default); the
    second, whose --out holds none of the trials, still writes the best trial's config."""
    config, url = _space_config(tmp_path), f"sqlite:///{tmp_path / 'shared.db'}"
    animat("tune", config, "--trials", "3", "--out", tmp_path / "a", "--storage", url)
    other = animat("tune", config, "--trials", "3", "--out", tmp_path / "b", "--storage", url)
    best = json.loads((tmp_path / "b" / "tune.json").read_text())["best"]
    assert not list((tmp_path / "b").glob("trial*"))  # every trial ran in the first worker's
    here = tmp_path / "a" / f"trial{best['trial']:03d}" / "config.yaml"
    assert (tmp_path / "b" / "best.yaml").read_text() == here.read_text()
    summary = json.loads((tmp_path / "a" / "tune.json").read_text())
    assert summary["study"] == json.loads((tmp_path / "b" / "tune.json").read_text())["study"]
    assert summary["study"].startswith("tune-") and f"study {summary['study']}" in other.stdout


def test_best_yaml_of_an_older_trial_is_rebuilt_from_the_config_and_its_params(tmp_path):
    """A trial an older version ran kept no config in the study, and its folder may be gone:
    the config and the trial's params make it again."""
    import optuna
    from optuna.storages.journal import JournalFileBackend

    config, out = _space_config(tmp_path), tmp_path / "study"
    out.mkdir()
    storage = optuna.storages.JournalStorage(JournalFileBackend(str(out / "journal.log")))
    study = optuna.create_study(storage=storage, study_name="tune", direction="maximize")
    study.add_trial(optuna.trial.create_trial(
        params={"learner.params.cooling": 0.625}, value=0.1, distributions={
            "learner.params.cooling": optuna.distributions.FloatDistribution(0.5, 0.99)}))
    animat("tune", config, "--trials", "1", "--out", out)
    assert load_config(out / "best.yaml").learner.params["cooling"] == 0.625
    assert json.loads((out / "tune.json").read_text())["study"] == "tune"  # continued


def test_named_studies_share_a_storage_and_an_older_tune_study_there_continues(tmp_path):
    import optuna

    config, url = _space_config(tmp_path), f"sqlite:///{tmp_path / 'shared.db'}"
    for name, trials in (("first", 1), ("second", 2)):
        animat("tune", config, "--trials", str(trials), "--out", tmp_path / name,
               "--storage", url, "--study", name)
    names = {s.study_name: s.n_trials for s in optuna.get_all_study_summaries(url)}
    assert names == {"first": 1, "second": 2}
    older = tmp_path / "older"  # an older version's study in the RDB, named "tune"
    optuna.create_study(storage=url, study_name="tune", direction="maximize")
    (older / "trial000").mkdir(parents=True)
    animat("tune", config, "--trials", "1", "--out", older, "--storage", url)
    assert json.loads((older / "tune.json").read_text())["study"] == "tune"
    refused = animat("tune", config, "--trials", "1", "--study", " ", check=False)
    assert refused.returncode == 2 and "--study must name the study" in refused.stderr


def test_a_lock_left_by_another_study_is_refused_not_waited_on(tmp_path):
    """Optuna's journal lock is a link to the journal; one that leads elsewhere (a moved OUT,
    a planted link) would make every worker wait for ever."""
    import optuna

    from animat.experiments.launch.lock import RunError
    from animat.experiments.tune import storage

    (tmp_path / "journal.log.lock").symlink_to("/nonexistent/journal.log")
    with pytest.raises(RunError, match="journal.log.lock: a lock that is not this study's"):
        storage(optuna, tmp_path, None)
