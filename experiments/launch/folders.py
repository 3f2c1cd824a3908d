"""Run folders: where one experiment keeps everything.

``runs/<env>/<learner>/seed<k>-<timestamp>/`` (or exactly ``--out DIR``) holds
``config.yaml`` (resolved), ``command.txt``, ``versions.json``, TensorBoard events in ``tb/``,
``scalars.csv``, ``checkpoints/`` and ``result.json``, written atomically:
``{"status": "running"|"done"|"failed", "env_steps", "wall_seconds", "metrics", ...}``
(a failed run's ``error`` is one line; its traceback is in ``error.log``)
(``pending`` for a folder a sweep has prepared but not started).
A run folder is never overwritten. A run that died without saying so (``running`` whose folder
lock is free: killed, or its last status not writable on a full or read-only disk) is reported
as ``killed``; ``animat run --resume DIR`` continues any unfinished run from its last
checkpoint. An OS error is one line (exit status 2 for a place that cannot hold a run folder,
1 while a run works) and leaves no temporary file or half-made folder.

This module makes and reads the folder; :mod:`.lock` is its lock, :mod:`.execute` runs it and
:mod:`.machine` says what it runs on (``versions.json``).
"""

from __future__ import annotations

import json
import os
import shlex
import socket
import stat
import time
from pathlib import Path

from animat.learners.base import LearnResult
from animat.learners.storage.files import (
    TMP_SUFFIX,
    UnsafeFile,
    atomic_write,
    make_dirs,
    read_bytes,
    read_json,
)
from animat.learners.storage.tree import run_folder, walk

from .config import ExperimentConfig, record_env, to_yaml
from .lock import LOCK_NAME, UNWRITABLE, RunError, lock_held, run_lock
from .machine import versions


def one_line(error: BaseException) -> str:
    """``Type: the first line of the message`` (at most 300 characters): what a failed run's
    result.json and the CLI say of an error."""
    lines = [line.strip() for line in str(error).splitlines() if line.strip()]
    line = f"{type(error).__name__}: {lines[0]}" if lines else type(error).__name__
    return line if len(line) <= 300 else line[:297] + "..."


def write_json(path: Path, data: dict) -> None:
    """Write JSON atomically (a reader never sees half a file)."""
    atomic_write(path, lambda file: json.dump(data, file, indent=1, default=str))


def default_run_dir(config: ExperimentConfig, root: Path = Path("runs")) -> Path:
    env = config.env.id.replace("/", "_")
    stamp = time.strftime("%Y%m%d-%H%M%S")
    base = root / env / config.learner.display_name / f"seed{config.seed}-{stamp}"
    candidate, k = base, 1
    while candidate.exists():
        candidate, k = base.with_name(f"{base.name}-{k}"), k + 1
    return candidate


def _refuse_if_used(folder: Path) -> None:
    """RunError if ``folder`` is a file, or holds anything but its lock file and what a run
    killed while its folder was being made left (:func:`_unfinished`, made again)."""
    if folder.exists() and not folder.is_dir():
        raise RunError(f"{folder}: is a file, not a folder; a run folder is never overwritten")
    if folder.exists() and not _unfinished(folder):
        raise RunError(f"{folder}: exists and is not empty; a run folder is never overwritten")


def _unfinished(folder: Path) -> bool:
    """Whether ``folder`` is empty, or holds the lock file :func:`create_run` makes first and
    nothing but the files :func:`_write_new_run` writes before its last, ``result.json`` (and
    their temporary files, a kept repertoire among them): a folder whose making was killed,
    which no run has used. A folder without the lock file is a user's, whatever its files are
    called."""
    names = {p.name for p in folder.iterdir()}
    if not names:
        return True
    return LOCK_NAME in names and "result.json" not in names and all(
        name in RUN_FILES or name.endswith(TMP_SUFFIX)
        or (name == KEPT_REPERTOIRE.parent.name and _only_kept(folder / name))
        for name in names - {LOCK_NAME})


def _only_kept(kept: Path) -> bool:
    """Whether ``kept`` is a folder (no link) holding at most the repertoire
    :func:`_write_new_run` copies in (and its temporary files)."""
    return kept.is_dir() and not kept.is_symlink() and all(
        p.name == KEPT_REPERTOIRE.name or p.name.endswith(TMP_SUFFIX) for p in kept.iterdir())


def clear_debris(folder: Path) -> None:
    """Remove the temporary files a killed process left in a run folder (``*.tmp``, which
    :func:`animat.learners.storage.files.atomic_write` writes before it renames one into
    place); only under the folder's lock, when no other process can be writing them."""
    for path, info in list(walk(folder)):
        if path.name.endswith(TMP_SUFFIX) and stat.S_ISREG(info.st_mode):
            path.unlink(missing_ok=True)


def create_run(config: ExperimentConfig, out: Path | None, command: list[str]) -> Path:
    """Make a new run folder (``out`` exactly, or the default under ``runs/``), under its lock
    (:func:`run_lock`): of two processes making one folder, one makes it and the other is
    refused. The lock is let go once it is made and taken again to run it, so a ``--resume``
    in between may be the one that runs it (still one run). A folder that cannot be made
    (a file in its path, a read-only disk) is a RunError; any OS error (a full disk) leaves
    nothing of it behind."""
    folder = run_folder(Path(out) if out else default_run_dir(config))
    made: list[Path] = []
    try:
        _refuse_if_used(folder)  # before anything, even a lock file, is written into it
        made = [p for p in (folder, *folder.parents) if not p.exists()]  # deepest first
        make_dirs(folder)
        with run_lock(folder):
            _refuse_if_used(folder)  # made meanwhile by another process
            clear_debris(folder)  # a killed making's
            try:
                _write_new_run(folder, config, command)
            except OSError:
                _unmake(folder, made)  # still holding the lock: no other process writes here
                raise
    except UnsafeFile:  # a link planted on the way
        _remove_empty(made)
        raise
    except OSError as error:
        _remove_empty(made)  # what is left of them: only empty folders are removed
        if error.errno not in UNWRITABLE:
            raise
        raise RunError(f"{folder}: cannot make a run folder there ({error.strerror})") from None
    return folder


RUN_FILES = ("config.yaml", "command.txt", "versions.json", "result.json")
KEPT_REPERTOIRE = Path("checkpoints") / "repertoire.json"  # where a run keeps the one it reads


def _write_new_run(folder: Path, config: ExperimentConfig, command: list[str]) -> None:
    """A new run folder's files, each written atomically, ``result.json`` ("pending") last;
    a repertoire the learner composes from is copied in first (``checkpoints/``), so that the
    folder, once made, reads no file outside it (a resume reads none: it may be someone
    else's, :func:`~animat.experiments.launch.config.learner_params`)."""
    repertoire = config.learner.params.get("repertoire")
    if isinstance(repertoire, str) and repertoire:
        kept = read_bytes(repertoire, "json")  # the user's file, its links resolved by the config
        atomic_write(folder / KEPT_REPERTOIRE, lambda file: file.write(kept), binary=True)
    atomic_write(folder / "config.yaml", lambda file: file.write(to_yaml(record_env(config))))
    atomic_write(folder / "command.txt", lambda file: file.write(shlex.join(command) + "\n"))
    write_json(folder / "versions.json", versions())
    write_json(folder / "result.json", make_status("pending", folder))


def _unmake(folder: Path, made: list[Path]) -> None:
    """Remove what :func:`create_run` wrote into ``folder`` (whose lock it holds), with the
    lock file if it made the folder (a folder it did not make keeps its lock file: another
    process may wait on it), then the folders it made. What cannot be removed is left."""
    names = RUN_FILES + (str(KEPT_REPERTOIRE),) + ((LOCK_NAME,) if folder in made else ())
    for name in names:
        try:
            (folder / name).unlink(missing_ok=True)
        except OSError:
            pass
    _remove_empty([folder / KEPT_REPERTOIRE.parent])
    _remove_empty(made)


def _remove_empty(made: list[Path]) -> None:
    """Remove the folders of ``made`` (deepest first) while they are empty."""
    for path in made:
        try:
            path.rmdir()
        except OSError:
            break


def make_status(status: str, folder: Path, result: LearnResult | None = None, **extra) -> dict:
    """A result.json's content: ``status``, this process and host, now, and ``result``'s
    env steps, wall seconds and metrics (none yet without one), with ``extra`` fields."""
    data = {"status": status, "env_steps": 0, "wall_seconds": 0.0, "metrics": {},
            "pid": os.getpid(), "host": socket.gethostname(), "updated": time.time(), **extra}
    if result is not None:
        data.update(env_steps=int(result.env_steps), wall_seconds=float(result.wall_seconds),
                    metrics={k: float(v) for k, v in result.metrics.items()})
    return data


def read_status(folder: Path) -> dict:
    """result.json, with ``status`` "killed" for a run whose process is gone: "running" is
    written only while the folder's lock is held, so a "running" folder whose lock is free
    died without a word (killed, or its last result.json could not be written on a full or
    read-only disk); where the lock cannot tell (an older folder), the recorded pid on this
    host."""
    path = run_folder(folder) / "result.json"
    if not os.path.lexists(path):
        raise RunError(f"{folder}: no result.json: not a run folder")
    data = read_json(path)
    if data.get("status") == "running" and not _still_running(Path(folder), data):
        data["status"] = "killed"
    return data


def _still_running(folder: Path, data: dict) -> bool:
    """Whether the process that wrote the "running" ``data`` runs: its folder's lock held;
    else (no lock to ask) its pid alive on this host (True when it cannot be told)."""
    held = lock_held(folder)
    if held is not None:
        return held
    if data.get("host") != socket.gethostname():
        return True
    try:
        os.kill(int(data.get("pid", -1)), 0)
    except (ProcessLookupError, ValueError):
        return False
    except PermissionError:
        pass
    return True


def find_runs(paths: list[str | Path]) -> list[Path]:
    """Run folders given directly or found below parent folders (any depth)."""
    found = []
    for path in map(Path, paths):
        if os.path.lexists(path / "result.json"):
            found.append(path)
        else:
            found.extend(sorted(p.parent for p in path.rglob("result.json")))
    if not found:
        raise FileNotFoundError(f"no run folders (with result.json) in {[str(p) for p in paths]}")
    return found
