"""The abstraction section of ``animat compare``: per run, what the learned controller scored
and what its FFT abstractions kept (read from each run folder's ``artefacts.json``).

For every run whose artefacts hold an abstraction (the black-box learners'): the learned
controller's metric, E and parameter count; the truncated abstraction (plain FFT
thresholding: parameters, metric, its share of the learned metric); and, where the learner
refined it over its frequency parameters, the refined abstraction likewise. Shares are the
value over the learned controller's (for speed, above 100% is faster; for a distance or an
error, above 100% is worse).
"""

from __future__ import annotations

import sys
from pathlib import Path

from animat.learners.storage.files import read_json


def abstraction_rows(runs, metric: str) -> list[dict]:
    """One row per run with abstraction artefacts (``runs``: objects with ``folder``,
    ``learner``, ``seed``, ``status``), sorted by learner and seed."""
    rows = []
    for run in sorted(runs, key=lambda r: (r.learner, r.seed)):
        path = Path(run.folder) / "artefacts.json"
        if not path.exists():
            continue
        try:
            artefacts = read_json(path)
        except (OSError, ValueError) as error:  # a broken run's: its row left out, said once
            print(f"animat: warning: {path}: no abstraction row: {error}", file=sys.stderr)
            continue
        if "abstraction_metrics" not in artefacts:
            continue
        learned = artefacts.get("learned_metrics") or run.status.get("metrics", {})
        final = artefacts["abstraction_metrics"]
        truncated = artefacts.get("truncated_abstraction_metrics", final)
        rows.append({
            "learner": run.learner, "seed": run.seed,
            "learned": _scores(learned, metric, artefacts.get("parameters")),
            "truncated": _scores(truncated, metric, truncated.get("parameters")),
            "refined": _scores(final, metric, final["parameters"]) if final.get("refined")
            else None,
            "before_refining": _scores(final["before_refining"], metric, final["parameters"])
            if final.get("refined") else None,
            "env_steps": run.status.get("env_steps"),
            "wall_seconds": run.status.get("wall_seconds")})
    return rows


def _scores(metrics: dict, metric: str, parameters) -> dict:
    return {"value": metrics.get(metric), "E": -metrics["eval/return"],
            "parameters": parameters}


def abstraction_markdown(rows: list[dict], metric: str) -> str:
    """The rows as a Markdown table ('' when there are none)."""
    if not rows:
        return ""

    def value(part: dict | None) -> str:
        return "n/a" if part is None or part["value"] is None else f"{part['value']:.3f}"

    def cells(part: dict | None, learned: dict) -> str:
        if part is None:
            return "— | — | —"
        share = (f" ({100 * part['value'] / learned['value']:.0f}%)" if part is not learned
                 and part["value"] is not None and learned["value"] else "")
        return f"{part['parameters']} | {value(part)}{share} | {part['E']:.3f}"

    name = metric.removeprefix("eval/")
    lines = [f"Abstractions, per run ({name}; E = -return; params = real parameters; % of the "
             "learned controller's value):", "",
             "| learner | seed | learned params | learned | E | truncated params | truncated | E "
             "| refined params | refined | E | before refining | env steps | wall s |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        learned, refined = row["learned"], row["refined"]
        lines.append(f"| {row['learner']} | {row['seed']} | {cells(learned, learned)} | "
                     f"{cells(row['truncated'], learned)} | {cells(refined, learned)} | "
                     f"{value(row['before_refining']) if refined else '—'} | "
                     f"{row['env_steps'] or 0:,} | {row['wall_seconds'] or 0:.0f} |")
    return "\n".join(lines) + "\n"
