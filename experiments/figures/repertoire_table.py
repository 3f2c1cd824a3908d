"""The table of a basic-training run: per skill, what was learned and what its abstraction
keeps, on the run's own start states and on start states it never saw.

``python -m animat.experiments.figures.repertoire_table RUN_DIR`` reads the run folder's
repertoire (``checkpoints/repertoire.json``: each skill's learned and abstracted figures on the
run's own starts, and its parameter counts) and its ``eval.json`` (``animat eval RUN_DIR
--episodes N``: the repertoire's abstractions played from N unseen starts), and prints a
Markdown table: for a swim its speed (BL/s) and the abstraction's share of the learned speed,
for a turn its final heading error (deg); the dolphin's skills likewise (an arc's speed round
it, a spin's pitch rate). The basic-training table of ``docs/fish_basic_training.md`` is this
command's output for ``results/fish_basic_training``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from animat.learners.storage.files import read_json

FIGURES = {"swim": ("eval/speed_bl_per_s", "BL/s"),
           "turn": ("eval/final_heading_error_deg", "deg off"),
           "dolphin_forward": ("eval/speed_bl_per_s", "BL/s"),
           "dolphin_turn": ("eval/final_turn_error_deg", "deg off"),
           "dolphin_arc": ("eval/arc_speed_bl_per_s", "BL/s round the arc"),
           "dolphin_spin": ("eval/spin_deg_per_s", "deg/s")}
SPEEDS = ("swim", "dolphin_forward", "dolphin_arc", "dolphin_spin")  # an abstraction's share
TURNS = ("turn", "dolphin_turn")
WITHIN_DEG = 10.0  # a turn that ends within this of its target, deg


def repertoire_rows(folder: Path) -> list[dict]:
    """One row per skill of the run in ``folder``: its name, task, figure and unit, the
    learned and abstracted figures on the run's starts (with their spread), the parameter
    counts, and the unseen figure (mean, std, start count) where ``eval.json`` has it; for a
    turn, how many of the unseen starts end within :data:`WITHIN_DEG` of its target."""
    repertoire = read_json(folder / "checkpoints" / "repertoire.json")
    unseen = read_json(folder / "eval.json") if (folder / "eval.json").exists() else None
    rows = []
    for skill in repertoire["skills"]:
        meta = skill["metadata"]
        key, unit = FIGURES.get(meta["task"], ("eval/return", ""))
        scored = (unseen or {}).get("metrics", {}).get(skill["name"], {})
        episodes = (unseen or {}).get("episodes", {}).get(skill["name"], [])
        within = (sum(e[key.removeprefix("eval/")] <= WITHIN_DEG for e in episodes)
                  if meta["task"] in TURNS and episodes else None)
        rows.append({
            "skill": skill["name"], "task": meta["task"], "figure": key, "unit": unit,
            "learned": meta["learned_metrics"].get(key),
            "learned_std": meta["learned_metrics"].get(f"{key}_std"),
            "parameters_learned": meta["parameters_learned"],
            "abstracted": meta["abstracted_metrics"].get(key),
            "parameters_abstracted": meta["parameters_abstracted"],
            "unseen": scored.get(key), "unseen_std": scored.get(f"{key}_std"),
            "unseen_starts": len(unseen["seeds"]) if unseen else 0, "unseen_within": within})
    return rows


def repertoire_markdown(rows: list[dict]) -> str:
    """The rows as a Markdown table."""
    lines = ["| skill | learned, own starts | parameters | abstraction, own starts "
             f"| parameters | abstraction, unseen starts | unseen within {WITHIN_DEG:g} deg |",
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        share = (f" ({r['abstracted'] / r['learned']:.0%})"
                 if r["task"] in SPEEDS and r["learned"] else "")
        unseen = (f"{r['unseen']:.2f} ± {r['unseen_std']:.2f} over {r['unseen_starts']}"
                  if r["unseen"] is not None else "not scored")
        within = ("" if r["unseen_within"] is None
                  else f"{r['unseen_within']}/{r['unseen_starts']}")
        lines.append(f"| {r['skill']} | {r['learned']:.2f} ± {r['learned_std']:.2f} {r['unit']} "
                     f"| {r['parameters_learned']} | {r['abstracted']:.2f}{share} "
                     f"| {r['parameters_abstracted']} | {unseen} | {within} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run_dir", type=Path, help="a finished basic-training run folder")
    print(repertoire_markdown(repertoire_rows(parser.parse_args(argv).run_dir)))


if __name__ == "__main__":
    main()
