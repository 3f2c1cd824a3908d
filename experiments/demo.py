"""Swim demo: the hand-designed motor controllers drive the fish; prints what they achieve.

``animat demo [--seconds 10] [--video DIR]`` (or ``python -m animat.experiments.demo``): swims
at full speed with the swim-MC and prints the biology figures of its cruise (tail-beat frequency
f, peak-to-peak tail amplitude A, speed U along the start heading, Strouhal number fA/U, stride
U/f), turns left and right with the turn-MCs, and rises and dives with the fin-MC (fin angles
through the action space); with ``--video`` it records the swim to DIR. ``--model-sweep`` prints
how the Strouhal number and stride respond to the force model and the swim-MC's gains (the
measurements behind the README's note that a resistive model alone cannot reach fish-like St).
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.core.env import BodyEnv
from animat.envs.motor.fish import SwimParams, fin_mc, swim_mc, to_action, turn_duration, turn_mc

from .parser import demo_arguments

TAIL_TIPS = [21, 22]


def play(env: gym.Env, actuation, seconds: float, fins=None) -> tuple[list[dict], np.ndarray]:
    """Run ``actuation(t) -> u (6,)`` for ``seconds`` (with fin commands ``fins`` (2,) in
    [-1, 1] appended when given); returns the per-step infos and the tail tip's track (T, 3)."""
    env.reset(seed=0)
    infos, tail = [], []
    for k in range(int(round(seconds / env.unwrapped.dt))):
        action = to_action(actuation((k + 1) * env.unwrapped.dt))
        if fins is not None:
            action = np.append(action, fins).astype(np.float32)
        infos.append(env.step(action)[4])
        tail.append(env.unwrapped.node_positions[TAIL_TIPS].mean(axis=0))
    return infos, np.array(tail)


def cruise_figures(infos: list[dict], tail: np.ndarray, dt: float, length: float,
                   hz: float, start: float) -> dict[str, float]:
    """Biology figures over the part of a swim after ``start`` s: U (BL/s, net travel per
    second), A (BL, the tail tip's peak-to-peak excursion across the travel direction), f (Hz),
    St = fA/U and the stride U/f (BL per beat)."""
    first = int(round(start / dt))
    com = np.array([i["com"] for i in infos])[first:, :2]
    travel = com[-1] - com[0]
    speed = np.linalg.norm(travel) / ((len(com) - 1) * dt)
    across = np.array([-travel[1], travel[0]]) / np.linalg.norm(travel)
    sway = (tail[first:, :2] - com) @ across
    amplitude = sway.max() - sway.min()
    return {"U": speed / length, "A": amplitude / length, "f": hz,
            "St": hz * amplitude / speed, "stride": speed / length / hz}


SWEEP = [  # (label, Water fields, SwimParams fields)
    ("default", {}, {}),
    ("no skin friction", {"friction_coefficient": 0.0}, {}),
    ("the paper's reaction (n.w)|w|", {"reaction": "paper"}, {}),
    ("fluid coefficient x0.5", {"fluid_coefficient": 250.0}, {}),
    ("fluid coefficient x2", {"fluid_coefficient": 1000.0}, {}),
    ("fluid coefficient x4", {"fluid_coefficient": 2000.0}, {}),
    ("amplitude x0.6", {}, {"max_amplitude": 0.6}),
    ("phase lag 0.5 pi", {}, {"phase_lag": 0.5 * np.pi}),
    ("phase lag 0", {}, {"phase_lag": 0.0}),
    ("5 Hz", {}, {"max_hz": 5.0}),
]


def model_sweep(seconds: float = 10.0) -> list[tuple[str, dict[str, float]]]:
    """Cruise figures of the full-speed swim-MC for each row of ``SWEEP`` (seeded start)."""
    rows = []
    for label, water, gains in SWEEP:
        params = SwimParams(**gains)
        env = BodyEnv("swim", duration=seconds, water=water)
        infos, tail = play(env, lambda t, params=params: swim_mc(1.0, t, params), seconds)
        rows.append((label, cruise_figures(infos, tail, env.dt, env.body_length, params.max_hz,
                                           seconds / 2)))
    return rows


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    demo_arguments(parser)
    run(parser.parse_args(argv))


def run(args: argparse.Namespace) -> None:
    """Print the swim, turns and fins' figures (see the module's docstring)."""
    if args.model_sweep:
        print(f"{'variant':<32} {'U BL/s':>7} {'A BL':>6} {'f Hz':>5} {'St':>5} {'stride':>7}")
        for label, fig in model_sweep(args.seconds):
            print(f"{label:<32} {fig['U']:>7.2f} {fig['A']:>6.2f} {fig['f']:>5.1f} "
                  f"{fig['St']:>5.2f} {fig['stride']:>7.2f}")
        return
    env = BodyEnv("swim", duration=args.seconds, render_mode="rgb_array" if args.video else None)
    if args.video:
        env = gym.wrappers.RecordVideo(env, args.video, episode_trigger=lambda e: e == 0,
                                       disable_logger=True)
    length, dt = env.unwrapped.body_length, env.unwrapped.dt
    infos, tail = play(env, lambda t: swim_mc(1.0, t), args.seconds)
    fig = cruise_figures(infos, tail, dt, length, SwimParams().max_hz, args.seconds / 2)
    along = infos[-1]["com"][0] - infos[len(infos) // 2 - 1]["com"][0]
    print(f"swim-MC, speed 1, over the last {args.seconds / 2:g} s: U {fig['U']:.2f} BL/s "
          f"({along / length / (args.seconds / 2):.2f} along the start heading), tail beat "
          f"f {fig['f']:.1f} Hz, amplitude A {fig['A']:.2f} BL (peak to peak), "
          f"Strouhal fA/U {fig['St']:.2f}, stride {fig['stride']:.2f} BL per beat; heading "
          f"{infos[-1]['heading_deg']:+.1f} deg at {args.seconds:g} s")
    env.close()
    end = turn_duration(np.pi / 2)
    for left in (True, False):
        sign = 1.0 if left else -1.0
        turn = BodyEnv("turn", duration=end + 3.0)
        turn_infos, _ = play(turn, lambda t, left=left: turn_mc(np.pi / 2, t, left), end + 3.0)
        headings = sign * np.array([i["heading_deg"] for i in turn_infos])
        at_end = headings[int(round(end / dt)) - 1]
        print(f"{'left' if left else 'right'}-turn-MC, 90 deg: {at_end:.1f} deg when it ends at "
              f"{end:.1f} s, {headings.max():.1f} at most, {headings[-1]:.1f} 3 s later")
    for pitch in (1.0, -1.0):
        dive = BodyEnv("swim", duration=6.0, fins=True)
        fin_infos, _ = play(dive, lambda t: swim_mc(1.0, t), 6.0,
                            fins=fin_mc(pitch=pitch) / fin_mc(pitch=1.0)[0])
        z = np.array([i["com"][2] for i in fin_infos]) / length
        print(f"fin-MC pitch {pitch:+.0f} while swimming: depth change {z[-1] - z[0]:+.2f} BL "
              f"in 6 s, {(z[-1] - z[59]) / 3.0:+.3f} BL/s over the last 3 s")


if __name__ == "__main__":
    main()
