"""Run folders: where one experiment keeps everything.

``runs/<env>/<learner>/seed<k>-<timestamp>/`` (or exactly ``--out DIR``) holds
``config.yaml`` (resolved), ``command.txt``, ``versions.json``, TensorBoard events in ``tb/``,
``scalars.csv``, ``checkpoints/`` and ``result.json``, written atomically:
``{"status": "running"|"done"|"failed", "env_steps", "wall_seconds", "metrics", ...}``
(a failed run's ``error`` is one line; its traceback is in ``error.log``)
(``pending`` for a folder a sweep has prepared but not started).
A run folder is never overwritten. A run that died without saying so (``running`` with a dead
process) is reported as ``killed``; ``animat run --resume DIR`` continues any unfinished run
from its last checkpoint.
"""

from __future__ import annotations

import fcntl
import json
import os
import shlex
import socket
import subprocess
import sys
import time
import traceback
from contextlib import contextmanager
from importlib import metadata
from pathlib import Path

from animat.experiments.config import ExperimentConfig, learner_params, load_config, to_yaml
from animat.learners.base import LearnResult, atomic_write, read_json
from animat.learners.logger import CsvSink, Logger, TensorBoardSink
from animat.learners.registry import make_learner

PACKAGES = ("artificial-animals", "numpy", "numba", "gymnasium", "stable-baselines3", "torch",
            "cma", "tensorboard", "pydantic", "pyyaml", "ray")


class RunError(RuntimeError):
    """A run-folder problem (exists already, nothing to resume, ...)."""


ERROR_LOG = "error.log"


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


def available_cpus() -> int:
    """CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def set_threads(threads: int | None) -> int:
    """Numba's threads for this run: ``threads`` (the CPUs it was given), else every CPU this
    process may use; never more than Numba started with. Returns the count set."""
    import numba

    count = max(1, min(int(threads or available_cpus()), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(count)
    return count


def source_revision() -> dict[str, object]:
    """The git commit of the code that runs, and whether it has uncommitted changes
    (``{}`` outside a git checkout: an installed wheel, even in a venv inside some
    repository, has no commit of its own)."""
    root = Path(__file__).resolve().parents[1]
    if not (root / ".git").exists():
        return {}
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], check=True,
                                capture_output=True, text=True, timeout=10).stdout.strip()
        changes = subprocess.run(["git", "-C", str(root), "status", "--porcelain",
                                  "--untracked-files=no"], check=True, capture_output=True,
                                 text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return {}
    return {"git_commit": commit, "git_dirty": bool(changes)}


def versions() -> dict[str, str]:
    found = {"python": sys.version.split()[0], **source_revision()}
    for name in PACKAGES:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return found


LOCK_NAME = ".lock"


@contextmanager
def run_lock(folder: Path):
    """Hold the run folder's exclusive lock for the ``with`` block: ``fcntl.flock`` on its
    ``.lock`` file, taken without waiting (RunError in one line if another process holds it)
    and released by the kernel when this process ends however it ends, so a killed run leaves
    no stale lock. Held while a folder is made and while it runs: one run per folder."""
    handle = os.open(Path(folder) / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise RunError(f"{folder}: another process is making or running this run (one run "
                           f"per folder)") from None
        os.ftruncate(handle, 0)
        os.write(handle, f"{os.getpid()}\n".encode())  # who holds it, for a person to read
        yield
    finally:
        os.close(handle)  # the only descriptor: closing it releases the lock


def folder_busy(folder: Path) -> bool:
    """Whether another process holds the run folder's lock (is making or running it): what a
    recorded pid cannot tell across hosts or after the pid is reused."""
    if not (Path(folder) / LOCK_NAME).exists():
        return False
    try:
        with run_lock(folder):
            return False
    except RunError:
        return True


def _refuse_if_used(folder: Path) -> None:
    """RunError if ``folder`` holds anything but its lock file."""
    if folder.exists() and any(p.name != LOCK_NAME for p in folder.iterdir()):
        raise RunError(f"{folder}: exists and is not empty; a run folder is never overwritten")


def create_run(config: ExperimentConfig, out: Path | None, command: list[str]) -> Path:
    """Make a new run folder (``out`` exactly, or the default under ``runs/``), under its lock
    (:func:`run_lock`): of two processes making one folder, one makes it and the other is
    refused. The lock is let go once it is made and taken again to run it, so a ``--resume``
    in between may be the one that runs it (still one run)."""
    folder = Path(out) if out else default_run_dir(config)
    _refuse_if_used(folder)  # before anything, even a lock file, is written into it
    folder.mkdir(parents=True, exist_ok=True)
    with run_lock(folder):
        _refuse_if_used(folder)  # made meanwhile by another process
        (folder / "config.yaml").write_text(to_yaml(config))
        (folder / "command.txt").write_text(shlex.join(command) + "\n")
        write_json(folder / "versions.json", versions())
        write_json(folder / "result.json", _status("pending", folder))
    return folder


def _status(status: str, folder: Path, result: LearnResult | None = None, **extra) -> dict:
    data = {"status": status, "env_steps": 0, "wall_seconds": 0.0, "metrics": {},
            "pid": os.getpid(), "host": socket.gethostname(), "updated": time.time(), **extra}
    if result is not None:
        data.update(env_steps=int(result.env_steps), wall_seconds=float(result.wall_seconds),
                    metrics={k: float(v) for k, v in result.metrics.items()})
    return data


def read_status(folder: Path) -> dict:
    """result.json, with ``status`` "killed" for a run whose process is gone."""
    path = Path(folder) / "result.json"
    if not path.exists():
        raise RunError(f"{folder}: no result.json: not a run folder")
    data = read_json(path)
    if data.get("status") == "running" and data.get("host") == socket.gethostname():
        try:
            os.kill(int(data.get("pid", -1)), 0)
        except (ProcessLookupError, ValueError):
            data["status"] = "killed"
        except PermissionError:
            pass
    return data


def flat_hparams(config: ExperimentConfig) -> dict[str, object]:
    """The config as TensorBoard hyperparameters: dotted names -> number, string or bool."""
    out: dict[str, object] = {}

    def walk(prefix: str, value) -> None:
        if isinstance(value, dict):
            for key, item in value.items():
                walk(f"{prefix}.{key}" if prefix else str(key), item)
        elif isinstance(value, bool | int | float | str):
            out[prefix] = value
        else:
            out[prefix] = str(value)

    data = config.model_dump(mode="json")
    walk("", {k: data[k] for k in ("env", "learner", "budget", "seed")})
    return out


def execute(folder: Path, progress=None, threads: int | None = None,
            trust_pickles: bool = False) -> dict:
    """Run (or continue) the experiment of a run folder with ``threads`` Numba threads (the
    CPUs it was given; default all this process may use), holding the folder's lock; returns
    the final result.json. RunError if another process holds the lock or the run is done."""
    folder = Path(folder)
    with run_lock(folder):
        if read_status(folder)["status"] == "done":  # finished by whoever held the lock
            raise RunError(f"{folder}: the run is done; nothing to resume")
        return _execute_locked(folder, progress, threads, trust_pickles)


def _failed(folder: Path, error: BaseException, threads: int | None) -> None:
    """Mark the run failed with the error's one line, its traceback in ``error.log``, and tag
    the error with the folder (the CLI points at the log)."""
    trace = traceback.format_exc()
    (folder / ERROR_LOG).write_text(trace)
    write_json(folder / "result.json", _status("failed", folder, error=one_line(error),
                                               traceback=trace, threads=threads))
    try:
        error.run_folder = folder
    except AttributeError:  # an exception type that takes no attributes
        pass


def _execute_locked(folder: Path, progress, threads: int | None, trust_pickles: bool) -> dict:
    (folder / ERROR_LOG).unlink(missing_ok=True)  # an earlier attempt's
    try:  # a config its folder can no longer build (a file it needs gone) fails the run too
        config = load_config(folder / "config.yaml")
    except Exception as error:
        _failed(folder, error, threads)
        raise
    threads = set_threads(threads)
    write_json(folder / "result.json", _status("running", folder, threads=threads))
    sinks = []
    if config.logging.tensorboard:
        sinks.append(TensorBoardSink(folder / "tb"))
    if config.logging.csv:
        sinks.append(CsvSink(folder / "scalars.csv"))
    if progress is not None:
        sinks.append(progress)
    logger = Logger(sinks)
    try:
        learner = make_learner(config.learner.name, config.env.id, config.env.kwargs,
                               learner_params(folder, config), config.seed, logger)
        learner.trust_pickles = trust_pickles  # an older version's pickled checkpoint
        result = learner.learn(config.budget.env_steps, folder / "checkpoints")
    except BaseException as error:
        logger.close()
        _failed(folder, error, threads)
        raise
    write_json(folder / "artefacts.json", dict(result.artefacts))
    final = _status("done", folder, result, threads=threads)
    write_json(folder / "result.json", final)
    try:  # extras after the result is safe: a failure here loses nothing
        logger.hparams(flat_hparams(config), {k: float(v) for k, v in result.metrics.items()})
    except Exception as error:
        print(f"animat: warning: {folder}: hyperparameters not written to TensorBoard: {error}",
              file=sys.stderr)
    finally:
        logger.close()
    return final


def resume(folder: Path, progress=None, threads: int | None = None,
           trust_pickles: bool = False) -> dict:
    """Continue an unfinished run from its last checkpoint (``trust_pickles``: also from an
    older version's pickled one)."""
    status = read_status(folder)
    if status["status"] == "done":
        raise RunError(f"{folder}: the run is done; nothing to resume")
    if status["status"] == "running" and folder_busy(folder):
        raise RunError(f"{folder}: the run is still running (pid {status.get('pid')})")
    return execute(folder, progress, threads, trust_pickles)  # a "running" one that died
