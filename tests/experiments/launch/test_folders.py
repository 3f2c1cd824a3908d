"""One run per folder: the folder's lock is held while it is made and while it runs, so of two
processes given one ``--out`` (or two ``--resume``s of one folder) exactly one runs and the
other is refused in one line; a killed run leaves no stale lock."""

import json
import subprocess
import sys
import time

import pytest

from animat.experiments.launch.config import ConfigError
from animat.experiments.launch.folders import read_status
from animat.experiments.launch.lock import run_lock
from animat.experiments.sweep import load_seed
from tests.support.cli import ROOT, TINY, animat, write_config
from tests.support.folders import finished, set_status

# both processes import everything first, then start the command at the same instant
RACE = """
import sys, time
from animat.experiments.cli import main
start = float(sys.argv[1])
while time.time() < start:
    pass
sys.exit(main(sys.argv[2:]))
"""


def _race(*commands: list[str]) -> list[subprocess.CompletedProcess]:
    start = time.time() + 8.0  # after both have imported
    procs = [subprocess.Popen([sys.executable, "-c", RACE, str(start), *map(str, c)], cwd=ROOT,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for c in commands]
    return [subprocess.CompletedProcess(p.args, p.wait(timeout=600), *p.communicate())
            for p in procs]


def _refused_once(done: list[subprocess.CompletedProcess]) -> subprocess.CompletedProcess:
    codes = sorted(d.returncode for d in done)
    assert codes == [0, 2], [d.stderr for d in done]
    refused = next(d for d in done if d.returncode == 2)
    assert len(refused.stderr.strip().splitlines()) == 1, refused.stderr
    return refused


def test_a_held_lock_refuses_a_run_and_a_resume_in_one_line_and_writes_nothing(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    empty = tmp_path / "empty"
    empty.mkdir()
    with run_lock(empty):
        refused = animat("run", config, "--out", empty, check=False)
    assert refused.returncode == 2 and "another process is making or running" in refused.stderr
    assert sorted(p.name for p in empty.iterdir()) == [".lock"]
    (folder,) = finished(tmp_path, "run")
    set_status(folder, status="failed")
    with run_lock(folder):
        again = animat("run", "--resume", folder, check=False)
    assert again.returncode == 2 and len(again.stderr.strip().splitlines()) == 1
    assert json.loads((folder / "result.json").read_text())["status"] == "failed"  # untouched
    animat("run", "--resume", folder, "--quiet")  # the lock is free again: it resumes


def test_two_processes_given_one_out_folder_run_it_once(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    folder = tmp_path / "run"
    done = _race(["run", config, "--out", folder, "--set", "seed=0", "--quiet"],
                 ["run", config, "--out", folder, "--set", "seed=1", "--quiet"])
    _refused_once(done)
    winner = next(d for d in done if d.returncode == 0)
    seed = int(winner.args[winner.args.index("--set") + 1].split("=")[1])
    assert f"seed: {seed}" in (folder / "config.yaml").read_text()
    rows = (folder / "scalars.csv").read_text().splitlines()
    assert len(rows) == len(set(rows))  # one run's rows, none twice
    writers = {p.name.split(".")[-2] for p in (folder / "tb").rglob("events.out.tfevents.*")}
    assert len(writers) == 1  # the event files of one process (their names end in pid.k)


def test_two_resumes_of_one_folder_run_it_once(tmp_path):
    (folder,) = finished(tmp_path, "run")
    set_status(folder, status="failed")
    refused = _refused_once(_race(["run", "--resume", folder, "--quiet"],
                                  ["run", "--resume", folder, "--quiet"]))
    assert any(m in refused.stderr for m in ("another process", "still running", "is done"))
    assert json.loads((folder / "result.json").read_text())["status"] == "done"


def test_a_corrupt_file_of_a_run_folder_is_named_in_one_line_and_compare_goes_on(tmp_path):
    good, broken = finished(tmp_path, "good", "broken")
    (broken / "artefacts.json").write_text('{"controller": ')  # truncated
    refused = animat("eval", broken, "--episodes", "1", check=False)
    assert refused.returncode == 2 and len(refused.stderr.strip().splitlines()) == 1
    assert f"{broken / 'artefacts.json'}: not valid JSON" in refused.stderr
    (broken / "result.json").write_text("")  # empty
    compared = animat("compare", tmp_path / "runs", "--metric", "eval/speed_bl_per_s")
    assert f"animat: warning: {broken}: left out" in compared.stderr
    assert "| annealing | 1 (1) |" in compared.stdout
    set_status(good, status="failed")
    (good / "checkpoints" / "checkpoint.json").write_text('{"format": "artificial-ani')
    resumed = animat("run", "--resume", good, check=False)
    assert resumed.returncode == 1 and len(resumed.stderr.strip().splitlines()) == 1
    assert f"{good / 'checkpoints' / 'checkpoint.json'}: cannot be read back" in resumed.stderr
    for text in (b"[" * 100_000, b'{"format": "\xff\xfe"}'):  # too deep; not UTF-8
        (good / "checkpoints" / "checkpoint.json").write_bytes(text)
        resumed = animat("run", "--resume", good, check=False)
        assert resumed.returncode == 1 and len(resumed.stderr.strip().splitlines()) == 1
        assert "checkpoint.json: cannot be read back" in resumed.stderr, resumed.stderr
    (good / "result.json").write_bytes(b"\xff\xfe{}")
    refused = animat("eval", good, check=False)
    assert refused.returncode == 2 and "result.json: not JSON text" in refused.stderr
    (good / "config.yaml").write_bytes(b"\xff\xfe: 1")
    compared = animat("compare", good, check=False)
    assert "config.yaml: not a text file (not UTF-8)" in compared.stderr


def test_inf_and_nan_survive_the_run_folder_and_yaml_aliases_are_refused(tmp_path):
    data = json.loads(json.dumps(TINY))
    data["env"]["kwargs"]["water"] = {"surface_z": float("inf")}  # the documented "no surface"
    folder = tmp_path / "run"
    animat("run", write_config(tmp_path / "inf.yaml", data), "--out", folder, "--quiet")
    assert "surface_z: .inf" in (folder / "config.yaml").read_text()
    assert json.loads((folder / "result.json").read_text())["status"] == "done"
    bomb = tmp_path / "bomb.yaml"
    bomb.write_text((tmp_path / "inf.yaml").read_text() + "x: &a [1, 1]\ny: [*a, *a]\n")
    refused = animat("run", bomb, "--out", tmp_path / "bomb", check=False)
    assert refused.returncode == 2 and "YAML aliases (*name) are not accepted" in refused.stderr
    assert not (tmp_path / "bomb").exists()


def test_a_running_status_whose_lock_is_free_is_a_dead_run_and_resumes(tmp_path):
    """The recorded pid can be alive and someone else's (reused, or another host's): the
    folder's lock, which the kernel frees when the run's process dies, is what says."""
    import os

    (folder,) = finished(tmp_path, "run")
    set_status(folder, status="running", pid=os.getpid())  # alive: this one
    animat("run", "--resume", folder, "--quiet")
    assert json.loads((folder / "result.json").read_text())["status"] == "done"


def test_compare_leaves_out_a_run_whose_config_is_malformed(tmp_path):
    good, odd = finished(tmp_path, "good", "odd")
    text = (odd / "config.yaml").read_text().replace("label: null", "label: [x]")
    (odd / "config.yaml").write_text(text)
    compared = animat("compare", tmp_path / "runs", "--metric", "eval/speed_bl_per_s")
    assert f"{odd}: left out" in compared.stderr and "| annealing | 1 (1) |" in compared.stdout


def test_a_running_status_from_another_host_is_read_by_its_lock(tmp_path):
    """No pid can be asked across hosts; the folder's lock (free once the run's process is
    gone, however it went) says whether the run still runs."""
    (folder,) = finished(tmp_path, "run")
    set_status(folder, status="running", host="elsewhere", pid=1)
    assert read_status(folder)["status"] == "killed"
    with run_lock(folder):  # held, as by a live run
        assert read_status(folder)["status"] == "running"


def test_a_sweeps_seed_is_read_as_every_config_is(tmp_path):
    """``load_seed`` refuses YAML aliases (a few nested ones expand to gigabytes) in a run
    folder's config.yaml, as every config read is."""
    (folder,) = finished(tmp_path, "run")
    assert load_seed(folder) == 0
    text = (folder / "config.yaml").read_text()
    (folder / "config.yaml").write_text(text + "x: &a [1, 1]\ny: [*a, *a]\n")
    with pytest.raises(ConfigError, match="YAML aliases"):
        load_seed(folder)


def test_a_folder_whose_making_was_killed_is_made_again_and_debris_is_cleared(tmp_path):
    """Killed while its folder was being made (its lock file, config.yaml written, result.json
    not yet, a temporary file half-written), a run is started again into the same folder;
    killed while it ran, its temporary files are gone once it resumes. A folder a run has used
    stays refused, and so does a user's folder that holds a file of the same name."""
    config = write_config(tmp_path / "tiny.yaml", TINY)
    users = tmp_path / "notes"
    users.mkdir()
    (users / "config.yaml").write_text("# my notes")
    refused = animat("run", config, "--out", users, check=False)
    assert refused.returncode == 2 and "exists and is not empty" in refused.stderr
    assert (users / "config.yaml").read_text() == "# my notes"
    folder = tmp_path / "run"
    folder.mkdir()
    (folder / ".lock").write_text("12345\n")
    (folder / "config.yaml").write_text("half of a config")
    (folder / "versions.json1a2b.tmp").write_text("{")
    animat("run", config, "--out", folder, "--quiet")
    assert read_status(folder)["status"] == "done"
    assert not list(folder.rglob("*.tmp"))
    refused = animat("run", config, "--out", folder, check=False)
    assert refused.returncode == 2 and "exists and is not empty" in refused.stderr
    set_status(folder, status="failed")
    (folder / "checkpoints" / "checkpoint.jsonx9y8.tmp").write_text('{"format": "art')
    animat("run", "--resume", folder, "--quiet")
    assert not list(folder.rglob("*.tmp"))


def test_a_reader_asking_at_the_same_instant_does_not_refuse_a_run(tmp_path):
    """lock_held (what read_status and compare ask) takes a shared lock for an instant: a run
    taking the folder's lock then waits that instant out instead of refusing."""
    import fcntl
    import os
    import threading

    folder = tmp_path / "run"
    folder.mkdir()
    (folder / ".lock").touch()
    reader = os.open(folder / ".lock", os.O_RDONLY)
    fcntl.flock(reader, fcntl.LOCK_SH)
    threading.Timer(0.03, os.close, [reader]).start()
    with run_lock(folder):
        assert (folder / ".lock").read_text().strip() == str(os.getpid())
