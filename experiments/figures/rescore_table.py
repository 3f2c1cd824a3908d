"""Every shipped result re-scored, and how far each moved: the check after a change of the
physics, a task or a controller.

``python -m animat.experiments.figures.rescore_table [FOLDER...]`` plays the agent of every
shipped run folder (each with an ``eval.json`` under ``results/``, or the FOLDERs given) on the
seeds of its ``eval.json`` (:func:`animat.experiments.evaluate.evaluate`, which writes nothing
into a shipped folder) and prints a Markdown table, a row a folder: whether it re-scores to
what it quotes (to 1e-9 relative, as ``tests/experiments/test_results.py`` asks), and the mean
figure that moved most, by how much of its value and of its spread over the starts
(:func:`animat.experiments.evaluate.largest_move`), and the wall seconds it took; then the
largest move of all, in the same two units. A move well inside the spread over the starts
is noise to every comparison the docs read; one that is not means the result must be learned
again. It exits 1 if any folder differs, 0 if none does.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from animat.learners.storage.files import read_json

from ..evaluate import evaluate, figure_names, figures_of, largest_move
from ..launch.lock import RunError
from ..launch.shipped import RESULTS, is_shipped_result


def shipped_folders(folders: list[str]) -> list[Path]:
    """The run folders with an ``eval.json`` under each of ``folders`` (default: the shipped
    ``results/``), resolved and sorted; a RunError for a folder outside ``results/`` (re-scoring
    writes a run's ``eval.json`` anywhere else)."""
    roots = [Path(f) for f in folders] or [RESULTS]
    for root in roots:
        if not is_shipped_result(root):
            raise RunError(f"{root} is not under the shipped {RESULTS}: re-score a run of "
                           "your own with animat eval")
    return sorted({p.parent.resolve() for root in roots for p in root.rglob("eval.json")})


def rescore_row(folder: Path) -> dict:
    """One folder re-scored on its ``eval.json``'s seeds: whether it is the same, its largest
    move (name, relative, in spread) and the wall seconds it took."""
    start = time.perf_counter()
    shipped = read_json(folder / "eval.json")
    result = evaluate(folder, seeds=shipped["seeds"])
    if set(figure_names(shipped["metrics"])) <= set(figure_names(result["metrics"])):
        name, relative, in_spread = largest_move(
            shipped["metrics"], figures_of(result["metrics"], shipped["metrics"]))
    else:
        name, relative, in_spread = "(other figures)", float("inf"), float("inf")
    return {"folder": folder, "same": result.get("shipped", "").startswith("the same as"),
            "figure": name, "relative": relative, "in_spread": in_spread,
            "seconds": time.perf_counter() - start}


def rescore_markdown(rows: list[dict], root: Path) -> str:
    """The rows as a Markdown table, then the largest moves of all."""
    lines = ["| folder | re-scores to what it quotes | the figure that moved most | "
             "by, of its value | by, of its spread over the starts | wall s |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        shown = r["folder"].relative_to(root)
        lines.append(f"| {shown} | {'yes' if r['same'] else 'NO'} | {r['figure'] or '-'} | "
                     f"{r['relative']:.2g} | {r['in_spread']:.2g} | {r['seconds']:.0f} |")
    moved = sum(not r["same"] for r in rows)
    lines.append(f"\n{len(rows) - moved} of {len(rows)} folders re-score to what they quote; "
                 f"the largest move: {max((r['relative'] for r in rows), default=0.0):.2g} of "
                 f"a figure's value, {max((r['in_spread'] for r in rows), default=0.0):.2g} of "
                 "its spread over the starts.")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m animat.experiments.figures.rescore_table",
        description="Re-score every shipped result and print how far each moved.")
    parser.add_argument("folders", nargs="*", help="folders holding run folders with an "
                        "eval.json (default: the shipped results/)")
    args = parser.parse_args(argv)
    try:
        folders = shipped_folders(args.folders)
    except RunError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    if not folders:
        print(f"no run folder with an eval.json under {args.folders or [str(RESULTS)]}",
              file=sys.stderr)
        return 2
    rows = [rescore_row(folder) for folder in folders]
    print(rescore_markdown(rows, RESULTS.resolve()))
    return 0 if all(r["same"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
