"""The launcher end to end: run, resume after SIGKILL, sweep, compare, bad configs.

Commands run in-process through :func:`animat.experiments.cli.main` (the ``animat`` entry point);
the resume test kills a real ``python -m animat.experiments`` process."""

import json
import os
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import yaml

from animat.experiments import cli
from animat.experiments.launch.config import ConfigError, load_config
from animat.experiments.parser import make_parser
from tests.support.cli import ROOT, TINY, animat, write_config


def test_run_end_to_end_fills_the_run_folder(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    animat("run", config, "--out", tmp_path / "run", "--set", "seed=2")
    folder = tmp_path / "run"
    for name in ("config.yaml", "command.txt", "versions.json", "scalars.csv", "result.json",
                 "artefacts.json"):
        assert (folder / name).exists(), name
    assert list((folder / "tb").glob("events.out.tfevents.*"))
    result = json.loads((folder / "result.json").read_text())
    assert result["status"] == "done" and 0 < result["env_steps"] <= 3200
    assert set(result["metrics"]) == {"eval/return", "eval/speed_bl_per_s",
                                      "eval/speed_bl_per_s_std"}
    assert yaml.safe_load((folder / "config.yaml").read_text())["seed"] == 2
    assert "--set seed=2" in (folder / "command.txt").read_text()
    again = animat("run", config, "--out", folder, check=False)
    assert again.returncode == 2 and "never overwritten" in again.stderr


def test_compare_two_learners_writes_table_and_plot(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    animat("run", config, "--out", tmp_path / "runs" / "a")
    animat("run", config, "--out", tmp_path / "runs" / "b", "--set", "learner.name=cmaes",
           "--set", "learner.params={popsize: 8, nodes: 4, period: 0.5}")
    animat("run", config, "--out", tmp_path / "runs" / "c", "--set", "learner.label=hot",
           "--set", "learner.params.initial_temperature=1.0",  # a variant, labelled
           "--set", "learner.params.refine={share: 0.5}")
    report = tmp_path / "report" / "swim.md"
    animat("compare", tmp_path / "runs", "--metric", "eval/speed_bl_per_s", "--threshold",
           "0.0", "-o", report)
    text = report.read_text()
    assert "| annealing | 1 (1) |" in text and "| cmaes |" in text and "| hot | 1 (1) |" in text
    png = report.with_suffix(".png")
    assert png.exists() and png.stat().st_size > 5000
    summary = json.loads(report.with_suffix(".json").read_text())
    assert {row["learner"] for row in summary["rows"]} == {"annealing", "cmaes", "hot"}
    assert summary["plotted"] == ["annealing", "cmaes", "hot"]  # every curve is in the plot
    # the abstraction table: one row per run, the refined variant with its refined columns
    rows = {row["learner"]: row for row in summary["abstraction"]}
    assert set(rows) == {"annealing", "cmaes", "hot"}
    assert rows["annealing"]["refined"] is None and rows["hot"]["refined"]["parameters"] < 24
    assert rows["hot"]["refined"]["E"] <= rows["hot"]["before_refining"]["E"]
    assert "Abstractions, per run" in text and text.count("| hot | 0 | 24 |") == 1


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(extra_key=1), "extra_key: unknown key"),
    (lambda d: d["budget"].update(env_steps="many"), "budget.env_steps:"),
    (lambda d: d.pop("learner"), "learner: required field is missing"),
    (lambda d: d["env"].update(id="Animat/Nope-v0"), "env.id: unknown env id"),
    (lambda d: d["learner"].update(name="sgd"), "learner.name: unknown learner 'sgd'"),
    (lambda d: d["learner"].update(label="a b/c"), "learner.label: String should match"),
    (lambda d: d["learner"].update(label=".."), "learner.label: String should match"),
    (lambda d: d["learner"]["params"].update(refine={"env_steps": 3200}),
     "learner.params: learner 'annealing': refine.env_steps is gone: give refine.share"),
    (lambda d: d["budget"].update(env_steps=30),
     "budget.env_steps: 30 is less than one round of annealing: the learning phase needs at "
     "least 40 env steps (1 candidates x 40 env steps each)"),
    (lambda d: d["learner"].update(name="ppo", params={}),
     "budget.env_steps: 3200 is less than one PPO rollout (4096 env steps"),
    (lambda d: d["env"]["kwargs"].update(duration=-1),
     "env.kwargs: duration must be a finite number in (0, 86400] s, got -1"),
    (lambda d: d["learner"]["params"].update(chainz=3),
     "learner.params: learner 'annealing' does not take parameter(s) ['chainz']"),
])
def test_malformed_configs_fail_in_one_line(tmp_path, change, message):
    data = json.loads(json.dumps(TINY))
    change(data)
    config = write_config(tmp_path / "bad.yaml", data)
    result = animat("run", config, "--out", tmp_path / "run", check=False)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and str(config) in lines[0] and message in lines[0], result.stderr
    assert not (tmp_path / "run").exists()  # failed before any work


def test_bad_override_fails_in_one_line(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    for override, message in [("seed", "must look like key.path=value"),
                              ("seed=-1", "seed:"), ("budget.env_steps.x=3", "not a mapping")]:
        result = animat("run", config, "--set", override, check=False)
        assert result.returncode == 2 and message in result.stderr
        assert len(result.stderr.strip().splitlines()) == 1 and "Traceback" not in result.stderr


def test_every_shipped_config_takes_seed_and_budget_overrides():
    configs = sorted((ROOT / "configs").rglob("*.yaml"))
    assert {c.relative_to(ROOT / "configs").as_posix() for c in configs} >= {
        "quickstart.yaml", "fish_swim/annealing.yaml", "fish_swim/cmaes.yaml",
        "fish_swim/ppo.yaml", "fish_swim/handmc.yaml", "fish_basic_training/default.yaml",
        "fish_reach/macro.yaml"}
    for path in configs:
        config = load_config(path, ["seed=3", "budget.env_steps=5000000"])
        assert config.seed == 3 and config.budget.env_steps == 5_000_000


def test_config_error_names_file_and_path(tmp_path):
    with pytest.raises(ConfigError, match=r"nope.yaml: cannot read the file"):
        load_config(tmp_path / "nope.yaml")


def test_sigkilled_run_resumes_to_the_uninterrupted_result(tmp_path):
    data = json.loads(json.dumps(TINY))
    data["budget"]["env_steps"] = 24000
    data["learner"]["params"]["checkpoint_every"] = 1
    config = write_config(tmp_path / "long.yaml", data)
    animat("run", config, "--out", tmp_path / "whole")
    folder = tmp_path / "killed"
    process = subprocess.Popen([sys.executable, "-m", "animat.experiments", "run", str(config),
                                "--out", str(folder)], cwd=ROOT, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    checkpoint = folder / "checkpoints" / "checkpoint.json"
    deadline = time.time() + 300
    while time.time() < deadline and process.poll() is None:
        if checkpoint.exists() and len((folder / "scalars.csv").read_text().splitlines()) > 30:
            break
        time.sleep(0.05)
    assert process.poll() is None, "the run ended before it could be killed"
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    status = animat("compare", folder, check=False)  # readable while unfinished
    assert status.returncode == 0
    animat("run", "--resume", folder)
    whole = json.loads((tmp_path / "whole" / "result.json").read_text())
    resumed = json.loads((folder / "result.json").read_text())
    assert resumed["status"] == "done"
    assert resumed["env_steps"] == whole["env_steps"]
    assert resumed["metrics"] == whole["metrics"]  # bit for bit
    whole_art = json.loads((tmp_path / "whole" / "artefacts.json").read_text())
    resumed_art = json.loads((folder / "artefacts.json").read_text())
    assert resumed_art["controller"] == whole_art["controller"]


def test_resume_refuses_a_finished_run(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    animat("run", config, "--out", tmp_path / "run")
    result = animat("run", "--resume", tmp_path / "run", check=False)
    assert result.returncode == 2 and "nothing to resume" in result.stderr


def test_local_sweep_one_folder_per_seed(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    animat("sweep", config, "--seeds", "0-2", "--jobs", "2", "--out", tmp_path / "sweep")
    results = sorted((tmp_path / "sweep").rglob("result.json"))
    assert len(results) == 3
    seeds = sorted(yaml.safe_load((r.parent / "config.yaml").read_text())["seed"]
                   for r in results)
    assert seeds == [0, 1, 2]
    assert all(json.loads(r.read_text())["status"] == "done" for r in results)


def test_a_sweep_goes_on_past_a_failed_run_and_says_why(tmp_path, monkeypatch):
    from animat.learners.blackbox import AnnealingLearner

    learn = AnnealingLearner.learn

    def flaky(self, budget, checkpoint_dir=None):
        if self.seed == 1:
            raise RuntimeError("the simulator blew up (seed 1)")
        return learn(self, budget, checkpoint_dir)

    monkeypatch.setattr(AnnealingLearner, "learn", flaky)
    config = write_config(tmp_path / "tiny.yaml", TINY)
    result = animat("sweep", config, "--seeds", "0-2", "--out", tmp_path / "sweep", check=False)
    assert result.returncode == 1 and "Traceback" not in result.stdout + result.stderr
    lines = result.stdout.strip().splitlines()
    header, rows = lines[-5].split(), [line.split() for line in lines[-4:-1]]
    assert header[:3] == ["seed", "status", "eval/speed_bl_per_s"]
    assert [r[:2] for r in rows] == [["0", "done"], ["1", "failed"], ["2", "done"]]
    assert rows[1][2] == "—" and float(rows[0][2]) > 0
    assert lines[-1] == "seed 1 failed: RuntimeError: the simulator blew up (seed 1)"
    statuses = [json.loads(p.read_text())["status"]
                for p in sorted((tmp_path / "sweep").rglob("result.json"))]
    assert sorted(statuses) == ["done", "done", "failed"]  # seed 2 still ran


def test_version_help_examples_and_every_argument_helped(capsys):
    with pytest.raises(SystemExit) as done:
        cli.main(["--version"])
    assert done.value.code == 0 and "animat (artificial-animals) " in capsys.readouterr().out
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    text = capsys.readouterr().out
    assert "examples:" in text and "animat eval runs/try" in text
    parser = make_parser()
    for name, sub in parser._subparsers._group_actions[0].choices.items():
        for action in sub._actions:
            assert action.help, f"animat {name} {action.dest}: no help text"


def test_resume_refuses_what_it_would_ignore_and_runs_record_threads_and_commit(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    folder = tmp_path / "run"
    animat("run", config, "--out", folder, "--threads", "1")
    result = json.loads((folder / "result.json").read_text())
    assert result["status"] == "done" and result["threads"] == 1
    found = json.loads((folder / "versions.json").read_text())
    assert len(found["git_commit"]) == 40 and isinstance(found["git_dirty"], bool)
    for extra in ([str(config)], ["--set", "seed=4"], ["--out", str(tmp_path / "x")]):
        refused = animat("run", "--resume", folder, *extra, check=False)
        assert refused.returncode == 2 and "they would be ignored" in refused.stderr, extra


def _tensor_plugins(folder):
    """The TensorBoard plugins the run's event files write for."""
    from tensorboard.backend.event_processing.event_file_loader import EventFileLoader

    plugins = set()
    for events in (folder / "tb").glob("events.out.tfevents.*"):
        for event in EventFileLoader(str(events)).Load():
            for value in event.summary.value:
                plugins.add(value.metadata.plugin_data.plugin_name)
    return plugins


def test_curves_mean_the_same_for_every_learner_and_runs_keep_their_hparams(tmp_path):
    from animat.experiments.compare import read_scalars

    config = write_config(tmp_path / "tiny.yaml", TINY)
    animat("run", config, "--out", tmp_path / "anneal")
    curves = read_scalars(tmp_path / "anneal")
    (_, current), (_, best) = curves["eval/return"], curves["best/return"]
    assert np.all(np.diff(best) >= 0) and np.all(current <= best + 1e-12)  # incumbent vs best
    assert not np.all(current == best)  # the incumbent is not the best so far every round
    steps, fps = curves["time/fps"]  # env steps per wall second, as PPO's SB3 logs it
    result = json.loads((tmp_path / "anneal" / "result.json").read_text())
    assert np.all(fps > 0) and steps[-1] == result["env_steps"]
    assert fps[-1] == pytest.approx(result["env_steps"] / result["wall_seconds"], rel=0.2)
    assert "hparams" in _tensor_plugins(tmp_path / "anneal")  # TensorBoard's HParams view
    animat("run", config, "--out", tmp_path / "ppo", "--set", "learner.name=ppo",
           "--set", "learner.params={n_envs: 2, n_steps: 16, batch_size: 32, n_epochs: 1, "
                    "eval_every: 32}", "--set", "budget.env_steps=64")
    tags = set(read_scalars(tmp_path / "ppo"))
    assert {"eval/return", "train/value_loss", "train/approx_kl", "time/fps"} <= tags


def test_compare_reads_scalars_csv_without_events_and_shows_intervals(tmp_path):
    data = json.loads(json.dumps(TINY))
    data["logging"] = {"tensorboard": False, "csv": True, "progress": False}
    config = write_config(tmp_path / "csv.yaml", data)
    for seed in (0, 1, 2):
        animat("run", config, "--set", f"seed={seed}", "--out", tmp_path / "runs" / f"s{seed}")
    assert not (tmp_path / "runs" / "s0" / "tb").exists()
    text = animat("compare", tmp_path / "runs", "--metric", "eval/speed_bl_per_s").stdout
    row = next(line for line in text.splitlines() if line.startswith("| annealing |"))
    found = re.search(r"(-?\d+\.\d+) ± (\d+\.\d+) \[(-?\d+\.\d+), (-?\d+\.\d+)\]",
                      row.split("|")[3])
    mean, std, low, high = (float(v) for v in found.groups())
    assert low <= mean <= high and std > 0 and low < high and "95% bootstrap interval" in text


def test_world_bench_growth_arguments_are_checked_in_one_line(tmp_path):
    for args, message in ((["--fish", "0,10"], "each in [1, 3000]"),
                          (["--fish", "ten"], "give fish counts like 10,100,1000"),
                          (["--plot", tmp_path / "g.png"], "give --fish too")):
        result = animat("world-bench", *args, check=False)
        assert result.returncode == 2 and message in result.stderr
    result = animat("world-bench", "--fish", "5,10", "--seconds", "0.05", "--plot",
                    tmp_path / "g.png")
    assert "us/fish-step" in result.stdout and (tmp_path / "g.png").stat().st_size > 1000
