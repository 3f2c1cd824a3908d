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
``results/``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from animat.learners.storage.files import read_json
from animat.learners.storage.tree import run_folder

from ..compare import find_runs
from ..launch.config import load_config
from .statistics import mean_std


def run_rows(folders: list[Path], metric: str) -> list[dict]:
    """One dict per run: learner label, seed, own-start and unseen figure (None where it has
    no ``eval.json``), the unseen spread, env steps and wall seconds."""
    rows = []
    for folder in map(run_folder, folders):  # its parents resolved, no link itself
        config = load_config(folder / "config.yaml", build=False, follow_links=False)
        status = read_json(folder / "result.json")
        unseen = read_json(folder / "eval.json")["metrics"] if (
            folder / "eval.json").exists() else {}
        rows.append({"learner": config.learner.display_name, "seed": config.seed,
                     "own": status["metrics"].get(metric), "unseen": unseen.get(metric),
                     "unseen_std": unseen.get(f"{metric}_std"),
                     "env_steps": status["env_steps"], "wall": status["wall_seconds"],
                     "folder": folder})
    return rows


def learner_markdown(rows: list[dict], metric: str) -> str:
    """The runs' rows grouped by learner, as a Markdown table."""
    def pm(values) -> str:
        summary = mean_std(np.array([v for v in values if v is not None], dtype=float))
        if summary is None:
            return "n/a"
        return f"{summary[0]:.2f} ± {summary[1]:.2f} [{summary[2]:.2f}, {summary[3]:.2f}]"

    lines = [f"| learner | seeds | {metric}, own starts | {metric}, unseen starts | "
             "spread over a run's unseen starts | env steps | wall s |",
             "|---|---|---|---|---|---|---|"]
    for learner in sorted({r["learner"] for r in rows}):
        group = [r for r in rows if r["learner"] == learner]
        spread = [r["unseen_std"] for r in group if r["unseen_std"] is not None]
        lines.append(
            f"| {learner} | {', '.join(str(r['seed']) for r in group)} | "
            f"{pm(r['own'] for r in group)} | {pm(r['unseen'] for r in group)} | "
            f"{f'{np.mean(spread):.2f}' if spread else 'n/a'} | "
            f"{np.mean([r['env_steps'] for r in group]):,.0f} | "
            f"{np.mean([r['wall'] for r in group]):.0f} |")
    return "\n".join(lines) + (
        "\n\nValues: mean ± std over the runs [95% bootstrap interval of the mean]; the "
        "spread is the mean over the runs of the std over one run's unseen starts.\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m animat.experiments.figures.unseen_table",
        description="A learner comparison's table, on own and unseen starts.")
    parser.add_argument("folders", nargs="+", help="run folders, or folders holding them")
    parser.add_argument("--metric", required=True, help="e.g. eval/final_distance_bl")
    args = parser.parse_args(argv)
    rows = run_rows(find_runs(args.folders), args.metric)
    for row in rows:
        if row["unseen"] is None:
            print(f"note: {row['folder']} has no eval.json (animat eval RUN --episodes N)",
                  file=sys.stderr)
    print(learner_markdown(rows, args.metric))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
