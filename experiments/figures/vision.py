"""The paper's vision figures, re-made from a pursuit with the active-vision policy.

``animat figures --out DIR [--seed S] [--frames N]`` plays ``Animat/FishPursuit-v0`` with
:class:`animat.envs.world.pursuit.policy.ActiveVisionPolicy` for N frames (default 150) and writes:

* ``fig5_retinas.png``: the 4 component images and the composite of each eye (Fig. 5) at the
  frame where the prey is nearest the middle of the pursuit;
* ``fig7_gaze.png``: theta and phi of both eyes, the vergence angle theta_R - theta_L and the
  turn angle theta_P (the mean of the eyes' theta) over the pursuit (Fig. 7);
* ``fig8_sequence.png``: the left eye's composite every N/8 frames (Fig. 8);

and prints the pursuit's metrics.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import gymnasium as gym
import numpy as np

import animat  # noqa: F401
from animat.envs.vision.retina import composite
from animat.envs.world.pursuit.policy import ActiveVisionPolicy


def play_pursuit(seed: int, frames: int) -> tuple[list[dict], list[np.ndarray]]:
    """Infos and (2, L, S, S, 3) retina images of each frame of a pursuit."""
    env = gym.make("Animat/FishPursuit-v0", duration=frames * 0.05)
    policy = ActiveVisionPolicy()
    obs, info = env.reset(seed=seed)
    infos, images = [], []
    for _ in range(frames):
        action, _ = policy.predict(obs)
        obs, _, _, _, info = env.step(action)
        infos.append(info)
        images.append(env.unwrapped.retina_images())
    return infos, images


def _labelled(image: np.ndarray, text: str) -> np.ndarray:
    out = image.copy()
    cv2.putText(out, text, (6, 18), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1,
                cv2.LINE_AA)
    return out


def fig5(images: np.ndarray) -> np.ndarray:
    """Rows: left eye, right eye; columns: levels 0..3 (each magnified to 256 px), then the
    eye's composite (512 px, downsized to 256)."""
    rows = []
    for eye, name in zip(images, ("left", "right")):
        tiles = [_labelled(cv2.resize(level, (256, 256), interpolation=cv2.INTER_NEAREST),
                           f"{name} level {k}") for k, level in enumerate(eye)]
        tiles.append(_labelled(cv2.resize(composite(eye), (256, 256),
                                          interpolation=cv2.INTER_AREA), f"{name} composite"))
        rows.append(np.concatenate(tiles, axis=1))
    return np.concatenate(rows, axis=0)


def fig7(infos: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    gaze = np.degrees(np.array([i["gaze"] for i in infos]))
    frames = np.arange(len(infos))
    figure, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    axes[0].plot(frames, gaze[:, 0], label="theta left")
    axes[0].plot(frames, gaze[:, 2], label="theta right")
    axes[0].plot(frames, gaze[:, 1], "--", label="phi left")
    axes[0].plot(frames, gaze[:, 3], "--", label="phi right")
    axes[0].set_ylabel("gaze angle, deg")
    axes[0].legend(loc="upper right", fontsize=8)
    axes[1].plot(frames, np.degrees([i["vergence"] for i in infos]), label="vergence")
    axes[1].plot(frames, 0.5 * (gaze[:, 0] + gaze[:, 2]), label="turn angle theta_P")
    axes[1].set_ylabel("deg")
    axes[1].set_xlabel("frame (0.05 s)")
    axes[1].legend(loc="upper right", fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def fig8(images: list[np.ndarray], count: int = 8) -> np.ndarray:
    picks = np.linspace(0, len(images) - 1, count).astype(int)
    tiles = [_labelled(cv2.resize(composite(images[k][0]), (256, 256),
                                  interpolation=cv2.INTER_AREA), f"frame {k}") for k in picks]
    return np.concatenate([np.concatenate(tiles[:count // 2], axis=1),
                           np.concatenate(tiles[count // 2:], axis=1)], axis=0)


def make_figures(out: str | Path, seed: int = 0, frames: int = 150) -> dict[str, float]:
    """Write the three figures into ``out``; returns the pursuit's figures."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    infos, images = play_pursuit(seed, frames)
    distances = np.array([i["target_distance"] for i in infos])
    middle = int(np.argmin(np.abs(np.arange(frames) - frames // 2)))
    cv2.imwrite(str(out / "fig5_retinas.png"), fig5(images[middle])[:, :, ::-1])
    fig7(infos, out / "fig7_gaze.png")
    cv2.imwrite(str(out / "fig8_sequence.png"), fig8(images)[:, :, ::-1])
    in_fovea = np.array([i["target_in_fovea"] for i in infos])
    return {"frames": float(frames), "fovea_fraction": float(in_fovea.mean()),
            "distance_start_m": float(distances[0]), "distance_end_m": float(distances[-1]),
            "vergence_end_deg": float(np.degrees(infos[-1]["vergence"]))}
