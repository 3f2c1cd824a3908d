"""Sweeps and tunes as Ray tasks: on a cluster of two Ray nodes started on this machine over
loopback (``ray start --head`` and ``ray start --address``, as on two machines), and on a
local cluster Ray starts itself."""

import json
import os
import shutil
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from animat.experiments.executors import run_ray
from animat.experiments.launch.config import validate
from animat.experiments.sweep import prepare
from tests.support.cli import TINY, animat, write_config

ray = pytest.importorskip("ray")

SHORT = {**TINY, "budget": {"env_steps": 400},
         "logging": {"tensorboard": True, "csv": True, "progress": False}}


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _ray_cli(*args: str, tries: int = 1) -> None:
    """``ray ARGS``, again up to ``tries`` times (a node joining a head just started may find
    it not ready yet); its output in the failure's message."""
    ray_bin = Path(sys.executable).with_name("ray")
    command = [str(ray_bin) if ray_bin.exists() else shutil.which("ray") or "ray", *args]
    env = {**os.environ, "RAY_USAGE_STATS_ENABLED": "0",
           "PATH": f"{ray_bin.parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    for _ in range(tries):
        done = subprocess.run(command, capture_output=True, text=True, timeout=120, env=env)
        if done.returncode == 0:
            return
        time.sleep(3.0)
    raise AssertionError(f"{' '.join(args)} failed: {done.stdout[-2000:]}\n{done.stderr[-2000:]}")


@pytest.fixture(scope="module")
def two_nodes(tmp_path_factory):
    """A head and a worker node of one CPU each, on 127.0.0.1: the cluster's address. Ray's
    files under HOME are this fixture's own while it lasts (a ``~/.ray/auth_token`` that a
    local ``ray.init`` leaves there stops a node joining a cluster started without one)."""
    port, home = _free_port(), os.environ.get("HOME")
    address = f"127.0.0.1:{port}"
    os.environ["HOME"] = str(tmp_path_factory.mktemp("home"))
    try:
        _ray_cli("start", "--head", "--node-ip-address=127.0.0.1", f"--port={port}",
                 "--num-cpus=1", "--include-dashboard=false", "--disable-usage-stats")
        _ray_cli("start", f"--address={address}", "--node-ip-address=127.0.0.1",
                 "--num-cpus=1", tries=3)
        yield address
    finally:
        _ray_cli("stop", "--force")
        if home is None:
            os.environ.pop("HOME", None)
        else:
            os.environ["HOME"] = home


def test_a_sweep_on_two_ray_nodes_returns_every_run_folder_to_the_driver(two_nodes, tmp_path):
    config = write_config(tmp_path / "tiny.yaml", SHORT)
    result = animat("sweep", config, "--seeds", "0-1", "--executor", "ray", "--address",
                    two_nodes, "--out", tmp_path / "runs")
    folders = sorted((tmp_path / "runs").glob("*/*/seed*"))
    assert len(folders) == 2
    for folder in folders:  # run in a node's temporary folder, then returned here
        assert json.loads((folder / "result.json").read_text())["status"] == "done"
        assert (folder / "scalars.csv").read_text().count("\n") > 2
        assert list((folder / "tb").glob("events.out.tfevents.*"))
    rows = [line.split() for line in result.stdout.splitlines() if line[:1].isdigit()]
    assert len(rows) == 2 and len({row[5] for row in rows}) == 2  # one seed on each node
    assert not list((tmp_path / "runs").rglob(".seed*"))  # no staging folder left


def test_two_tune_workers_share_one_study_and_never_run_a_parameter_set_twice(tmp_path):
    space = {"learner.params.nodes": {"choices": [3, 4]},
             "learner.params.chains": {"choices": [4, 8]}}  # four parameter sets in all
    config = write_config(tmp_path / "tune.yaml", {**SHORT, "tune": {"space": space},
                                                  "logging": {"progress": False}})
    out = tmp_path / "study"
    animat("tune", config, "--trials", "4", "--workers", "2", "--out", out)
    rows = json.loads((out / "tune.json").read_text())["trials"]
    ran = [row for row in rows if "not run again" not in (row["error"] or "")]
    assert sorted(tuple(sorted(r["params"].items())) for r in ran) == sorted(
        {tuple(sorted(r["params"].items())) for r in ran})  # no set twice
    assert len(ran) == 4 and all(r["state"] in ("COMPLETE", "PRUNED") for r in ran)
    pids = {json.loads((out / f"trial{r['trial']:03d}" / "result.json").read_text())["pid"]
            for r in ran}
    assert len(pids) == 2  # both workers ran trials
    for row in rows:
        if row not in ran:  # a twin: told, not run
            assert not (out / f"trial{row['trial']:03d}").exists()


@pytest.mark.slow
def test_a_tune_as_ray_tasks_on_two_nodes(two_nodes, tmp_path):
    config = write_config(tmp_path / "tune.yaml", {
        **SHORT, "tune": {"space": {"learner.params.cooling": {"low": 0.5, "high": 0.99}}}})
    out = tmp_path / "study"  # its journal file: on this machine, every node's
    animat("tune", config, "--trials", "3", "--workers", "2", "--executor", "ray",
           "--address", two_nodes, "--out", out)
    rows = json.loads((out / "tune.json").read_text())["trials"]
    assert len(rows) >= 3 and sum(r["state"] == "COMPLETE" for r in rows) >= 3


@pytest.mark.slow
def test_ray_sweep_on_a_local_cluster_runs_every_seed_into_its_folder(tmp_path):
    config = validate({**SHORT, "seed": 0}, "test")
    folders = prepare(config, [0, 1], tmp_path, ["test"])
    ray.init(address="local", num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        results = run_ray(folders)
    finally:
        ray.shutdown()
    assert [r["status"] for r in results] == ["done", "done"]
    for folder in folders:
        assert (Path(folder) / "tb").exists() and (Path(folder) / "scalars.csv").exists()
