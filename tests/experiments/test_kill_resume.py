"""SIGKILL at random moments, then resume: every learner that checkpoints ends with exactly the
uninterrupted run's numbers, and its run folder holds each logged (tag, step) once.

Each case runs the config once whole, then kills a real ``python -m animat.experiments run``
process twice, each time once its log has reached a seeded random row (the second time while
it resumes), and finishes it with ``run --resume``. Slow (about half a minute per learner):
``python -m pytest -m slow -k kill``.
"""

import csv
import json
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.support.cli import ROOT, TINY, write_config

PPO = {"n_envs": 4, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "eval_every": 320,
       "checkpoint_every": 64, "policy_kwargs": "dict(net_arch=[16])",
       "normalize": "{'norm_obs': True, 'norm_reward': True}"}
CASES = {
    "annealing": {**TINY, "learner": {"name": "annealing", "params": {
        "chains": 8, "nodes": 4, "period": 0.5, "checkpoint_every": 1}},
        "budget": {"env_steps": 16000}},
    "cmaes": {**TINY, "learner": {"name": "cmaes", "params": {
        "popsize": 8, "nodes": 4, "period": 0.5, "checkpoint_every": 1,
        "refine": {"share": 0.25, "threshold": 0.3, "sigma0": 0.1}}},
        "budget": {"env_steps": 16000}},
    "macro": {"env": {"id": "Animat/FishReach-v0", "kwargs": {
        "duration": 2.0, "distance_bl": [2.0, 2.0], "bearing_deg": [180.0, 180.0]}},
        "learner": {"name": "macro", "params": {
            "repertoire": str(ROOT / "repertoires" / "fish.json"), "slots": 2,
            "min_duration": 0.5, "max_duration": 1.0, "chains": 8, "checkpoint_every": 1}},
        "budget": {"env_steps": 16000}, "seed": 0, "eval": {"metric": "eval/return"}},
    "ppo": {**TINY, "learner": {"name": "ppo", "params": PPO}, "budget": {"env_steps": 6400}},
    "basic_training": {**TINY, "learner": {"name": "basic_training", "params": {"regimen": [
        {"name": "swim", "env_id": "Animat/FishSwim-v0", "env_kwargs": {"duration": 0.5},
         "params": {"nodes": 4, "period": 0.5}},
        {"name": "turn", "env_id": "Animat/FishTurn-v0", "env_kwargs": {"duration": 0.5},
         "params": {"nodes": 4, "period": None}}],
        "annealing": {"chains": 8, "checkpoint_every": 1}}}, "budget": {"env_steps": 16000}},
}


def _animat(*args) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "animat.experiments", *map(str, args),
                             "--quiet"], cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def _finish(process: subprocess.Popen) -> None:
    _, err = process.communicate(timeout=600)
    assert process.returncode == 0, err


def _start_again(config: Path, folder: Path) -> subprocess.Popen | None:
    """What a user does after a kill: resume the run (or run it again into the same folder,
    killed before the folder was made whole)."""
    if not (folder / "result.json").exists():
        return _animat("run", config, "--out", folder)
    if json.loads((folder / "result.json").read_text())["status"] == "done":
        return None  # killed after it said so, while closing its logs
    return _animat("run", "--resume", folder)


def _wait_for_rows(process: subprocess.Popen | None, folder: Path, rows: int) -> None:
    """Until the run's scalars.csv has ``rows`` rows (or the process has ended)."""
    path = folder / "scalars.csv"
    while process is not None and process.poll() is None:
        if path.exists() and len(path.read_bytes().splitlines()) > rows:
            return
        time.sleep(0.01)


def _scalars(folder: Path) -> list[tuple[int, str, str]]:
    """scalars.csv's rows but the wall-clock ``time/*`` (a basic-training skill's too,
    ``skill/NAME/time/*``)."""
    with (folder / "scalars.csv").open(newline="") as file:
        return [(int(r["step"]), r["tag"], r["value"]) for r in csv.DictReader(file)
                if "time" not in r["tag"].split("/")[:-1]]


def _events(folder: Path) -> list[tuple[str, int]]:
    from tensorboard.backend.event_processing.event_file_loader import EventFileLoader

    return [(value.tag, event.step) for path in sorted((folder / "tb").glob("events.*"))
            for event in EventFileLoader(str(path)).Load() for value in event.summary.value]


@pytest.mark.slow
@pytest.mark.parametrize("name", CASES)
def test_a_run_killed_at_random_moments_resumes_to_the_uninterrupted_numbers(tmp_path, name):
    config = write_config(tmp_path / f"{name}.yaml",
                          {**CASES[name], "logging": {"tensorboard": True, "csv": True}})
    _finish(_animat("run", config, "--out", tmp_path / "whole"))
    total = len((tmp_path / "whole" / "scalars.csv").read_text().splitlines()) - 1
    draw, killed_learning = random.Random(name), 0
    for attempt in range(2):
        folder = tmp_path / f"killed{attempt}"
        process = _animat("run", config, "--out", folder)
        for _ in range(2):  # at a random row of its log, then again while it resumes
            _wait_for_rows(process, folder, draw.randint(1, total))
            if process is None or process.poll() is not None:  # done before this kill
                break
            process.send_signal(signal.SIGKILL)
            process.wait()
            killed_learning += (folder / "checkpoints").exists()
            process = _start_again(config, folder)
        if process is not None:
            _finish(process)
        whole = json.loads((tmp_path / "whole" / "result.json").read_text())
        resumed = json.loads((folder / "result.json").read_text())
        assert resumed["status"] == "done"
        assert resumed["metrics"] == whole["metrics"]  # bit for bit
        assert resumed["env_steps"] == whole["env_steps"]
        rows = _scalars(folder)
        assert len({(step, tag) for step, tag, _ in rows}) == len(rows)  # no row twice
        assert sorted(rows) == sorted(_scalars(tmp_path / "whole"))
        events = _events(folder)
        assert len(set(events)) == len(events)
        assert set(events) == set(_events(tmp_path / "whole"))
        assert not list(folder.rglob("*.tmp")) and not list(folder.rglob("*.partial"))
    assert killed_learning >= 2  # not all kills fell before the learning began
