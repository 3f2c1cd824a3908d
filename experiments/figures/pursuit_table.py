"""The pursuit benchmark's comparison table, each policy beside its blind and oracle baselines.

``python -m animat.experiments.figures.pursuit_table FOLDER...`` reads every run folder under the
FOLDERs scored on ``Animat/FishPursuit-v0`` (``result.json``, ``config.yaml`` and the
``eval.json`` of ``animat eval RUN --episodes N``: N episodes of seeds it never saw) and prints a
Markdown table per benchmark variant (the env's arguments but those that are the agent's: the
privileged ``oracle`` entry, ``eyes``, ``sensors`` and ``frames``, what it observes, and
``glances``, the looks a frame, a column of the table): for each
run, on the unseen episodes, ``eval/fovea_fraction`` (the share of all frames with the prey in
both foveas; mean ± std over the episodes, and a 95% bootstrap interval of the mean), the same
normalised between the
variant's blind and oracle baselines ((x - blind) / (oracle - blind): 0 is what the start gives
away, 1 is what sight could give at best with the same body), the time to the first foveation,
the distance closed, the share of episodes with a capture, and the share of frames the
distractor held the gaze. A run without ``eval.json`` is named and left out.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

from animat.learners.storage.files import read_json
from animat.learners.storage.tree import run_folder

from ..launch.config import load_config
from ..launch.folders import find_runs
from .statistics import mean_std

# the env's arguments that are the agent's (what it observes, how often it looks), not the
# benchmark's: runs that differ only in them are rows of one table
AGENTS = ("oracle", "glances", "eyes", "frames", "sensors")
COLUMNS = (("first_foveation_s", "first foveation, s", 1), ("distance_closed_bl",
           "closed, BL", 1), ("captured", "captured", 2), ("distractor_fraction",
           "distractor", 2))


def pursuit_rows(folders: list[Path]) -> list[dict]:
    """One dict per run with an ``eval.json``: its variant (JSON of the env's arguments but
    ``oracle``), role (``blind``, ``oracle`` or ``policy``), label, unseen metrics and
    episodes."""
    rows = []
    for folder in map(run_folder, folders):  # its parents resolved, no link itself
        if not (folder / "eval.json").exists():
            print(f"note: {folder} has no eval.json (animat eval RUN --episodes N)",
                  file=sys.stderr)
            continue
        config = load_config(folder / "config.yaml", build=False, follow_links=False)
        params = config.learner.params
        role = "blind" if params.get("blind") else "oracle" if params.get("oracle") else "policy"
        kwargs = {k: v for k, v in config.env.kwargs.items() if k not in AGENTS}
        unseen = read_json(folder / "eval.json")
        shares = np.array([e["fovea_fraction"] for e in unseen["episodes"]], float)
        rows.append({"variant": json.dumps(kwargs, sort_keys=True), "role": role,
                     "label": _label(config), "seed": config.seed, "metrics": unseen["metrics"],
                     "episodes": len(unseen["seeds"]), "folder": folder,
                     "glances": int(config.env.kwargs.get("glances", 1)),
                     "interval": mean_std(shares)})
    return rows


def _label(config) -> str:
    """The learner's name, and what it observes where the run chose: the env's ``sensors``
    (e.g. ``ppo (pixels, gaze, proprioception)``), or ``state`` for the env's ``oracle``
    observation (the prey's true position)."""
    sensors = config.env.kwargs.get("sensors")
    if not sensors:
        learned = not config.learner.params.get("oracle")  # not the oracle baseline itself
        state = " (state)" if config.env.kwargs.get("oracle") and learned else ""
        return config.learner.display_name + state
    names = [s["name"] if isinstance(s, dict) else str(s) for s in sensors]
    return f"{config.learner.display_name} ({', '.join(names)})"


def normalised(value: float, blind: float | None, oracle: float | None) -> str:
    """``(value - blind) / (oracle - blind)`` to two places, or n/a without both baselines."""
    if blind is None or oracle is None or oracle <= blind:
        return "n/a"
    return f"{(value - blind) / (oracle - blind):.2f}"


def variant_markdown(rows: list[dict]) -> str:
    """One variant's rows as a Markdown table, the policies first, then the baselines; a
    label that several runs share (seeds of one config) names each run's seed."""
    ends = {r["role"]: r["metrics"]["eval/fovea_fraction"] for r in rows if r["role"] != "policy"}
    lines = ["| policy | glances | fovea fraction [95% interval] | normalised | "
             + " | ".join(name for _, name, _ in COLUMNS) + " | episodes |",
             "|---|---|---|---|" + "---|" * len(COLUMNS) + "---|"]
    seeded = Counter((r["role"], r["label"]) for r in rows)  # several seeds: each named
    for row in sorted(rows, key=lambda r: (r["role"] != "policy", r["role"], r["label"],
                                           r["seed"])):
        m = row["metrics"]
        label = row["label"] + (f", seed {row['seed']}" if seeded[row["role"], row["label"]] > 1
                                else "")
        cells = [f"{m['eval/' + key]:.{places}f} ± {m['eval/' + key + '_std']:.{places}f}"
                 for key, _, places in COLUMNS]
        share, (_, _, low, high) = m["eval/fovea_fraction"], row["interval"]
        lines.append(f"| {label} | {row['glances']} | {share:.2f} ± "
                     f"{m['eval/fovea_fraction_std']:.2f} [{low:.2f}, {high:.2f}] | "
                     f"{normalised(share, ends.get('blind'), ends.get('oracle'))} | "
                     f"{' | '.join(cells)} | {row['episodes']} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m animat.experiments.figures.pursuit_table",
        description="The pursuit benchmark's table on unseen episodes, with its baselines.")
    parser.add_argument("folders", nargs="+", help="run folders, or folders holding them")
    args = parser.parse_args(argv)
    rows = pursuit_rows(find_runs(args.folders))
    for variant in sorted({r["variant"] for r in rows}):
        print(f"Env arguments {variant}:\n")
        print(variant_markdown([r for r in rows if r["variant"] == variant]) + "\n")
    print("Values on the unseen episodes: mean ± std over the episodes; the interval is a 95% "
          "bootstrap interval of the mean over them.")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
