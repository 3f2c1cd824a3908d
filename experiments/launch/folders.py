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
"""

from __future__ import annotations

import errno
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

from animat.learners.base import TMP_SUFFIX, LearnResult, atomic_write, read_json
from animat.learners.logger import CsvSink, Logger, TensorBoardSink
from animat.learners.registry import make_learner

from .config import ExperimentConfig, learner_params, load_config, to_yaml

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
    root = Path(__file__).resolve().parents[2]
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
# OS errors that say a place cannot hold a run folder (what the user chose), not that the
# disk failed while working: a read-only file system, no permission, a file in the path
UNWRITABLE = {errno.EROFS, errno.EACCES, errno.EPERM, errno.ENOTDIR, errno.EEXIST,
              errno.ENOENT, errno.ENAMETOOLONG, errno.ELOOP}


@contextmanager
def run_lock(folder: Path):
    """Hold the run folder's exclusive lock for the ``with`` block: ``fcntl.flock`` on its
    ``.lock`` file, taken without waiting (RunError in one line if another process holds it)
    and released by the kernel when this process ends however it ends, so a killed run leaves
    no stale lock. Held while a folder is made and while it runs: one run per folder. A folder
    that cannot be written (read-only) or a file system without locks is a RunError too."""
    try:
        handle = os.open(Path(folder) / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        if error.errno not in UNWRITABLE:
            raise  # a full disk: the OS error itself
        raise RunError(f"{folder}: cannot write into the run folder ({error.strerror}); a run "
                       f"needs its folder writable") from None
    try:
        _lock_exclusive(handle, folder)
        try:
            os.ftruncate(handle, 0)
            os.write(handle, f"{os.getpid()}\n".encode())  # who holds it, for a person to read
        except OSError:  # a full disk: the lock holds without the note
            pass
        yield
    finally:
        os.close(handle)  # the only descriptor: closing it releases the lock


NO_LOCKS = {errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOTSUP, errno.ENOSYS}  # flock: no locks here


LOCK_TRIES = 10  # a reader's shared lock (lock_held) lasts an instant: a few tries 10 ms apart


def _lock_exclusive(handle: int, folder: Path) -> None:
    """``flock`` the open lock file exclusively (a few short tries, so that a reader asking
    :func:`lock_held` at that instant does not refuse a run); RunError in one line if another
    process holds it or the file system has no locks (some network file systems)."""
    try:
        for attempt in range(LOCK_TRIES):
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                return
            except BlockingIOError:
                if attempt == LOCK_TRIES - 1:
                    raise
                time.sleep(0.01)
    except BlockingIOError:
        raise RunError(f"{folder}: another process is making or running this run (one run "
                       f"per folder)") from None
    except OSError as error:
        if error.errno not in NO_LOCKS:
            raise
        raise RunError(f"{folder}: the file system does not support file locks (flock: "
                       f"{error.strerror}), which keep one run per folder; put the run folder "
                       f"on a local disk (--out)") from None


def lock_held(folder: Path) -> bool | None:
    """Whether a process holds the run folder's lock (is making or running it): True or
    False, or None when the lock cannot tell (no lock file: an older folder; a file system
    without locks). Takes a shared lock on a read-only descriptor for an instant, so it writes
    nothing and works on a read-only folder; what a recorded pid cannot tell across hosts or
    after the pid is reused."""
    try:
        handle = os.open(Path(folder) / LOCK_NAME, os.O_RDONLY)
    except OSError:
        return None
    try:
        fcntl.flock(handle, fcntl.LOCK_SH | fcntl.LOCK_NB)
        return False
    except BlockingIOError:
        return True
    except OSError:
        return None
    finally:
        os.close(handle)  # releases the shared lock, if taken


def folder_busy(folder: Path) -> bool:
    """Whether another process holds the run folder's lock (:func:`lock_held`; False when it
    cannot tell)."""
    return lock_held(folder) is True


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
    their temporary files): a folder whose making was killed, which no run has used. A folder
    without the lock file is a user's, whatever its files are called."""
    names = {p.name for p in folder.iterdir()}
    if not names:
        return True
    return LOCK_NAME in names and "result.json" not in names and all(
        name in RUN_FILES or name.endswith(TMP_SUFFIX) for name in names - {LOCK_NAME})


def clear_debris(folder: Path) -> None:
    """Remove the temporary files a killed process left in a run folder (``*.tmp``, which
    :func:`animat.learners.base.atomic_write` writes before it renames one into place); only
    under the folder's lock, when no other process can be writing them."""
    for path in Path(folder).rglob(f"*{TMP_SUFFIX}"):
        if path.is_file():
            path.unlink(missing_ok=True)


def create_run(config: ExperimentConfig, out: Path | None, command: list[str]) -> Path:
    """Make a new run folder (``out`` exactly, or the default under ``runs/``), under its lock
    (:func:`run_lock`): of two processes making one folder, one makes it and the other is
    refused. The lock is let go once it is made and taken again to run it, so a ``--resume``
    in between may be the one that runs it (still one run). A folder that cannot be made
    (a file in its path, a read-only disk) is a RunError; any OS error (a full disk) leaves
    nothing of it behind."""
    folder = Path(out) if out else default_run_dir(config)
    _refuse_if_used(folder)  # before anything, even a lock file, is written into it
    made = [p for p in (folder, *folder.parents) if not p.exists()]  # deepest first
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with run_lock(folder):
            _refuse_if_used(folder)  # made meanwhile by another process
            clear_debris(folder)  # a killed making's
            try:
                _write_new_run(folder, config, command)
            except OSError:
                _unmake(folder, made)  # still holding the lock: no other process writes here
                raise
    except OSError as error:
        _remove_empty(made)  # what is left of them: only empty folders are removed
        if error.errno not in UNWRITABLE:
            raise
        raise RunError(f"{folder}: cannot make a run folder there ({error.strerror})") from None
    return folder


RUN_FILES = ("config.yaml", "command.txt", "versions.json", "result.json")


def _write_new_run(folder: Path, config: ExperimentConfig, command: list[str]) -> None:
    """A new run folder's files, each written atomically, ``result.json`` ("pending") last."""
    atomic_write(folder / "config.yaml", lambda file: file.write(to_yaml(config)))
    atomic_write(folder / "command.txt", lambda file: file.write(shlex.join(command) + "\n"))
    write_json(folder / "versions.json", versions())
    write_json(folder / "result.json", _status("pending", folder))


def _unmake(folder: Path, made: list[Path]) -> None:
    """Remove what :func:`create_run` wrote into ``folder`` (whose lock it holds), with the
    lock file if it made the folder (a folder it did not make keeps its lock file: another
    process may wait on it), then the folders it made. What cannot be removed is left."""
    names = RUN_FILES + ((LOCK_NAME,) if folder in made else ())
    for name in names:
        try:
            (folder / name).unlink(missing_ok=True)
        except OSError:
            pass
    _remove_empty(made)


def _remove_empty(made: list[Path]) -> None:
    """Remove the folders of ``made`` (deepest first) while they are empty."""
    for path in made:
        try:
            path.rmdir()
        except OSError:
            break


def _status(status: str, folder: Path, result: LearnResult | None = None, **extra) -> dict:
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
    path = Path(folder) / "result.json"
    if not path.exists():
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
        try:
            return _execute_locked(folder, progress, threads, trust_pickles)
        except BaseException as error:
            if getattr(error, "run_folder", None) is None:  # not recorded yet (e.g. an OS
                _failed(folder, error, threads)  # error writing a status or the artefacts)
            raise


def _failed(folder: Path, error: BaseException, threads: int | None) -> None:
    """Mark the run failed with the error's one line (result.json first: readers go by it),
    its traceback in ``error.log``, each as far as the disk lets (:func:`_record`); tag the
    error with the folder and the log that holds its traceback (the CLI points at it)."""
    trace = traceback.format_exc()
    _record(folder, _status("failed", folder, error=one_line(error), traceback=trace,
                            threads=threads))
    log: Path | None = folder / ERROR_LOG
    try:
        atomic_write(log, lambda file: file.write(trace))
    except OSError:
        log = None
    for name, value in (("run_folder", folder), ("error_log", log)):
        try:
            setattr(error, name, value)
        except AttributeError:  # an exception type that takes no attributes
            pass


def _record(folder: Path, status: dict) -> bool:
    """Write ``status`` as result.json, atomically; on a disk too full for a new file,
    overwrite the one there in place (within the blocks it has: no new space), without the
    traceback. Returns whether it was written; if not, a "running" one left there is read as
    killed (:func:`read_status`: the lock is free once this process ends)."""
    path = folder / "result.json"
    try:
        write_json(path, status)
        return True
    except OSError:
        pass
    brief = json.dumps({k: v for k, v in status.items() if k != "traceback"},
                       default=str).encode()
    try:
        handle = os.open(path, os.O_WRONLY)
    except OSError:
        return False
    try:
        stat = os.fstat(handle)
        text = brief + b" " * (stat.st_size - len(brief))  # JSON allows trailing spaces
        if len(text) > stat.st_blocks * 512:
            return False  # it would need blocks the file does not have
        # one write and no truncation: no shorter text leaves the old one's tail behind
        written = os.write(handle, text)
        os.fsync(handle)
        return written == len(text)
    except OSError:
        return False
    finally:
        os.close(handle)


def _execute_locked(folder: Path, progress, threads: int | None, trust_pickles: bool) -> dict:
    (folder / ERROR_LOG).unlink(missing_ok=True)  # an earlier attempt's
    clear_debris(folder)  # a killed attempt's
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
