"""A video of the living world (``animat world-video``): the 10-fish scenario of
``Animat/MarineWorld-v0`` from above a corner of the tank, at the env's rate, with the
episode's running totals written in, and its middle frame as a PNG beside it."""

from __future__ import annotations

from pathlib import Path

import cv2
import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)
from animat.envs.world.marine_env import MarineSummary

from .video import H264Video


def _caption(frame: np.ndarray, text: str) -> np.ndarray:
    out = np.ascontiguousarray(frame)
    cv2.putText(out, text, (8, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 255), 1,
                cv2.LINE_AA)
    return out


def world_video(out: str | Path, seconds: float = 60.0, seed: int = 0,
                vision: bool = False) -> dict[str, float]:
    """Write the mp4 ``out`` of ``seconds`` of the world from ``seed`` (the shark with eyes
    if ``vision``) and its middle frame (``out`` with ``.png``); returns the episode's
    totals."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    env = gym.make("Animat/MarineWorld-v0", duration=seconds, render_mode="rgb_array",
                   vision=0 if vision else None)
    env.reset(seed=seed)
    fps = round(1.0 / env.unwrapped.dt)
    summary, action = MarineSummary(), np.zeros(env.action_space.shape, np.float32)
    middle = env.unwrapped.episode_steps // 2
    with H264Video(out, fps) as video:  # a finished video only under its own name
        for step in range(env.unwrapped.episode_steps):
            info = env.step(action)[4]
            summary.update(info)
            t = summary.totals
            text = (f"t {info['time']:4.1f} s  food {t['food_eaten']:.0f}  catches "
                    f"{t['catches']:.0f}  matings {t['matings']:.0f}  obstacle hits "
                    f"{t['obstacle_collisions']:.0f}  fish hits {t['fish_collisions']:.0f}")
            picture = _caption(env.render(), text)
            video.write(picture)
            if step == middle:
                cv2.imwrite(str(out.with_suffix(".png")), picture[:, :, ::-1])
    return summary.summary()
