"""Running a run folder: :func:`execute` runs (or continues) the experiment a folder holds,
under its lock, from its own ``config.yaml``; :func:`resume` continues an unfinished one. The
run's status goes into ``result.json`` as it goes (running, then done or failed, with the
error's one line and its traceback in ``error.log``), as far as the disk lets.
:func:`run_experiment` is ``animat run CONFIG`` from Python (a config file, a shipped config's
name or a config mapping), in the caller's process: the learners, tasks, bodies and env ids the
caller registered are there (docs/tutorials/extending.md).
"""

from __future__ import annotations

import json
import os
import sys
import traceback
from pathlib import Path

from animat.learners.logger import CsvSink, Logger, Sink, TensorBoardSink
from animat.learners.registry import make_learner
from animat.learners.storage.files import atomic_write, open_file
from animat.learners.storage.tree import check_tree, run_folder

from .config import (
    ExperimentConfig,
    check_buildable,
    config_from_data,
    learner_params,
    load_config,
    load_run_config,
)
from .folders import clear_debris, create_run, make_status, one_line, read_status, write_json
from .lock import RunError, folder_busy, run_lock
from .machine import set_threads

ERROR_LOG = "error.log"


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
            trust_pickles: bool = False, own_files_only: bool = False,
            checked: bool = False) -> dict:
    """Run (or continue) the experiment of a run folder with ``threads`` Numba threads (the
    CPUs it was given; default all this process may use), holding the folder's lock; returns
    the final result.json. RunError if another process holds the lock or the run is done;
    UnsafeFile, before anything is written, for a folder holding anything but regular files
    and folders (:func:`~animat.learners.storage.tree.check_tree`). ``own_files_only``: the
    folder may be someone else's (a resume), so its config reaches no file outside it
    (:func:`~animat.experiments.launch.config.learner_params`: a RunError before anything is
    written where it would have to). ``progress``: a logger sink with ``finish(env_steps)``,
    called when the learner is done with the env steps it ran
    (:mod:`animat.experiments.launch.progress`; tune's pruning sink). ``checked``: the folder
    was just made from a config this process built once
    (:func:`~animat.experiments.launch.config.check_buildable`), so its env and learner are not
    built again to check it."""
    folder = run_folder(folder)
    with run_lock(folder):
        check_tree(folder, writing=True)  # a link, FIFO or hard link planted in a shared folder
        if read_status(folder)["status"] == "done":  # finished by whoever held the lock
            raise RunError(f"{folder}: the run is done; nothing to resume")
        if own_files_only:
            _check_own_files(folder)
        try:
            return _execute_locked(folder, progress, threads, trust_pickles, own_files_only,
                                   checked)
        except BaseException as error:
            if getattr(error, "run_folder", None) is None:  # not recorded yet (e.g. an OS
                _failed(folder, error, threads)  # error writing a status or the artefacts)
            raise


def _check_own_files(folder: Path) -> None:
    """RunError, before anything is written, where the folder's config would reach a file
    outside it (:func:`~animat.experiments.launch.config.learner_params`); a warning where
    it names an output, which the run leaves as it is."""
    config = load_run_config(folder)
    learner_params(folder, config, own_files_only=True)
    if "output" in config.learner.params:
        print(f"animat: warning: {folder}: a resumed run writes nothing outside its folder; "
              "learner.params.output is left as it is, the repertoire kept in the folder",
              file=sys.stderr)


def _failed(folder: Path, error: BaseException, threads: int | None) -> None:
    """Mark the run failed with the error's one line (result.json first: readers go by it),
    its traceback in ``error.log``, each as far as the disk lets (:func:`_record`); tag the
    error with the folder and the log that holds its traceback (the CLI points at it)."""
    trace = traceback.format_exc()
    _record(folder, make_status("failed", folder, error=one_line(error), traceback=trace,
                                threads=threads))
    log: Path | None = folder / ERROR_LOG
    try:
        atomic_write(folder / ERROR_LOG, lambda file: file.write(trace))
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
        handle = open_file(path, os.O_WRONLY)
    except (OSError, ValueError):  # gone, or not a regular file of the folder's own
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


def _execute_locked(folder: Path, progress, threads: int | None, trust_pickles: bool,
                    own_files_only: bool, checked: bool) -> dict:
    (folder / ERROR_LOG).unlink(missing_ok=True)  # an earlier attempt's
    clear_debris(folder)  # a killed attempt's
    try:  # a config its folder can no longer build (a file it needs gone) fails the run too
        config = load_run_config(folder, build=not checked, own_files_only=own_files_only)
    except Exception as error:
        _failed(folder, error, threads)
        raise
    threads = set_threads(threads)
    write_json(folder / "result.json", make_status("running", folder, threads=threads))
    sinks: list[Sink] = []
    if config.logging.tensorboard:
        sinks.append(TensorBoardSink(folder / "tb"))
    if config.logging.csv:
        sinks.append(CsvSink(folder / "scalars.csv"))
    if progress is not None:
        sinks.append(progress)
    logger = Logger(sinks)
    try:
        learner = make_learner(config.learner.name, config.env.id, config.env.kwargs,
                               learner_params(folder, config, own_files_only), config.seed,
                               logger)
        learner.trust_pickles = trust_pickles  # an older version's pickled checkpoint
        result = learner.learn(config.budget.env_steps, folder / "checkpoints")
    except BaseException as error:
        logger.close()
        _failed(folder, error, threads)
        raise
    if progress is not None:
        progress.finish(int(result.env_steps))
    write_json(folder / "artefacts.json", dict(result.artefacts))
    try:  # before "done", so a run killed in between writes them on resume (each sink once)
        logger.hparams(flat_hparams(config), {k: float(v) for k, v in result.metrics.items()})
    except Exception as error:  # an extra: a failure here loses nothing
        print(f"animat: warning: {folder}: hyperparameters not written to TensorBoard: {error}",
              file=sys.stderr)
    finally:
        logger.close()
    final = make_status("done", folder, result, threads=threads)
    write_json(folder / "result.json", final)
    return final


def resume(folder: Path, progress=None, threads: int | None = None,
           trust_pickles: bool = False) -> dict:
    """Continue an unfinished run from its last checkpoint (``trust_pickles``: also from an
    older version's pickled one), as a folder that may be someone else's: its config reaches
    no file outside it (``own_files_only``; a ``learner.params.output`` is not written)."""
    status = read_status(folder)
    if status["status"] == "done":
        raise RunError(f"{folder}: the run is done; nothing to resume")
    if status["status"] == "running" and folder_busy(folder):
        raise RunError(f"{folder}: the run is still running (pid {status.get('pid')})")
    return execute(folder, progress, threads, trust_pickles, own_files_only=True)


def run_experiment(config: dict | str | Path, overrides: list[str] | None = None,
                   out: str | Path | None = None, threads: int | None = None,
                   progress: bool = True) -> tuple[Path, dict]:
    """What ``animat run CONFIG [--set ...] [--out DIR] [--threads N]`` does, from Python: check
    ``config`` (a config file, a shipped config's name, or a mapping of the file's fields),
    with ``overrides`` (``key.path=value``) applied, and build its env and learner once; make
    its run folder (``out`` exactly, or one under ``runs/``); run it here (``threads``: Numba's
    threads, default every CPU this process may use), with the progress lines of
    :mod:`.progress` unless ``progress`` is False or the config's ``logging.progress`` is.
    Returns (the run folder, its final result.json). Refusals as the command's:
    :class:`~.config_yaml.ConfigError` naming the field, :class:`~.lock.RunError`.

    It runs in the caller's process, so a config may name what the caller registered
    (:func:`animat.learners.register_learner`, :func:`animat.envs.register_env`); ``animat run``
    in another process knows only the package's own. A mapping's relative file params are
    taken from the current directory."""
    from .progress import ProgressSink, compile_notice
    from .shipped import find_config

    if threads is not None and (type(threads) is not int or threads < 1):
        raise RunError(f"threads must be an integer of at least 1, got {threads!r}")
    if isinstance(config, dict):
        source = "<config mapping>"
        loaded = config_from_data(config, source, Path.cwd(), overrides)
        check_buildable(loaded, source)
    else:
        source = str(find_config(config))
        loaded = load_config(source, overrides)
    command = ["run_experiment", source, *[f"--set={o}" for o in overrides or []]]
    folder = create_run(loaded, Path(out) if out is not None else None, command)
    sink = None
    if progress and loaded.logging.progress:
        compile_notice()
        sink = ProgressSink.for_output(loaded.budget.env_steps, loaded.eval.metric)
    return folder, execute(folder, sink, threads, checked=True)
