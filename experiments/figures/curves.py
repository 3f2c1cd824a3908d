"""The plots of a comparison: each learner's mean curve with a +-std band against env steps,
and the performance profile of the runs' results; each learner in one colour throughout."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class RunCurves:
    """A run's record as a comparison reads it: who learned what, and its scalars."""

    folder: Path
    learner: str
    env_id: str
    seed: int
    status: dict
    scalars: dict[str, tuple[np.ndarray, np.ndarray]]  # tag -> (steps, values)
    setting: str = ""  # the env id, its water and integrator: what a comparison holds fixed
    metric: str = "eval/return"  # the config's eval.metric


def plot(runs: list[RunCurves], metric: str, path: Path) -> list[str]:
    """Mean curve and +-std band per learner on a common grid of env steps; returns the
    learners drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(7, 4.2))
    drawn = []
    for learner, colour in learner_colours(runs).items():
        curves = [r.scalars[metric] for r in runs if r.learner == learner and metric in r.scalars]
        if not curves:
            continue
        end = max(c[0][-1] for c in curves)
        if all(len(c[0]) == 1 for c in curves):  # a learner that learns nothing: a level line
            values = [c[1][0] for c in curves]
            axes.axhline(np.mean(values), linestyle="--", color=colour,
                         label=f"{learner} (n={len(curves)})")
            drawn.append(learner)
            continue
        grid = np.linspace(0, end, 200)
        values = np.array([np.interp(grid, c[0], c[1], left=np.nan) for c in curves])
        logged = np.isfinite(values).any(axis=0)  # before a run's first point: no value
        grid, values = grid[logged], values[:, logged]
        mean, std = np.nanmean(values, axis=0), np.nanstd(values, axis=0)
        axes.plot(grid, mean, color=colour, label=f"{learner} (n={len(curves)})")
        axes.fill_between(grid, mean - std, mean + std, alpha=0.2, color=colour)
        drawn.append(learner)
    axes.set_xlabel("env steps")
    axes.set_ylabel(metric)
    axes.grid(alpha=0.3)
    if drawn:
        axes.legend()
    else:  # folders that keep no scalars.csv (as the shipped results)
        axes.text(0.5, 0.5, f"no run logged {metric}", ha="center", transform=axes.transAxes)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return drawn


def learner_colours(runs: list[RunCurves]) -> dict[str, str]:
    """Each learner's own colour (matplotlib's cycle, in the learners' sorted order), so that a
    learner has one style in every plot of a report."""
    import matplotlib.pyplot as plt

    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    return {learner: cycle[k % len(cycle)]
            for k, learner in enumerate(sorted({r.learner for r in runs}))}


def profile(runs: list[RunCurves], metric: str, path: Path) -> list[str]:
    """A performance profile (rliable's): for each score tau, the share of each learner's runs
    whose result (``result.json``'s ``metric``) is above tau; returns the learners drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scores = {learner: np.array([r.status["metrics"][metric] for r in runs
                                 if r.learner == learner
                                 and metric in r.status.get("metrics", {})])
              for learner in learner_colours(runs)}
    scores = {k: v for k, v in scores.items() if v.size}
    figure, axes = plt.subplots(figsize=(7, 4.2))
    if scores:
        every = np.concatenate(list(scores.values()))
        taus = np.linspace(every.min(), every.max(), 200)
        colours = learner_colours(runs)
        for learner, values in scores.items():
            share = (values[None, :] > taus[:, None]).mean(axis=1)
            axes.step(taus, share, where="post", color=colours[learner],
                      label=f"{learner} (n={values.size})")
        axes.legend()
    axes.set_xlabel(f"{metric} (tau)")
    axes.set_ylabel("share of runs with result > tau")
    axes.set_ylim(-0.02, 1.02)
    axes.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
    return list(scores)
