"""The paper's dolphin figures, re-made from finished stunt runs.

``animat stunt-figures --out DIR --leap RUN [--nose-ball RUN] [--tail-ball RUN]
[--somersault RUN] [--belly-flop RUN]`` plays each finished run's agent (a macro controller
on its own repertoire copy; the leap's must be one: Fig. 10 draws it; the others may be PPO
or exit-stroke runs), seed = the run's seed, and writes:

* ``fig10_macro_controller.png``: the leap's macro controller (Fig. 10): on top the basic
  abstracted controllers it uses, each over the duration it was learned for; below, which of
  them it plays, in what order and for how long, and the blended actuation curves;
* ``fig11_stunts.png``: frames of the stunts (Fig. 11): the dolphin leaving the water, at the
  apex, hitting the ball with its nose, with its tail, turning in the air (the somersault
  run), and right after splashdown (each from its own run, where given);
* ``leap.mp4``: the whole leap, seen from beside the pool;

and returns the figures it read off the episodes.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.bodies.dolphin import ACTUATOR_NAMES
from animat.learners.controllers.concatenation import schedule
from animat.learners.controllers.repertoire import Repertoire
from animat.learners.macro import MacroSequence
from animat.learners.storage.files import read_json

from ..launch.config import load_run_config
from .video import H264Video


def macro_of(run_dir: str | Path) -> tuple[MacroSequence, Repertoire, dict]:
    """A finished macro run's learned sequence, its repertoire copy and its config."""
    folder = Path(run_dir)
    config = load_run_config(folder)
    repertoire = Repertoire.load(folder / "checkpoints" / "repertoire.json")
    artefacts = read_json(folder / "artefacts.json")
    steps = [(s["skill"], float(s["duration"])) for s in artefacts["sequence"]]
    overlap = float(config.learner.params.get("overlap", 0.05))
    return MacroSequence(repertoire, steps, overlap), repertoire, {
        "env_id": config.env.id, "env_kwargs": dict(config.env.kwargs), "seed": config.seed,
        "overlap": overlap}


def play(run_dir: str | Path, render: bool = True) -> tuple[list[dict], list[np.ndarray]]:
    """The infos and rendered frames of a finished run's agent (a macro sequence, a PPO
    policy, ...) from its first start."""
    from ..evaluate import load

    folder = Path(run_dir)
    config = load_run_config(folder)
    agent = load(folder)
    env = gym.make(config.env.id, render_mode="rgb_array" if render else None,
                   **dict(config.env.kwargs))
    obs, _ = env.reset(seed=config.seed)
    if hasattr(agent, "reset"):
        agent.reset()
    infos, frames = [], []
    for _ in range(env.unwrapped.episode_steps):
        action, _ = agent.predict(obs)
        obs, _, _, _, info = env.step(action)
        infos.append(info)
        if render:
            frames.append(env.render())
    return infos, frames


def fig10(run_dir: str | Path, path: Path) -> list[tuple[str, float]]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    sequence, repertoire, setup = macro_of(run_dir)
    overlap = setup["overlap"]
    used = sorted({name for name, _ in sequence.steps})
    figure = plt.figure(figsize=(11, 7))
    grid = figure.add_gridspec(2, len(used), height_ratios=[1, 1.3])
    for k, name in enumerate(used):
        axis = figure.add_subplot(grid[0, k])
        skill = repertoire[name]
        t = np.linspace(0.0, skill.duration, 400)
        axis.plot(t, skill.controller(t))
        axis.set_title(f"{name} ({skill.controller.num_parameters} params)", fontsize=9)
        axis.set_xlabel("s", fontsize=8)
        axis.set_ylim(-0.05, 1.05)
    axis = figure.add_subplot(grid[1, :])
    t = np.linspace(0.0, sequence.duration, 1000)
    curves = sequence(t)
    for a, name in enumerate(ACTUATOR_NAMES):
        axis.plot(t, curves[:, a], label=name)
    starts, _ = schedule([d for _, d in sequence.steps], overlap)
    for (name, duration), start in zip(sequence.steps, starts):
        axis.axvspan(start, start + duration, alpha=0.08, color="k")
        axis.text(start + 0.05, 1.08, f"{name}\n{duration:.2f} s", fontsize=8, va="bottom")
    axis.set_ylim(-0.05, 1.35)
    axis.set_xlabel("time, s")
    axis.set_ylabel("activation u")
    axis.legend(loc="upper right", fontsize=7, ncol=3)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return sequence.steps


def _labelled(image: np.ndarray, text: str) -> np.ndarray:
    out = image.copy()
    cv2.putText(out, text, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (20, 20, 20), 2,
                cv2.LINE_AA)
    return out


def _pick(infos: list[dict], frames: list[np.ndarray], which: str) -> tuple[int, np.ndarray]:
    """The frame of an event: ``exit`` (the centre of mass crossing up through the surface),
    ``apex``, ``touch`` (the first ball contact), ``spin`` (mid-way through the airborne
    rotation), ``splash`` (just after the re-entry)."""
    heights = np.array([i["height_bl"] for i in infos])
    if which == "exit":
        k = int(np.argmax(heights > 0.0))
    elif which == "apex":
        k = int(np.argmax(heights))
    elif which == "touch":
        touched = np.array([i.get("first_touch", -1) >= 0 for i in infos])
        k = int(np.argmax(touched)) if touched.any() else int(np.argmax(heights))
    elif which == "spin":  # half-way through its best flight's turn
        rotation = np.array([i["flight_rotation_deg"] for i in infos])
        k = int(np.argmax(rotation >= 0.5 * rotation.max()))
    else:
        entered = np.array([i["reentered"] for i in infos]) > 0
        k = min(int(np.argmax(entered)) + 2, len(frames) - 1) if entered.any() else -1
    return k, frames[k]


def make_stunt_figures(out: str | Path, leap: str | Path, nose_ball=None, tail_ball=None,
                       somersault=None, belly_flop=None) -> dict[str, float]:
    """Write Fig. 10, Fig. 11 and the leap's video into ``out``; returns what they show."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    steps = fig10(leap, out / "fig10_macro_controller.png")
    infos, frames = play(leap)
    fps = round(1.0 / gym.make(macro_of(leap)[2]["env_id"]).unwrapped.dt)
    with H264Video(out / "leap.mp4", fps) as video:
        for frame in frames:
            video.write(frame)
    tiles = [_labelled(_pick(infos, frames, "exit")[1], "(a) leaving the water"),
             _labelled(_pick(infos, frames, "apex")[1], "(a') the apex")]
    result = {"leap_apex_bl": float(infos[-1]["apex_height_bl"]),
              "leap_steps": float(len(steps))}
    for run, which, caption, key in ((nose_ball, "touch", "(b) nose hits the ball", "nose"),
                                     (tail_ball, "touch", "(c) tail hits the ball", "tail"),
                                     (somersault, "spin", "(c') mid-somersault",
                                      "somersault"),
                                     (belly_flop, "splash", "(d) belly flop", "belly_flop")):
        if run is None:
            continue
        run_infos, run_frames = play(run)
        tiles.append(_labelled(_pick(run_infos, run_frames, which)[1], caption))
        last = run_infos[-1]
        result[f"{key}_ball_hit" if key in ("nose", "tail") else key] = float(
            last.get("ball_hit", last["flight_rotation_deg"] if key == "somersault"
                     else last["reentry_splash"]))
    while len(tiles) % 3:
        tiles.append(np.full_like(tiles[0], 255))
    rows = [np.concatenate(tiles[k:k + 3], axis=1) for k in range(0, len(tiles), 3)]
    cv2.imwrite(str(out / "fig11_stunts.png"), np.concatenate(rows, axis=0)[:, :, ::-1])
    return result
