"""``animat tune CONFIG --trials N``: hyperparameter search with Optuna over a config's
``tune.space``, every trial an ordinary run folder.

The study (TPE sampler, median pruner) lives in ``OUT/journal.log`` (Optuna's JournalStorage
on a file, which several processes may share; ``OUT/study.db``, SQLite, where an older study
left one; or ``--storage URL``, an RDB such as PostgreSQL for a cluster), so a killed tune
continues where it stopped when run again with the same ``--out`` (the trial it was running
counts as failed; its folder says ``killed``). Each trial's sample is drawn by a sampler seeded
by the config's seed and the trial's number, so a restarted tune (or a second process on the
same study) draws new samples, never the ones an earlier start drew. Each trial samples the
space (config field paths such as ``learner.params.cooling``), validates the config with those
values like ``animat run`` does (a sample that cannot work is told to the study as failed), and
runs it into ``OUT/trial<k>/``; the learner's ``eval.metric`` evaluations are reported to the
study as they are logged, and a trial whose curve falls below the median of earlier trials at
the same env step is pruned (its folder says ``pruned``). The trial's value is the run's result
for ``eval.metric``. At the end: a table of the trials, and ``OUT/best.yaml``, the resolved
config of the best trial (the tuned config).

``--workers N`` runs N workers on the study at once (processes here, or Ray tasks with
``--executor ray``: :mod:`animat.experiments.executors`); whatever the workers, a parameter set
already tried, or being tried, is never run again: the sample is told to the study as a failed
twin (:func:`twin_of`), not run, and not counted in the trials.
"""

from __future__ import annotations

import hashlib
import json
import os
import time
from pathlib import Path

from animat.learners.storage.files import (
    atomic_write,
    make_dirs,
    open_file,
    read_text,
)
from animat.learners.storage.tree import run_folder

from .executors import run_workers
from .launch.config import (
    ConfigError,
    ExperimentConfig,
    load_config,
    record_env,
    to_yaml,
)
from .launch.execute import execute
from .launch.folders import create_run, read_status, write_json
from .launch.lock import RunError


def _optuna():
    try:
        import optuna
    except ImportError:
        raise RunError("animat tune needs Optuna: pip install optuna") from None
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    return optuna


def sample(trial, config: ExperimentConfig) -> list[str]:
    """``key.path=value`` overrides of one trial's sample of ``config.tune.space``."""
    overrides = []
    for path, dim in config.tune.space.items():
        if dim.choices is not None:
            value = trial.suggest_categorical(path, dim.choices)
        elif all(isinstance(v, int) for v in (dim.low, dim.high)) and (
                dim.step is None or isinstance(dim.step, int)):
            value = trial.suggest_int(path, dim.low, dim.high, log=dim.log, step=dim.step or 1)
        else:
            value = trial.suggest_float(path, float(dim.low), float(dim.high), log=dim.log,
                                        step=dim.step)
        overrides.append(f"{path}={json.dumps(value)}")
    return overrides


class PruningSink:
    """Reports the metric's evaluations to the trial and stops the run when the pruner says
    so (a logger sink: ``scalar``, ``text``, ``close``; and ``finish``, as a run's progress)."""

    def __init__(self, trial, metric: str, pruned: type[Exception]) -> None:
        self.trial, self.metric, self.pruned, self.last = trial, metric, pruned, -1

    def scalar(self, tag: str, value: float, step: int) -> None:
        if tag != self.metric or step <= self.last:
            return
        self.last = step
        self.trial.report(value, step)
        if self.trial.should_prune():
            raise self.pruned(f"pruned at {step} env steps ({self.metric} {value:.4g})")

    def text(self, tag: str, text: str, step: int) -> None:
        pass

    def finish(self, env_steps: int) -> None:
        """The run is done (nothing to report: the trial's value is the run's result)."""

    def close(self) -> None:
        pass


def run_trial(optuna, trial, path: Path, overrides: list[str], out: Path,
              config: ExperimentConfig) -> tuple[str, float | None]:
    """One trial: its state name and value."""
    try:
        sampled = sample(trial, config)
        twin = twin_of(optuna, trial)
        if twin is not None:  # never run twice (another worker may have drawn it too)
            trial.set_user_attr("duplicate_of", twin)
            trial.set_user_attr("error", f"the parameters of trial {twin}: not run again")
            return "FAIL", None
        trial_config = load_config(path, overrides + sampled)
    except ConfigError as error:
        trial.set_user_attr("error", str(error))
        return "FAIL", None
    # best.yaml's, wherever it ran: the trial folder's config.yaml, its water and start written out
    trial.set_user_attr("config", to_yaml(record_env(trial_config)))
    folder = out / f"trial{trial.number:03d}"
    create_run(trial_config, folder, ["animat", "tune", str(path), f"(trial {trial.number})"])
    sink = PruningSink(trial, config.eval.metric, optuna.TrialPruned)
    try:
        result = execute(folder, sink)
    except optuna.TrialPruned as reason:
        write_json(folder / "result.json", {**read_status(folder), "status": "pruned",
                                            "error": str(reason)})
        return "PRUNED", None
    except Exception as error:
        trial.set_user_attr("error", f"{type(error).__name__}: {error}")
        return "FAIL", None
    value = result["metrics"].get(config.eval.metric)
    return ("COMPLETE", float(value)) if value is not None else ("FAIL", None)


def twin_of(optuna, trial) -> int | None:
    """The number of another trial of the study with ``trial``'s parameters that ran, runs or
    is about to (complete, pruned or running, not itself a twin), or None."""
    states = optuna.trial.TrialState
    for other in trial.study.get_trials(deepcopy=False, states=(
            states.COMPLETE, states.PRUNED, states.RUNNING)):
        if (other.number != trial.number and other.params == trial.params
                and "duplicate_of" not in other.user_attrs):
            return other.number
    return None


def storage(optuna, out: Path, url: str | None):
    """Where the study lives: ``url`` (an RDB URL) when given; else ``OUT/study.db`` where an
    older study left one; else a journal file, ``OUT/journal.log``."""
    if url:
        return url
    for name in ("study.db", "journal.log"):  # a shared OUT's: no link or FIFO written through
        if os.path.lexists(out / name):
            os.close(open_file(out / name, os.O_RDWR))
    lock = out / "journal.log.lock"  # Optuna's lock, a link to the journal while it is held
    if os.path.islink(lock) and os.path.realpath(lock) != os.path.realpath(out / "journal.log"):
        raise RunError(f"{lock}: a lock that is not this study's (a link to "
                       f"{os.readlink(lock)}); remove it if no tune is running")
    if (out / "study.db").exists():
        return f"sqlite:///{out / 'study.db'}"
    from optuna.storages.journal import JournalFileBackend

    return optuna.storages.JournalStorage(JournalFileBackend(str(out / "journal.log")))


def trial_sampler(optuna, seed: int, number: int):
    """The sampler for trial ``number``: TPE seeded by the config's seed and the number, so
    that no restart or second worker replays another trial's random draws."""
    return optuna.samplers.TPESampler(seed=(seed * 1_000_003 + number) % 2**32)


LOCAL_STUDY = "tune"  # the study of a storage in OUT (one per folder; every version's name)


def default_study_name(optuna, path: Path, overrides: list[str], url: str | None,
                       out: Path) -> str:
    """The study's name when ``--study`` is not given. In OUT's own storage: ``tune``, as
    ever. In a shared RDB (``url``): the config file's name and a digest of its text and the
    overrides, so that workers given the same command join one study and another config or
    override starts its own; but a study an older version made there (``tune``, whose trial
    folders are in OUT) is continued."""
    if not url:
        return LOCAL_STUDY
    text = "\n".join([read_text(path, "config", follow_links=True), *overrides])
    name = f"{path.stem}-{hashlib.sha256(text.encode()).hexdigest()[:8]}"
    names = optuna.study.get_all_study_names(storage=url)
    if name not in names and LOCAL_STUDY in names and any(out.glob("trial[0-9]*")):
        return LOCAL_STUDY
    return name


def open_study(optuna, config: ExperimentConfig, out: Path, url: str | None, name: str):
    """The study ``name`` in its storage (:func:`storage`), made if it is new: TPE sampler,
    median pruner, the config's direction."""
    return optuna.create_study(
        storage=storage(optuna, out, url), study_name=name, load_if_exists=True,
        direction=config.tune.direction, sampler=trial_sampler(optuna, config.seed, 0),
        pruner=optuna.pruners.MedianPruner(n_startup_trials=3,
                                           n_warmup_steps=config.budget.env_steps // 4))


def tune(path: str | Path, trials: int, out: str | Path | None = None,
         overrides: list[str] | None = None, storage_url: str | None = None,
         study_name: str | None = None, workers: int = 1, executor: str = "local",
         address: str | None = None) -> dict:
    """Run the study (``study_name``, default :func:`default_study_name`) to ``trials``
    finished trials, here (``workers`` 1) or by ``workers`` workers at once
    (:func:`animat.experiments.executors.run_workers`: processes, or Ray tasks on the
    cluster at ``address``); returns its summary (also printed by the CLI) and writes
    ``best.yaml``."""
    optuna = _optuna()
    path, overrides = Path(path), list(overrides or [])
    config = load_config(path, overrides)
    if config.tune is None or not config.tune.space:
        raise RunError(f"{path}: no tune.space: say which fields to search, e.g. "
                       "tune: {space: {learner.params.cooling: {low: 0.8, high: 0.99}}}")
    stamp = time.strftime("%Y%m%d-%H%M%S")
    out = run_folder(Path(out) if out else Path("runs") / "tune" / f"{path.stem}-{stamp}")
    make_dirs(out)
    name = study_name or default_study_name(optuna, path, overrides, storage_url, out)
    study = open_study(optuna, config, out, storage_url, name)
    for stale in study.get_trials(states=(optuna.trial.TrialState.RUNNING,)):
        if _killed(out / f"trial{stale.number:03d}"):  # a killed tune's, not a live worker's
            study.tell(stale.number, state=optuna.trial.TrialState.FAIL)
    if workers > 1 or executor == "ray":
        run_workers(worker, workers, executor, address, str(path), trials, str(out), overrides,
                    storage_url, name)
        study = open_study(optuna, config, out, storage_url, name)  # every worker's trials
    else:
        work(optuna, study, config, path, overrides, out, trials)
    return summarise(study, out, config, path, overrides)


MAX_TWINS = 200  # twins in a row: the space holds no parameter set not yet tried


def finished(study) -> int:
    """The study's finished trials, twins (:func:`twin_of`) not counted."""
    return sum(t.state.is_finished() and "duplicate_of" not in t.user_attrs
               for t in study.get_trials(deepcopy=False))


def work(optuna, study, config: ExperimentConfig, path: Path, overrides: list[str], out: Path,
         trials: int) -> None:
    """Ask, run and tell trials until the study has ``trials`` finished ones (with other
    workers on the study, those running when it gets there finish too), or
    :data:`MAX_TWINS` samples in a row were twins."""
    twins = 0
    while finished(study) < trials and twins < MAX_TWINS:
        trial = study.ask()
        study.sampler = trial_sampler(optuna, config.seed, trial.number)  # draws at suggest
        state, value = run_trial(optuna, trial, path, overrides, out, config)
        study.tell(trial, value, state=getattr(optuna.trial.TrialState, state))
        twins = twins + 1 if "duplicate_of" in trial.user_attrs else 0


def worker(threads: int, path: str, trials: int, out: str, overrides: list[str],
           storage_url: str | None, name: str) -> None:
    """One of several workers on the study ``name`` (a process or a Ray task): :func:`work`
    with ``threads`` Numba threads."""
    import numba

    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    optuna = _optuna()
    config = load_config(Path(path), overrides)
    study = open_study(optuna, config, Path(out), storage_url, name)
    work(optuna, study, config, Path(path), overrides, Path(out), trials)


def _killed(folder: Path) -> bool:
    """Whether a trial's run died while it ran (``running`` with its folder's lock free). A
    trial whose run is pending, done or failed may belong to a live worker about to run it or
    to tell the study (telling it first would make that worker's tell fail): it is left."""
    try:
        return read_status(folder)["status"] == "killed"
    except (OSError, ValueError, RunError):  # no run folder, or not one yet
        return False


def best_config(best, path: Path, overrides: list[str]) -> str:
    """The resolved config of the trial ``best`` as YAML, from the study (the trial's own,
    kept with it by whichever worker ran it, here or on another machine); for a trial of an
    older version, which kept none, rebuilt from the config, the overrides and its params."""
    kept = best.user_attrs.get("config")
    if isinstance(kept, str):
        return kept
    sampled = [f"{key}={json.dumps(value)}" for key, value in best.params.items()]
    return to_yaml(record_env(load_config(path, overrides + sampled, build=False),
                              before_records=True))  # an older version's ran in them


def summarise(study, out: Path, config: ExperimentConfig, path: Path,
              overrides: list[str]) -> dict:
    """The trials and the best one; its resolved config written to ``best.yaml``
    (:func:`best_config`)."""
    rows = [{"trial": t.number, "state": t.state.name, "value": t.value, "params": t.params,
             "error": t.user_attrs.get("error")} for t in study.trials]
    complete = [t for t in study.trials if t.state.name == "COMPLETE"]
    best = study.best_trial if complete else None
    if best is not None:
        text = best_config(best, path, overrides)
        atomic_write(out / "best.yaml", lambda file: file.write(text))
    summary = {"study": study.study_name, "metric": config.eval.metric,
               "direction": config.tune.direction, "trials": rows,
               "best": None if best is None else {
                   "trial": best.number, "value": best.value, "params": best.params,
                   "config": str(out / "best.yaml")}}
    write_json(out / "tune.json", summary)
    return summary


def table(summary: dict) -> str:
    """The study's name, its trials as aligned text lines, then the best."""
    lines = [f"study {summary.get('study', LOCAL_STUDY)}",
             f"{'trial':>5}  {'state':8}  {summary['metric']:>14}  params"]
    for row in summary["trials"]:
        value = "—" if row["value"] is None else f"{row['value']:.4g}"
        params = ", ".join(f"{k.split('.')[-1]}={v:.4g}" if isinstance(v, float) else
                           f"{k.split('.')[-1]}={v}" for k, v in row["params"].items())
        note = f"  ({row['error']})" if row.get("error") else ""
        lines.append(f"{row['trial']:>5}  {row['state']:8}  {value:>14}  {params}{note}")
    best = summary["best"]
    lines.append("best: none complete" if best is None else
                 f"best: trial {best['trial']}, {summary['metric']} {best['value']:.4g}; "
                 f"config {best['config']}")
    return "\n".join(lines)
