"""Swim demo: the hand-designed motor controllers drive the fish; prints what they achieve.

``animat demo [--seconds 10] [--video DIR]`` (or ``python -m animat.experiments.demo``): for
each water, the paper's resistive one (``Water(model="resistive")``) and the reactive one of
Lighthill's theory (``model="reactive"``, the default), swims at full speed with the swim-MC and
prints the biology figures of its cruise (tail-beat frequency f, peak-to-peak tail amplitude A,
speed U along the start heading, Strouhal number fA/U, stride U/f), the fastest head-to-tail
wave of a grid and the same wave reversed, a C-start, the turn-MCs, the swim- and turn-MCs over
32 starts of the fish's start spread, and the fin-MC (fin angles through the action space); the
dolphin's fluke stroke and turn-MCs; with ``--video`` it records the swim to DIR.
``--model-sweep`` prints how the Strouhal number and stride respond to the force model and the
swim-MC's gains. The figures' functions are in :mod:`animat.experiments.biology`.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.core.env import BodyEnv
from animat.envs.motor.dolphin import dolphin_calibrated
from animat.envs.motor.fish import (
    PAPER_SWIM,
    CStartParams,
    SwimParams,
    calibrated,
    fin_mc,
    swim_mc,
    turn_duration,
    turn_mc,
)
from animat.envs.physics.system import Water

from .biology import (
    c_start,
    cruise_figures,
    dolphin_cruise,
    dolphin_turn,
    fish_cruise,
    gait_grid,
    hand_mc_over_starts,
    play,
)
from .parser import demo_arguments

MODELS = ("resistive", "reactive")  # each printed with its own hand controllers (calibrated)
GRID_HZ, GRID_LAGS = [2.0, 3.0, 4.0], [0.0, 0.5, 1.0, 1.5, 2.0]  # Hz; rad per segment
SPREAD_SEEDS = list(range(1000, 1032))  # starts of the fish's start spread

PAPER = {"model": "resistive"}
PAPER_GAINS = {"max_amplitude": PAPER_SWIM.max_amplitude}  # the paper's swim-MC's (1.0)
SWEEP = [  # (label, Water fields, SwimParams fields)
    ("resistive (cross-flow, skin friction)", PAPER, PAPER_GAINS),
    ("no skin friction", {**PAPER, "friction_coefficient": 0.0}, PAPER_GAINS),
    ("the paper's reaction (n.w)|w|", {**PAPER, "reaction": "paper"}, PAPER_GAINS),
    ("fluid coefficient x0.5", {**PAPER, "fluid_coefficient": 250.0}, PAPER_GAINS),
    ("fluid coefficient x2", {**PAPER, "fluid_coefficient": 1000.0}, PAPER_GAINS),
    ("fluid coefficient x4", {**PAPER, "fluid_coefficient": 2000.0}, PAPER_GAINS),
    ("amplitude x0.6", PAPER, {"max_amplitude": 0.6}),
    ("phase lag 0.5 pi", PAPER, {**PAPER_GAINS, "phase_lag": 0.5 * np.pi}),
    ("phase lag 0", PAPER, {**PAPER_GAINS, "phase_lag": 0.0}),
    ("5 Hz", PAPER, {**PAPER_GAINS, "max_hz": 5.0}),
    ("reactive, the paper's swim-MC", {"model": "reactive"}, PAPER_GAINS),
    ("reactive (the default), its swim-MC", {"model": "reactive"}, {}),
    ("reactive, added mass x0.5", {"model": "reactive", "added_mass": 0.5}, {}),
    ("reactive, no skin friction", {"model": "reactive", "friction_coefficient": 0.0}, {}),
]


def model_sweep(seconds: float = 10.0) -> list[tuple[str, dict[str, float]]]:
    """Cruise figures of the full-speed swim-MC for each row of ``SWEEP`` (seeded start)."""
    rows = []
    for label, water, gains in SWEEP:
        rows.append((label, fish_cruise(water, SwimParams(**gains), seconds)))
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    demo_arguments(parser)
    run(parser.parse_args(argv))


def run(args: argparse.Namespace) -> None:
    """Print the swim, turns and fins' figures (see the module's docstring)."""
    if args.model_sweep:
        print(f"{'variant':<40} {'U BL/s':>7} {'A BL':>6} {'f Hz':>5} {'St':>5} {'stride':>7}")
        for label, fig in model_sweep(args.seconds):
            print(f"{label:<40} {fig['U']:>7.2f} {fig['A']:>6.2f} {fig['f']:>5.1f} "
                  f"{fig['St']:>5.2f} {fig['stride']:>7.2f}")
        return
    for model in MODELS:
        print(f"== {model} water (water={{'model': '{model}'}}) ==")
        water_figures(model, args)
        dolphin_figures(model)


def water_figures(model: str, args: argparse.Namespace) -> None:
    """Print one water's figures (the module's docstring), its recalibrated controllers'."""
    water, (swim, turn) = {"model": model}, calibrated(model)
    video = bool(args.video) and model == Water().model  # the default water's swim
    env = BodyEnv("swim", duration=args.seconds, water=water, start_spread="point",
                  render_mode="rgb_array" if video else None)
    if video:
        env = gym.wrappers.RecordVideo(env, args.video, episode_trigger=lambda e: e == 0,
                                       disable_logger=True)
    length, dt = env.unwrapped.body_length, env.unwrapped.dt
    infos, nodes = play(env, lambda t: swim_mc(1.0, t, swim), args.seconds)
    fig = cruise_figures(infos, nodes, dt, env.unwrapped.body, swim.max_hz, args.seconds / 2)
    along = infos[-1]["com"][0] - infos[len(infos) // 2 - 1]["com"][0]
    heading_speed = along / length / (args.seconds / 2)
    print(f"swim-MC (amplitude {swim.max_amplitude:g}), speed 1, over the last "
          f"{args.seconds / 2:g} s: U {fig['U']:.2f} BL/s ({heading_speed:.2f}"
          f" along the start heading), tail beat f {fig['f']:.1f} Hz, amplitude A "
          f"{fig['A']:.2f} BL (peak to peak), Strouhal fA/U {fig['St']:.2f}, stride "
          f"{fig['stride']:.2f} BL per beat, the body's rear wave {fig['V']:.2f} BL/s (slip "
          f"U/V {fig['slip']:.2f}); heading {infos[-1]['heading_deg']:+.1f} deg at "
          f"{args.seconds:g} s")
    env.close()
    grid, waves = gait_grid(water, GRID_HZ, GRID_LAGS)
    f, k = np.unravel_index(np.argmax(grid[..., 0]), grid[..., 0].shape)
    kept = grid[..., 1] / grid[..., 0]
    print(f"waves of contraction, {GRID_HZ} Hz x lags {GRID_LAGS} rad per segment: the fastest "
          f"{GRID_HZ[f]:g} Hz, lag {GRID_LAGS[k]:g}, at {grid[f, k, 0]:.2f} BL/s; reversed "
          f"{grid[f, k, 1]:.2f} ({grid[f, k, 1] / grid[f, k, 0]:.0%}; speeds along the start "
          f"heading, negative: it turned back); each wave reversed "
          f"keeps {kept.min():.0%}-{kept.max():.0%}")
    backward = waves[:, 1:] < 0  # the body's rear wave runs tail to head (not the flaps)
    fastest = grid[:, 1:][backward].max() if backward.any() else float("nan")
    print(f"  the body's own rear wave: {waves[f, k, 0]:+.2f} BL/s for the fastest, "
          f"{waves[f, k, 1]:+.2f} reversed (+: head to tail); it runs tail to head in "
          f"{int(backward[..., 1].sum())} of the {backward[..., 1].size} reversed muscle waves "
          f"(and {int(backward[..., 0].sum())} of the forward ones), the fastest of those at "
          f"{fastest:.2f} BL/s")
    headings = c_start(water, CStartParams())
    start = CStartParams()
    print(f"C-start (bend {start.bend:g} s, counter-stroke {start.counter:g} s): "
          f"{headings.max():.1f} deg at most within 1 s, {headings[-1]:.1f} at 1 s")
    end = turn_duration(np.pi / 2, turn)
    for left in (True, False):
        sign = 1.0 if left else -1.0
        env = BodyEnv("turn", duration=end + 3.0, water=water, start_spread="point")
        turn_infos, _ = play(env, lambda t, left=left: turn_mc(np.pi / 2, t, left, turn),
                             end + 3.0)
        headings = sign * np.degrees(np.unwrap(np.radians([i["heading_deg"]
                                                           for i in turn_infos])))
        at_end = headings[int(round(end / dt)) - 1]
        print(f"{'left' if left else 'right'}-turn-MC, 90 deg: {at_end:.1f}"
              f" deg when it ends at {end:.1f} s, {headings.max():.1f} at most, "
              f"{headings[-1]:.1f} 3 s later")
    spread_figures(water)
    for pitch in (1.0, -1.0):
        dive = BodyEnv("swim", duration=6.0, fins=True, water=water, start_spread="point")
        fin_infos, _ = play(dive, lambda t: swim_mc(1.0, t, swim), 6.0,
                            fins=fin_mc(pitch=pitch) / fin_mc(pitch=1.0)[0])
        z = np.array([i["com"][2] for i in fin_infos]) / length
        print(f"fin-MC pitch {pitch:+.0f} while swimming: depth change {z[-1] - z[0]:+.2f} BL "
              f"in 6 s, {(z[-1] - z[59]) / 3.0:+.3f} BL/s over the last 3 s")


def spread_figures(water: dict) -> None:
    """Print the swim-MC's speed and the 90 deg turn-MCs' final errors over the fish's start
    spread (:data:`SPREAD_SEEDS`), and from the point start (the node noise only): what an
    open-loop controller meets from starts that differ."""
    for label, spread in (("the fish's start spread", None), ("the point start", "point")):
        kwargs = {"water": water, "duration": 4.0, "start_spread": spread}
        swim = hand_mc_over_starts("Animat/FishSwim-v0", kwargs, SPREAD_SEEDS)
        speed = swim["speed_bl_per_s"]
        print(f"over {len(SPREAD_SEEDS)} starts of {label} (seeds {SPREAD_SEEDS[0]}-"
              f"{SPREAD_SEEDS[-1]}): swim-MC, 4 s, {speed.mean():.2f} +- {speed.std():.3f} BL/s "
              f"({speed.min():.2f}-{speed.max():.2f})")
        for direction in ("left", "right"):
            error = hand_mc_over_starts("Animat/FishTurn-v0", {**kwargs, "direction": direction},
                                        SPREAD_SEEDS)["final_heading_error_deg"]
            print(f"  {direction}-turn-MC, 90 deg, at 4 s: {error.mean():.1f} deg from the "
                  f"target on average (std {error.std():.1f}, at most {error.max():.1f})")


def dolphin_figures(model: str) -> None:
    """Print one water's figures of the dolphin's hand MCs (calibrated for it)."""
    calibration = dolphin_calibrated(model)
    swim = dolphin_cruise({"model": model}, calibration.swim)
    print(f"dolphin fluke stroke (amplitude {calibration.swim.max_amplitude:g}, "
          f"{calibration.swim.max_hz:g} Hz), last 3 of 6 s: U {swim['U']:.2f} BL/s, A "
          f"{swim['A']:.2f} BL, St {swim['St']:.2f}, stride {swim['stride']:.2f} BL per beat; "
          f"pitch {swim['pitch']:+.0f} deg at 6 s (the stroke pitches it nose down)")
    for direction, angle in (("up", 90.0), ("down", 90.0), ("left", 90.0), ("right", 90.0)):
        at_end, later = dolphin_turn(model, direction, angle)
        print(f"  dolphin turn-MC {direction} {angle:g} deg: {at_end:.0f} when it ends, "
              f"{later:.0f} 2 s later")


if __name__ == "__main__":
    main()
