"""``animat compare``: read run folders' TensorBoard events back (TensorBoard's own reader,
keeping every scalar; a run's ``scalars.csv`` when it has no events), group runs by learner
(its ``label`` where the config gives one), aggregate over seeds (mean, std and a 95%
bootstrap interval of the mean) and write a Markdown table and a PNG plot (mean curve with a
shaded +-std band per learner, x = env steps), then the runs' abstractions
(:mod:`animat.experiments.figures.abstraction_table`).

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
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

from animat.learners.storage.files import read_text
from animat.learners.storage.tree import check_tree, listing, run_folder

from .figures.abstraction_table import abstraction_markdown, abstraction_rows
from .launch.config import load_config
from .launch.folders import one_line, read_status
from .launch.lock import RunError


@dataclass
class RunCurves:
    folder: Path
    learner: str
    env_id: str
    seed: int
    status: dict
    scalars: dict[str, tuple[np.ndarray, np.ndarray]]  # tag -> (steps, values)


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
                     read_status(folder), read_scalars(folder))


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
            "steps_to_threshold": (float(np.mean(reached)) if reached else None, len(reached)),
            "wall_seconds": float(np.mean([r.status.get("wall_seconds", 0.0) for r in group])),
            "env_steps": float(np.mean([r.status.get("env_steps", 0) for r in group])),
        })
    return rows


BOOTSTRAP_RESAMPLES, CONFIDENCE = 10_000, 0.95


def mean_std(values: np.ndarray) -> tuple[float, float, float, float] | None:
    """(mean, std, and the bounds of a 95% percentile-bootstrap interval of the mean over
    runs), or None. The bootstrap resamples the runs (seeded, so a report is reproducible);
    with the 3-5 seeds these comparisons have it is narrow-tailed and optimistic, which is
    why the std is kept beside it; one run gives a zero-width interval."""
    if not values.size:
        return None
    rng = np.random.default_rng(0)
    means = rng.choice(values, (BOOTSTRAP_RESAMPLES, values.size)).mean(axis=1)
    tail = 100 * (1 - CONFIDENCE) / 2
    low, high = np.percentile(means, [tail, 100 - tail])
    return float(values.mean()), float(values.std()), float(low), float(high)


def markdown(rows: list[dict], metric: str, threshold: float | None) -> str:
    def pm(value):
        if value is None:
            return "n/a"
        return f"{value[0]:.3f} ± {value[1]:.3f} [{value[2]:.3f}, {value[3]:.3f}]"

    head = (f"| learner | runs (done) | result {metric} | final {metric} | best {metric} | "
            f"env steps to {threshold if threshold is not None else '—'} (runs reaching) | "
            "env steps | wall s |")
    lines = [head, "|---|---|---|---|---|---|---|---|"]
    for row in rows:
        steps, count = row["steps_to_threshold"]
        if threshold is None:
            reach = "—"
        elif steps is None:
            reach = f"never (0/{row['runs']})"
        else:
            reach = f"{steps:,.0f} ({count}/{row['runs']})"
        lines.append(f"| {row['learner']} | {row['runs']} ({row['done']}) | {pm(row['result'])} | "
                     f"{pm(row['final'])} | {pm(row['best'])} | {reach} | "
                     f"{row['env_steps']:,.0f} | {row['wall_seconds']:.0f} |")
    return "\n".join(lines) + "\n\n" + (
        "Values: mean ± std over runs [95% bootstrap interval of the mean, 10,000 resamples "
        "of the runs]. result: what the run returned (result.json); final and best: the last "
        "and the highest point of the logged curve (eval/*: the current incumbent).\n")


def plot(runs: list[RunCurves], metric: str, path: Path) -> list[str]:
    """Mean curve and +-std band per learner on a common grid of env steps; returns the
    learners drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4.2))
    drawn = []
    for learner in sorted({r.learner for r in runs}):
        curves = [r.scalars[metric] for r in runs if r.learner == learner and metric in r.scalars]
        if not curves:
            continue
        end = max(c[0][-1] for c in curves)
        if all(len(c[0]) == 1 for c in curves):  # a learner that learns nothing: a level line
            values = [c[1][0] for c in curves]
            axes.axhline(np.mean(values), linestyle="--", color="0.3",
                         label=f"{learner} (n={len(curves)})")
            drawn.append(learner)
            continue
        grid = np.linspace(0, end, 200)
        values = np.array([np.interp(grid, c[0], c[1], left=np.nan) for c in curves])
        logged = np.isfinite(values).any(axis=0)  # before a run's first point: no value
        grid, values = grid[logged], values[:, logged]
        mean, std = np.nanmean(values, axis=0), np.nanstd(values, axis=0)
        (line,) = axes.plot(grid, mean, label=f"{learner} (n={len(curves)})")
        axes.fill_between(grid, mean - std, mean + std, alpha=0.2, color=line.get_color())
        drawn.append(learner)
    axes.set_xlabel("env steps")
    axes.set_ylabel(metric)
    axes.grid(alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return drawn


def compare(paths: list[str | Path], metric: str = "eval/return", threshold: float | None = None,
            report: str | Path | None = None) -> tuple[str, Path | None]:
    """Compare runs; returns the Markdown and the plot's path (beside ``report`` if given)."""
    runs = load_runs(find_runs(paths))
    rows = summarise(runs, metric, threshold)
    abstractions = abstraction_rows(runs, metric)
    envs = sorted({r.env_id for r in runs})
    text = f"Runs of {', '.join(envs)}; metric `{metric}` (x = env steps).\n\n" + markdown(
        rows, metric, threshold)
    table = abstraction_markdown(abstractions, metric)
    image = None
    if report:
        report = Path(report)
        report.parent.mkdir(parents=True, exist_ok=True)
        image = report.with_suffix(".png")
        drawn = plot(runs, metric, image)
        report.write_text(text + f"\n![{metric}]({image.name})\n" + (
            f"\n{table}" if table else ""))
        (report.with_suffix(".json")).write_text(json.dumps(
            {"rows": rows, "plotted": drawn, "abstraction": abstractions}, indent=1))
    return text + (f"\n{table}" if table else ""), image
