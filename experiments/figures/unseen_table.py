"""The table of a learner comparison scored on start states the runs never saw.

``python -m animat.experiments.figures.unseen_table FOLDER... --metric eval/final_distance_bl``
reads every run folder under the FOLDERs (each with ``result.json``, ``config.yaml`` and the
``eval.json`` that ``animat eval RUN --episodes N`` writes: its agent on N unseen starts) and
prints a Markdown table, one row per learner (its label): the metric on the run's own starts
(``result.json``) and on the unseen ones (``eval.json``), each as mean ± std over the runs with a
95% bootstrap interval of the mean (:func:`~animat.experiments.figures.statistics.mean_std`),
the spread over one run's unseen starts (the mean of the runs' stds), the runs' seeds, env steps
and wall seconds. A run without ``eval.json`` is named and left out of the unseen column. The docs'
learner comparisons on the turn and the reach are this command's output for the folders under
``results/``. ``--at-least X`` (or ``--at-most X``) adds each run's count of unseen starts whose
figure meets it (``14/16``): a criterion that must hold on each start, not on average (a leap's
``eval/apex_height_bl --at-least 0.5``, a turn's ``eval/final_heading_error_deg --at-most 10``).
Where a run has ``eval_point_start.json`` (``animat eval RUN --point-start``: its agent from the
task's documented start, as the paper shows a stunt), a column gives that figure too.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

from animat.learners.storage.files import read_json
from animat.learners.storage.tree import run_folder

from ..launch.config import load_config
from ..launch.folders import find_runs
from .statistics import mean_std


def run_rows(folders: list[Path], metric: str,
             criterion: Callable[[float], bool] | None = None) -> list[dict]:
    """One dict per run: learner label, seed, own-start and unseen figure (None where it has
    no ``eval.json``), the figure from the documented start (None without
    ``eval_point_start.json``), the unseen spread, env steps and wall seconds; with
    ``criterion``, the number of unseen starts whose figure meets it and of unseen starts
    (``met``, ``starts``)."""
    rows = []
    for folder in map(run_folder, folders):  # its parents resolved, no link itself
        config = load_config(folder / "config.yaml", build=False, follow_links=False)
        status = read_json(folder / "result.json")
        scored = read_json(folder / "eval.json") if (folder / "eval.json").exists() else {}
        unseen = scored.get("metrics", {})
        per_start = [e[metric.removeprefix("eval/")] for e in scored.get("episodes", [])]
        point = folder / "eval_point_start.json"
        documented = read_json(point)["metrics"].get(metric) if point.exists() else None
        rows.append({"learner": config.learner.display_name, "seed": config.seed,
                     "own": status["metrics"].get(metric), "unseen": unseen.get(metric),
                     "documented": documented,
                     "unseen_std": unseen.get(f"{metric}_std"),
                     "met": sum(map(criterion, per_start)) if criterion else None,
                     "starts": len(per_start),
                     "env_steps": status["env_steps"], "wall": status["wall_seconds"],
                     "folder": folder})
    return rows


def learner_markdown(rows: list[dict], metric: str, criterion: str = "") -> str:
    """The runs' rows grouped by learner, as a Markdown table; with ``criterion`` (its words,
    e.g. ``≥ 0.5``), a column of each run's unseen starts that meet it; where any run was
    played from the documented start, a column of that figure."""
    def pm(values) -> str:
        summary = mean_std(np.array([v for v in values if v is not None], dtype=float))
        if summary is None:
            return "n/a"
        return f"{summary[0]:.2f} ± {summary[1]:.2f} [{summary[2]:.2f}, {summary[3]:.2f}]"

    met = f" unseen starts {criterion}, each run |" if criterion else ""
    point = any(r.get("documented") is not None for r in rows)
    lines = [f"| learner | seeds |{f' {metric}, documented start |' if point else ''} "
             f"{metric}, own starts | {metric}, unseen starts | "
             f"spread over a run's unseen starts |{met} env steps | wall s |",
             "|---|---|---|---|---|" + ("---|" if point else "") + ("---|" if criterion else "")
             + "---|---|"]
    for learner in sorted({r["learner"] for r in rows}):
        group = [r for r in rows if r["learner"] == learner]
        spread = [r["unseen_std"] for r in group if r["unseen_std"] is not None]
        lines.append(
            f"| {learner} | {', '.join(str(r['seed']) for r in group)} | "
            + (f"{pm(r.get('documented') for r in group)} | " if point else "") +
            f"{pm(r['own'] for r in group)} | {pm(r['unseen'] for r in group)} | "
            f"{f'{np.mean(spread):.2f}' if spread else 'n/a'} | "
            + (f"{', '.join(_met(r) for r in group)} | " if criterion else "")
            + f"{np.mean([r['env_steps'] for r in group]):,.0f} | "
            f"{np.mean([r['wall'] for r in group]):.0f} |")
    return "\n".join(lines) + (
        "\n\nValues: mean ± std over the runs [95% bootstrap interval of the mean]; the "
        "spread is the mean over the runs of the std over one run's unseen starts.\n")


def _met(row: dict) -> str:
    """A run's count of unseen starts meeting the criterion (``14/16``; n/a without any)."""
    return f"{row['met']}/{row['starts']}" if row["starts"] else "n/a"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m animat.experiments.figures.unseen_table",
        description="A learner comparison's table, on own and unseen starts.")
    parser.add_argument("folders", nargs="+", help="run folders, or folders holding them")
    parser.add_argument("--metric", required=True, help="e.g. eval/final_distance_bl")
    bound = parser.add_mutually_exclusive_group()
    bound.add_argument("--at-least", type=float, help="count each run's unseen starts >= this")
    bound.add_argument("--at-most", type=float, help="count each run's unseen starts <= this")
    args = parser.parse_args(argv)
    criterion, words = None, ""
    if args.at_least is not None:
        criterion, words = (lambda v: v >= args.at_least), f"≥ {args.at_least:g}"
    elif args.at_most is not None:
        criterion, words = (lambda v: v <= args.at_most), f"≤ {args.at_most:g}"
    rows = run_rows(find_runs(args.folders), args.metric, criterion)
    for row in rows:
        if row["unseen"] is None:
            print(f"note: {row['folder']} has no eval.json (animat eval RUN --episodes N)",
                  file=sys.stderr)
    print(learner_markdown(rows, args.metric, words))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
