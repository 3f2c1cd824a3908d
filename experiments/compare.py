"""``animat compare``: read run folders' TensorBoard events back (TensorBoard's own reader,
keeping every scalar; a run's ``scalars.csv`` when it has no events), group runs by learner
(its ``label`` where the config gives one), aggregate over seeds (mean and std, and the
interquartile mean with a 95% stratified-bootstrap interval, as rliable reports them: Agarwal
et al., "Deep RL at the edge of the statistical precipice", 2021) and write a Markdown table, a
PNG plot (mean curve with a shaded +-std band per learner, x = env steps) and a performance
profile (the share of each learner's runs above each score), then the runs' abstractions
(:mod:`animat.experiments.figures.abstraction_table`).

Runs of different settings (env id and version, water, integrator) are not compared: a
comparison of them is refused, naming the settings. The metric is the runs' configs'
``eval.metric`` unless one is given.

Every learner logs ``eval/*`` with one meaning: its current incumbent (PPO's current policy,
a black-box learner's best candidate of the latest round), scored over the evaluation start
states; the black-box learners also log ``best/*``, the best so far, which is what they
return."""

from __future__ import annotations

import csv
import io
import json
import os
import sys
from pathlib import Path

import numpy as np
import yaml

from animat.learners.storage.files import read_text
from animat.learners.storage.tree import check_tree, listing, run_folder

from .figures.abstraction_table import abstraction_markdown, abstraction_rows
from .figures.curves import RunCurves, plot, profile
from .figures.statistics import iqm_interval, mean_std
from .launch.config import load_config
from .launch.folders import find_runs, one_line, read_status
from .launch.lock import RunError


def read_scalars(folder: Path) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Every scalar of a run: tag -> (steps, values), sorted by step, the last value kept
    where a resumed run logged a step twice; from its TensorBoard events, or from its
    ``scalars.csv`` when it has none (a run with ``logging.tensorboard: false``)."""
    series: dict[str, dict[int, float]] = {}
    events = listing(folder / "tb", "events.out.tfevents.*", "events")  # no link, bounded
    if events:
        from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

        for path in events:
            accumulator = EventAccumulator(str(path), size_guidance={"scalars": 0})
            accumulator.Reload()
            for tag in accumulator.Tags()["scalars"]:
                for event in accumulator.Scalars(tag):
                    series.setdefault(tag, {})[event.step] = event.value
    elif os.path.lexists(folder / "scalars.csv"):
        text = read_text(folder / "scalars.csv", "scalars")
        for row in csv.DictReader(io.StringIO(text, newline="")):
            series.setdefault(row["tag"], {})[int(row["step"])] = float(row["value"])
    return {tag: (np.array(sorted(v)), np.array([v[s] for s in sorted(v)]))
            for tag, v in series.items()}


def load_run(folder: Path) -> RunCurves:
    """A run's curves, its config read and validated as ``animat run`` reads one (not built);
    a folder holding a link or a FIFO is not read (UnsafeFile)."""
    folder = run_folder(folder)
    check_tree(folder)
    config = load_config(folder / "config.yaml", build=False, follow_links=False)
    return RunCurves(folder, config.learner.display_name, config.env.id, config.seed,
                     read_status(folder), read_scalars(folder),
                     setting_of(config.env.id, config.env.kwargs), config.eval.metric)


def setting_of(env_id: str, kwargs: dict) -> str:
    """What a comparison must hold fixed, in words: the env id (with its version), the water
    model (a folder made before folders recorded it ran in the resistive water) and the
    integrator where it is not the default."""
    water = kwargs.get("water") if isinstance(kwargs.get("water"), dict) else {}
    model = water.get("model", "resistive")
    integrator = kwargs.get("integrator", "explicit")
    return f"{env_id}, {model} water" + ("" if integrator == "explicit" else f", {integrator}")


def one_setting(runs: list[RunCurves]) -> str:
    """The runs' one setting; RunError naming each setting and its run count if they differ."""
    settings = sorted({r.setting for r in runs})
    if len(settings) > 1:
        counts = "; ".join(f"{s}: {sum(r.setting == s for r in runs)} runs" for s in settings)
        raise RunError(f"the runs are of {len(settings)} settings ({counts}); compare the "
                       "runs of one setting at a time")
    return settings[0]


def metric_of(runs: list[RunCurves], metric: str | None) -> str:
    """``metric``, or the runs' configs' ``eval.metric``; RunError if those differ."""
    if metric is not None:
        return metric
    metrics = sorted({r.metric for r in runs})
    if len(metrics) > 1:
        raise RunError(f"the runs' configs score different metrics ({', '.join(metrics)}); "
                       "give one with --metric")
    return metrics[0]


def load_runs(folders: list[Path]) -> list[RunCurves]:
    """Every run that can be read; one that cannot (a corrupt or missing file, a config that
    is not one) is left out with a one-line warning naming it, so one broken run does not stop
    a comparison of the rest. RunError if none can be read."""
    runs = []
    for folder in folders:
        try:
            runs.append(load_run(folder))
        except (OSError, ValueError, KeyError, TypeError, AttributeError, RunError,
                yaml.YAMLError) as error:
            print(f"animat: warning: {folder}: left out, it cannot be read: "
                  f"{one_line(error)}", file=sys.stderr)
    if not runs:
        raise RunError(f"none of the {len(folders)} run folders could be read")
    return runs


def _steps_to(curve: tuple[np.ndarray, np.ndarray] | None, threshold: float | None):
    if curve is None or threshold is None:
        return None
    steps, values = curve
    reached = np.flatnonzero(values >= threshold)
    return int(steps[reached[0]]) if reached.size else None


def summarise(runs: list[RunCurves], metric: str, threshold: float | None) -> list[dict]:
    """One row per learner: runs, final and best mean +- std, env steps to ``threshold``
    (mean over the runs that reached it, and how many did), wall seconds, env steps."""
    rows = []
    for learner in sorted({r.learner for r in runs}):
        group = [r for r in runs if r.learner == learner]
        curves = [r.scalars.get(metric) for r in group]
        finals = np.array([c[1][-1] for c in curves if c is not None])
        bests = np.array([c[1].max() for c in curves if c is not None])
        reached = [s for s in (_steps_to(c, threshold) for c in curves) if s is not None]
        results = np.array([r.status["metrics"][metric] for r in group
                            if metric in r.status.get("metrics", {})])
        rows.append({
            "learner": learner, "runs": len(group),
            "done": sum(r.status.get("status") == "done" for r in group),
            "result": mean_std(results), "final": mean_std(finals), "best": mean_std(bests),
            "result_iqm": iqm_interval(results),
            "steps_to_threshold": (float(np.mean(reached)) if reached else None, len(reached)),
            "wall_seconds": float(np.mean([r.status.get("wall_seconds", 0.0) for r in group])),
            "env_steps": float(np.mean([r.status.get("env_steps", 0) for r in group])),
        })
    return rows


def markdown(rows: list[dict], metric: str, threshold: float | None) -> str:
    def pm(value):
        if value is None:
            return "n/a"
        return f"{value[0]:.3f} ± {value[1]:.3f} [{value[2]:.3f}, {value[3]:.3f}]"

    def interval(value):
        return "n/a" if value is None else f"{value[0]:.3f} [{value[1]:.3f}, {value[2]:.3f}]"

    head = (f"| learner | runs (done) | result {metric} | IQM of result | final {metric} | "
            f"best {metric} | "
            f"env steps to {threshold if threshold is not None else '—'} (runs reaching) | "
            "env steps | wall s |")
    lines = [head, "|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        steps, count = row["steps_to_threshold"]
        if threshold is None:
            reach = "—"
        elif steps is None:
            reach = f"never (0/{row['runs']})"
        else:
            reach = f"{steps:,.0f} ({count}/{row['runs']})"
        lines.append(f"| {row['learner']} | {row['runs']} ({row['done']}) | {pm(row['result'])} | "
                     f"{interval(row['result_iqm'])} | {pm(row['final'])} | {pm(row['best'])} | "
                     f"{reach} | "
                     f"{row['env_steps']:,.0f} | {row['wall_seconds']:.0f} |")
    return "\n".join(lines) + "\n\n" + (
        "Values: mean ± std over runs [95% bootstrap interval of the mean, 10,000 resamples "
        "of the runs]. IQM: the interquartile mean of the runs' results [95% stratified-"
        "bootstrap interval, 10,000 resamples], as rliable reports it. result: what the run "
        "returned (result.json); final and best: the last and the highest point of the logged "
        "curve (eval/*: the current incumbent).\n")


def compare(paths: list[str | Path], metric: str | None = None,
            threshold: float | None = None, report: str | Path | None = None
            ) -> tuple[str, Path | None]:
    """Compare runs of one setting (:func:`one_setting`) on ``metric`` (default: their
    configs' ``eval.metric``); returns the Markdown and the plot's path (beside ``report``, with
    the performance profile, if given)."""
    runs = load_runs(find_runs(paths))
    setting, metric = one_setting(runs), metric_of(runs, metric)
    rows = summarise(runs, metric, threshold)
    abstractions = abstraction_rows(runs, metric)
    text = f"Runs of {setting}; metric `{metric}` (x = env steps).\n\n" + markdown(
        rows, metric, threshold)
    table = abstraction_markdown(abstractions, metric)
    image = None
    if report:
        report = Path(report)
        report.parent.mkdir(parents=True, exist_ok=True)
        image = report.with_suffix(".png")
        drawn = plot(runs, metric, image)
        profiled = image.with_name(f"{image.stem}_profile.png")
        profile(runs, metric, profiled)
        report.write_text(text + f"\n![{metric}]({image.name})\n\n"
                          f"![performance profile]({profiled.name})\n"
                          + (f"\n{table}" if table else ""))
        (report.with_suffix(".json")).write_text(json.dumps(
            {"rows": rows, "plotted": drawn, "abstraction": abstractions}, indent=1))
    return text + (f"\n{table}" if table else ""), image
