"""A run folder someone else wrote is untrusted input: a link, a FIFO, a device or a hard link
planted in it makes ``animat run --out``, ``--resume``, ``eval`` and ``compare`` refuse in one
line (exit 2), within seconds, with nothing outside the folder read, written or truncated and
the folder itself left as it was."""

import json
import os
import shutil
import stat
import subprocess
import sys

import pytest

from tests.support.cli import ROOT, TINY, animat, write_config
from tests.support.folders import finished, set_status


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory):
    """One finished run of the tiny config, copied by each test that changes it."""
    return finished(tmp_path_factory.mktemp("hostile"), "run")[0]


@pytest.fixture
def outside(tmp_path):
    """A file and a folder outside every run folder, which nothing may change."""
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "notes.txt").write_text("my notes\n")
    return tmp_path / "outside"


def _copy(finished_run, tmp_path, unfinished: bool = False):
    folder = tmp_path / "shared"
    shutil.copytree(finished_run, folder, symlinks=True)
    if unfinished:
        set_status(folder, status="failed")
    return folder


def _snapshot(*roots) -> dict:
    """Every entry below ``roots`` (links as links): its kind and bytes; a run folder's own lock
    file (the pid of whoever last held it) only as being there."""
    seen = {}
    for root in roots:
        for base, folders, names in os.walk(root):
            for name in folders + names:
                path = os.path.join(base, name)
                own_lock = name == ".lock" and os.lstat(path).st_nlink == 1
                seen[path] = (os.readlink(path) if os.path.islink(path) else
                              "folder" if os.path.isdir(path) else "FIFO"
                              if not os.path.isfile(path) else "lock" if own_lock
                              else open(path, "rb").read())
    return seen


def _refused(result, *names: str) -> None:
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 2 and len(lines) == 1, result.stderr
    assert all(name in lines[0] for name in names), lines[0]


def _link(target, at) -> None:
    os.symlink(target, at)


PLANTS = {  # where, what -> the file the refusal names
    "lock link": (".lock", lambda o, at: _link(o / "notes.txt", at)),
    "lock hard link": (".lock", lambda o, at: os.link(o / "notes.txt", at)),
    "lock FIFO": (".lock", lambda o, at: os.mkfifo(at)),
    "scalars link": ("scalars.csv", lambda o, at: _link(o / "notes.txt", at)),
    "scalars hard link": ("scalars.csv", lambda o, at: os.link(o / "notes.txt", at)),
    "tb link": ("tb", lambda o, at: _link(o, at)),
    "checkpoints link": ("checkpoints", lambda o, at: _link(o, at)),
    "config link": ("config.yaml", lambda o, at: _link(o / "notes.txt", at)),
    "artefacts link to a device": ("artefacts.json", lambda o, at: _link("/dev/zero", at)),
    "artefacts device": ("artefacts.json", lambda o, at: _device(at)),
    "result FIFO": ("result.json", lambda o, at: os.mkfifo(at)),
}


def _plant(folder, outside, case) -> str:
    name, make = PLANTS[case]
    target = folder / name
    if target.is_dir() and not target.is_symlink():
        shutil.rmtree(target)
    elif os.path.lexists(target):
        target.unlink()
    make(outside, target)
    return name


@pytest.mark.parametrize("case", sorted(PLANTS))
def test_resume_refuses_a_planted_entry_and_changes_nothing(finished_run, tmp_path, outside,
                                                            case):
    folder = _copy(finished_run, tmp_path, unfinished=True)
    name = _plant(folder, outside, case)
    before = _snapshot(folder, outside)
    _refused(_cli("run", "--resume", folder), name)
    assert _snapshot(folder, outside) == before


def _device(at) -> None:
    """A character device like /dev/null at ``at`` (making one takes root)."""
    try:
        os.mknod(at, 0o600 | stat.S_IFCHR, os.makedev(1, 3))
    except PermissionError:
        pytest.skip("making a device needs root")


READ_ONLY_SAFE = {"lock hard link", "scalars hard link"}  # read, a hard link is a plain file


@pytest.mark.parametrize("case", sorted(set(PLANTS) - READ_ONLY_SAFE))
def test_eval_refuses_a_planted_entry_and_changes_nothing(finished_run, tmp_path, outside,
                                                          case):
    folder = _copy(finished_run, tmp_path)
    name = _plant(folder, outside, case)
    before = _snapshot(folder, outside)
    _refused(_cli("eval", folder, "--episodes", "1"), name)
    assert _snapshot(folder, outside) == before


def _cli(*args):
    """``animat ARGS`` in a subprocess that must end within a minute (a FIFO read would block
    for ever), its output kept."""
    return subprocess.run([sys.executable, "-m", "animat.experiments", *map(str, args)],
                          cwd=ROOT, capture_output=True, text=True, timeout=60)


@pytest.mark.parametrize("case", ["lock link", "lock hard link", "lock FIFO"])
def test_a_new_run_into_a_folder_holding_a_planted_lock_is_refused(tmp_path, outside, case):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    folder = tmp_path / "d"
    folder.mkdir()
    _plant(folder, outside, case)
    before = _snapshot(folder, outside)
    _refused(animat("run", config, "--out", folder, "--quiet", check=False), ".lock")
    assert _snapshot(folder, outside) == before


def test_a_run_folder_that_is_a_link_is_refused(finished_run, tmp_path):
    folder = _copy(finished_run, tmp_path, unfinished=True)
    (tmp_path / "link").symlink_to(folder)
    before = _snapshot(folder)
    _refused(animat("run", "--resume", tmp_path / "link", check=False), "symbolic link")
    _refused(animat("eval", tmp_path / "link", check=False), "symbolic link")
    config = write_config(tmp_path / "tiny.yaml", TINY)
    (tmp_path / "empty").mkdir()
    (tmp_path / "to-empty").symlink_to(tmp_path / "empty")
    _refused(animat("run", config, "--out", tmp_path / "to-empty", check=False), "symbolic")
    assert _snapshot(folder) == before and list((tmp_path / "empty").iterdir()) == []


def test_a_run_folder_under_a_linked_parent_is_used_where_it_is(finished_run, tmp_path):
    """Where a user keeps runs may be a link: the parents are resolved once."""
    (tmp_path / "real").mkdir()
    (tmp_path / "runs").symlink_to(tmp_path / "real")
    shutil.copytree(finished_run, tmp_path / "real" / "run", symlinks=True)
    assert "written:" in animat("eval", tmp_path / "runs" / "run", "--episodes", "1").stdout
    assert (tmp_path / "real" / "run" / "eval.json").is_file()


def test_compare_leaves_out_a_folder_holding_a_link(finished_run, tmp_path, outside):
    good = _copy(finished_run, tmp_path / "a")
    bad = _copy(finished_run, tmp_path / "b")
    (bad / "scalars.csv").unlink()
    shutil.rmtree(bad / "tb")
    (bad / "tb").symlink_to(good / "tb")
    compared = animat("compare", good, bad, "--metric", "eval/speed_bl_per_s")
    assert f"{bad}: left out" in compared.stderr and "symbolic link" in compared.stderr


def test_nan_in_artefacts_is_named_with_its_file(finished_run, tmp_path):
    folder = _copy(finished_run, tmp_path)
    artefacts = _poisoned(json.loads((folder / "artefacts.json").read_text()))
    assert "NaN" in json.dumps(artefacts)
    (folder / "artefacts.json").write_text(json.dumps(artefacts))
    _refused(animat("eval", folder, "--episodes", "1", check=False), "artefacts.json")


def _poisoned(data):
    """``data`` with its first float replaced by NaN."""
    if isinstance(data, float):
        return float("nan")
    if isinstance(data, list) and data:
        return [_poisoned(data[0]), *data[1:]]
    if isinstance(data, dict):
        for key, value in data.items():
            changed = _poisoned(value)
            if json.dumps(changed) != json.dumps(value):
                return {**data, key: changed}
    return data


def test_eval_reads_a_hard_linked_copy_and_changes_nothing_outside(finished_run, tmp_path,
                                                                   outside):
    """A copy made with ``cp -al`` (rsync --link-dest, DVC's cache) is read as it is: reading
    a hard link reads the folder's own file; a run that writes in place refuses it."""
    folder = tmp_path / "copy"
    subprocess.run(["cp", "-al", str(finished_run), str(folder)], check=True)
    before = _snapshot(finished_run, outside)
    assert "written:" in _cli("eval", folder, "--episodes", "1").stdout
    assert _snapshot(finished_run, outside) == before
    set_status(folder, status="failed")
    _refused(_cli("run", "--resume", folder), "other hard link")


def test_resume_writes_no_output_and_reads_no_repertoire_outside_its_folder(
        finished_run, tmp_path, outside):
    import yaml

    folder = _copy(finished_run, tmp_path, unfinished=True)
    config = yaml.safe_load((folder / "config.yaml").read_text())
    config["learner"] = {"name": "macro", "params": {
        "chains": 8, "slots": 2, "repertoire": str(outside / "notes.txt")}}
    config["env"]["id"] = "Animat/FishReach-v0"
    (folder / "config.yaml").write_text(yaml.safe_dump(config))
    before = _snapshot(folder, outside)
    _refused(_cli("run", "--resume", folder), "learner.params.repertoire names")
    assert _snapshot(folder, outside) == before


def test_a_resumed_run_leaves_its_configs_output_alone(tmp_path, outside):
    from animat.experiments.launch.config import learner_params, validate

    config = validate({**TINY, "learner": {"name": "basic_training", "params": {
        "output": str(outside / "notes.txt"), "force": True}}}, "test")
    assert learner_params(tmp_path, config)["output"] == str(outside / "notes.txt")
    resumed = learner_params(tmp_path, config, own_files_only=True)
    assert "output" not in resumed and "force" not in resumed


def test_compare_reads_a_folder_under_a_linked_parent(finished_run, tmp_path):
    (tmp_path / "real").mkdir()
    (tmp_path / "runs").symlink_to(tmp_path / "real")
    shutil.copytree(finished_run, tmp_path / "real" / "run", symlinks=True)
    compared = animat("compare", tmp_path / "runs" / "run", "--metric", "eval/speed_bl_per_s")
    assert "| annealing |" in compared.stdout and "left out" not in compared.stderr
