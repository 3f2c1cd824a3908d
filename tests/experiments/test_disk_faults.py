"""Disk faults, for real: a full disk and a read-only one are a small tmpfs mounted in a private
mount namespace (``unshare -m``; these tests skip where no namespace can be made), filled up
or remounted read-only; a folder made read-only while it runs is ``chmod`` in a process
without the capability that lets root write anyway (``setpriv``). The disk fills, or the
folder turns read-only, at the run's first logged scalar (a logger sink that acts once), so
that the fault comes while the run works. Each fault ends in one line on stderr, leaves no
``*.tmp`` file and no run folder that says "running"."""

import errno
import json
import os
import shutil
import subprocess
import sys
import tempfile
from functools import cache

import pytest

from animat.experiments.launch import lock
from animat.experiments.launch.folders import read_status
from tests.support.cli import ROOT, TINY, animat, write_config

# animat's CLI whose progress sink acts once, at the run's first scalar: "fill" fills the
# disk the run is on, "readonly" takes the write permission off everything under a folder
HOOK = """
import os, sys
from animat.experiments import cli

action, where = sys.argv[1], sys.argv[2]

class Hook:
    done = False

    def scalar(self, tag, value, step):
        if self.done:
            return
        self.done = True
        if action == "fill":
            with open(os.path.join(where, "filler"), "wb") as file:
                try:
                    while True:
                        file.write(bytes(65536))
                        file.flush()
                except OSError:
                    pass
        else:
            for root, _, files in os.walk(where):
                for name in files:
                    os.chmod(os.path.join(root, name), 0o444)
                os.chmod(root, 0o555)

    def text(self, tag, text, step):
        pass

    def close(self):
        pass

cli._progress = lambda args, config: Hook()
sys.exit(cli.main(sys.argv[3:]))
"""

# inside the namespace: run the plan's steps (animat commands, hooked or not, and shell
# lines), then report each step's exit status and output, every file under the disk and
# each run folder's status as read_status reads it, as one JSON line
HARNESS = """
import json, subprocess, sys
from pathlib import Path
from animat.experiments.launch.folders import read_status

hook, disk, plan = sys.argv[1], Path(sys.argv[2]), json.loads(sys.argv[3])
steps = []
for step in plan:
    if "sh" in step:
        done = subprocess.run(step["sh"], shell=True, capture_output=True, text=True)
    else:
        head = ([sys.executable, hook, step["hook"], str(disk)] if step.get("hook") else
                [sys.executable, "-m", "animat.experiments"])
        done = subprocess.run(head + step["animat"], capture_output=True, text=True)
    steps.append({"rc": done.returncode, "stdout": done.stdout, "stderr": done.stderr})
files = sorted(str(p.relative_to(disk)) for p in disk.rglob("*"))
status = {str(p.parent.relative_to(disk)): read_status(p.parent)["status"]
          for p in disk.rglob("result.json")}
print(json.dumps({"steps": steps, "files": files, "status": status}))
"""


@cache
def _namespace() -> tuple[str, ...] | None:
    """The command that runs a process in a private mount namespace where a tmpfs can be
    mounted (root: ``unshare -m``; a user: ``unshare -r -m``), or None where there is none."""
    if shutil.which("unshare") is None:
        return None
    with tempfile.TemporaryDirectory() as where:
        for prefix in (("unshare", "-m"), ("unshare", "-r", "-m")):
            try:
                probe = subprocess.run([*prefix, "mount", "-t", "tmpfs", "-o", "size=1m",
                                        "tmpfs", where], capture_output=True, timeout=60)
            except (OSError, subprocess.SubprocessError):
                continue
            if probe.returncode == 0:
                return prefix
    return None


def _on_tmpfs(tmp_path, plan: list[dict], size: str = "8m") -> dict:
    """Run ``plan`` (see HARNESS) with a fresh tmpfs of ``size`` at ``tmp_path/disk``, in a
    private mount namespace (gone with it); what HARNESS reports."""
    prefix = _namespace()
    if prefix is None:
        pytest.skip("needs a private mount namespace (unshare -m) to mount a small tmpfs")
    (tmp_path / "hook.py").write_text(HOOK)
    (tmp_path / "harness.py").write_text(HARNESS)
    script = 'mount -t tmpfs -o size="$1" tmpfs "$2" && exec "$3" "$4" "$5" "$2" "$6"'
    done = subprocess.run([*prefix, "sh", "-c", script, "sh", size, tmp_path / "disk",
                           sys.executable, tmp_path / "harness.py", tmp_path / "hook.py",
                           json.dumps(plan)], capture_output=True, text=True, timeout=900,
                          cwd=ROOT)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def _one_line(step: dict, code: int, *words: str) -> None:
    """The step ended with exit status ``code`` and one line on stderr holding ``words``."""
    lines = step["stderr"].strip().splitlines()
    assert step["rc"] == code and len(lines) == 1, step
    assert all(word in lines[0] for word in words), lines[0]


def _said(result) -> dict:
    """An in-process ``animat(...)`` result as a step of :func:`_one_line`."""
    return {"rc": result.returncode, "stderr": result.stderr}


@pytest.fixture
def disk(tmp_path):
    (tmp_path / "disk").mkdir()
    return tmp_path / "disk"


def test_a_full_disk_while_running_is_one_line_and_the_folder_says_failed(tmp_path, disk):
    """The disk fills at the first scalar: the run's next write fails; result.json, which no
    new file can hold now, is overwritten in place and says "failed"."""
    config = write_config(tmp_path / "tiny.yaml", TINY)
    report = _on_tmpfs(tmp_path, [{"animat": ["run", str(config), "--out", f"{disk}/run"],
                                   "hook": "fill"}])
    (step,) = report["steps"]
    _one_line(step, 1, "No space left on device")
    assert not [f for f in report["files"] if f.endswith(".tmp")], report["files"]
    assert report["status"] == {"run": "failed"}


def test_a_full_disk_before_a_run_leaves_no_folder(tmp_path, disk):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    report = _on_tmpfs(tmp_path, [{"sh": f"cat /dev/zero > {disk}/filler"},
                                  {"animat": ["run", str(config), "--out", f"{disk}/runs/new"]}])
    _one_line(report["steps"][1], 1, "No space left on device", str(disk))
    assert report["files"] == ["filler"]  # no runs/, no half-made folder, no .tmp


def test_a_read_only_disk_refuses_a_run_and_a_resume_in_one_line_and_eval_still_scores(
        tmp_path, disk):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    failed = ("import json, sys; p = sys.argv[1]; d = json.load(open(p)); "
              "d['status'] = 'failed'; json.dump(d, open(p, 'w'))")
    report = _on_tmpfs(tmp_path, [
        {"animat": ["run", str(config), "--out", f"{disk}/run", "--quiet"]},
        {"sh": f"mount -o remount,ro {disk}"},
        {"animat": ["eval", f"{disk}/run", "--episodes", "1"]},
        {"animat": ["run", str(config), "--out", f"{disk}/new", "--quiet"]},
        {"sh": f"mount -o remount,rw {disk} && {sys.executable} -c \"{failed}\" "
               f"{disk}/run/result.json && mount -o remount,ro {disk}"},  # unfinished now
        {"animat": ["run", "--resume", f"{disk}/run", "--quiet"]}])
    made, remounted, scored, new, marked, resumed = report["steps"]
    assert made["rc"] == remounted["rc"] == marked["rc"] == 0, report["steps"]
    _one_line(scored, 1, "not written:", "eval.json: Read-only file system")
    assert "eval/speed_bl_per_s" in scored["stdout"]  # the score is printed all the same
    _one_line(new, 2, f"{disk}/new: cannot make a run folder there (Read-only file system)")
    _one_line(resumed, 2, f"{disk}/run: cannot write into the run folder (Read-only file system)")
    assert report["status"] == {"run": "failed"}
    assert not any(f.startswith("new") or f.endswith(".tmp") for f in report["files"])


def test_a_folder_made_read_only_while_running_is_one_line_and_is_not_left_running(tmp_path):
    """Root writes through any permission; the run's process here has not the capability
    (``setpriv --bounding-set -dac_override``), so the chmod binds it as it binds a user.
    result.json cannot be rewritten: it keeps "running", which every reader, here and on
    another host, reads as killed (the folder's lock is free)."""
    drop = []
    if os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.skip("needs setpriv to run without root's dac_override")
        drop = ["setpriv", "--bounding-set", "-dac_override,-dac_read_search", "--"]
    config = write_config(tmp_path / "tiny.yaml", TINY)
    (tmp_path / "hook.py").write_text(HOOK)
    where = tmp_path / "shared"
    done = subprocess.run([*drop, sys.executable, tmp_path / "hook.py", "readonly", where,
                           "run", config, "--out", where / "run"], capture_output=True,
                          text=True, timeout=600, cwd=ROOT)
    try:
        _one_line({"rc": done.returncode, "stderr": done.stderr}, 1, "Permission denied")
        assert not list(where.rglob("*.tmp"))
        assert json.loads((where / "run" / "result.json").read_text())["status"] == "running"
        assert read_status(where / "run")["status"] == "killed"
        status = json.loads((where / "run" / "result.json").read_text())
        (where / "run" / "result.json").chmod(0o644)
        (where / "run").chmod(0o755)
        (where / "run" / "result.json").write_text(json.dumps({**status, "host": "elsewhere"}))
        assert read_status(where / "run")["status"] == "killed"  # no pid to ask: the lock
    finally:
        for path in [where, *where.rglob("*")]:
            path.chmod(0o755 if path.is_dir() else 0o644)


def test_out_under_a_file_is_refused_in_one_line(tmp_path):
    config = write_config(tmp_path / "tiny.yaml", TINY)
    (tmp_path / "file").write_text("not a folder")
    under = animat("run", config, "--out", tmp_path / "file" / "run", check=False)
    _one_line(_said(under), 2, f"{tmp_path / 'file' / 'run'}: cannot make a run folder there",
              "Not a directory")
    itself = animat("run", config, "--out", tmp_path / "file", check=False)
    _one_line(_said(itself), 2, f"{tmp_path / 'file'}: is a file, not a folder")
    assert (tmp_path / "file").read_text() == "not a folder"


def test_a_file_system_without_locks_is_named_in_one_line(tmp_path, monkeypatch):
    """No file system without ``flock`` (some network ones) is at hand: its error is raised
    by ``fcntl.flock`` itself, as such a file system raises it."""
    def flock(handle, operation):
        raise OSError(errno.ENOLCK, os.strerror(errno.ENOLCK))

    monkeypatch.setattr(lock.fcntl, "flock", flock)
    config = write_config(tmp_path / "tiny.yaml", TINY)
    refused = animat("run", config, "--out", tmp_path / "run", check=False)
    _one_line(_said(refused), 2, "the file system does not support file locks",
              "No locks available")
