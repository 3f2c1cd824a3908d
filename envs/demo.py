"""Swim demo: the hand-designed motor controllers drive the fish; prints what they achieve.

``python -m envs.demo [--seconds 10] [--video DIR]``: swims at full speed with the swim-MC, turns
left and right with the turn-MCs, and rises and dives with the fin-MC, printing speed (body
lengths per second), heading and depth change; with ``--video`` it records the swim to DIR.
"""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np

import envs  # noqa: F401
from envs.fish_env import FishEnv
from envs.motor import fin_mc, swim_mc, to_action, turn_mc


def play(env: gym.Env, actuation, seconds: float, fins=None) -> list[dict]:
    """Run ``actuation(t) -> u (6,)`` for ``seconds``; returns the per-step infos."""
    core = env.unwrapped.core
    env.reset(seed=0)
    infos = []
    for k in range(int(round(seconds / env.unwrapped.dt))):
        if fins is not None:
            core.fins[0] = fins
        infos.append(env.step(to_action(actuation((k + 1) * env.unwrapped.dt)))[4])
    return infos


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--video", default=None, help="folder for an mp4 of the swim")
    args = parser.parse_args(argv)
    env = FishEnv("swim", duration=args.seconds, render_mode="rgb_array" if args.video else None)
    if args.video:
        env = gym.wrappers.RecordVideo(env, args.video, episode_trigger=lambda e: e == 0,
                                       disable_logger=True)
    infos = play(env, lambda t: swim_mc(1.0, t), args.seconds)
    length, dt = env.unwrapped.body_length, env.unwrapped.dt
    com = np.array([i["com"] for i in infos])
    per_second = int(round(1.0 / dt))
    travel = np.diff(np.concatenate([[com[0]], com[per_second - 1::per_second]]), axis=0)
    direction = np.degrees(np.arctan2(travel[:, 1], travel[:, 0]))
    speed = np.linalg.norm(com[-1, :2] - com[2 * per_second, :2]) / (
        len(com) * dt - 2.0) / length
    print(f"swim-MC, speed 1: {speed:.2f} BL/s after the first 2 s; travel direction of each "
          f"second within {np.abs(direction).max():.1f} deg of +x; {com[-1, 0] / length:.2f} BL "
          "travelled")
    env.close()
    for left in (True, False):
        sign = 1.0 if left else -1.0
        turn = FishEnv("turn", duration=3.0)
        headings = sign * np.array([i["heading_deg"] for i in play(
            turn, lambda t, left=left: turn_mc(np.pi / 2, t, left), 3.0)])
        first = np.flatnonzero(headings >= 90.0)
        when = f"reached 90 deg at {(first[0] + 1) * dt:.2f} s" if first.size else "not reached"
        print(f"{'left' if left else 'right'}-turn-MC, 90 deg: {when}; "
              f"{headings[-1]:.1f} deg when the controller ends at 3 s")
    for pitch in (1.0, -1.0):
        dive = FishEnv("swim", duration=6.0)
        infos = play(dive, lambda t: swim_mc(1.0, t), 6.0, fins=fin_mc(pitch=pitch))
        change = (infos[-1]["com"][2] - infos[0]["com"][2]) / length
        print(f"fin-MC pitch {pitch:+.0f} while swimming: depth change {change:+.2f} BL in 6 s")


if __name__ == "__main__":
    main()
