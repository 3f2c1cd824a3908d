"""Write one documentation page per registered ``Animat/...`` env, from its docstrings, its
registration and the env as built, with a picture of its first frames (as Gymnasium's
``docs/_scripts/gen_mds.py`` does for its envs).

    python docs/scripts/gen_env_pages.py            # docs/envs/*.md and their pictures
    python docs/scripts/gen_env_pages.py --check    # exit 1 if a page's text is out of date
"""

from __future__ import annotations

import argparse
import inspect
import sys
from pathlib import Path

import cv2
import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)
from animat.envs.registration import ENVS, timing
from animat.envs.tasks import make_task

PAGES = Path(__file__).resolve().parents[1] / "envs"
SKIP_KWARGS = {"task", "body"}


def slug(env_id: str) -> str:
    """``Animat/FishSwim-v0`` -> ``FishSwim-v0``."""
    return env_id.split("/", 1)[1]


def described(env_id: str) -> str:
    """The env's own description: its task's docstring for the body envs, the env class's
    docstring otherwise (the first paragraphs, up to its argument lists)."""
    entry = ENVS[env_id]
    kwargs = dict(entry.get("kwargs", {}))
    if "task" in kwargs:
        task_kwargs = {k: v for k, v in kwargs.items() if k in {"part"}}
        source = type(make_task(kwargs["task"], **task_kwargs))
    else:
        module, name = entry["entry_point"].split(":")
        source = getattr(__import__(module, fromlist=[name]), name)
    return inspect.cleandoc(source.__doc__ or "").strip()


def page(env_id: str) -> str:
    """The Markdown page of ``env_id``."""
    env = gym.make(env_id)
    clock = timing(env_id)
    entry = ENVS[env_id]
    kwargs = {k: v for k, v in entry.get("kwargs", {}).items() if k not in SKIP_KWARGS}
    vector = "native (`gym.make_vec`)" if "vector_entry_point" in entry else "sync or async"
    rows = [("action space", f"`{env.action_space}`"),
            ("observation space", f"`{_short(env.observation_space)}`"),
            ("env step", f"{clock.dt:g} s"),
            ("episode", f"{clock.episode_steps} steps ({clock.episode_steps * clock.dt:g} s)"),
            ("vector env", vector),
            ("registered kwargs", f"`{kwargs}`" if kwargs else "none")]
    env.close()
    table = "\n".join(f"| {name} | {value} |" for name, value in rows)
    name = slug(env_id)
    return (f"# {env_id}\n\n![{env_id}]({name}.png)\n\n| | |\n|---|---|\n{table}\n\n"
            f"```python\nimport gymnasium as gym\nimport animat\n\nenv = gym.make(\"{env_id}\")\n"
            f"```\n\n## Description\n\n{described(env_id)}\n")


def _short(space) -> str:
    text = str(space)
    return text if len(text) <= 160 else text[:157] + "..."


def picture(env_id: str, path: Path, steps: int = 10) -> None:
    """A frame of ``env_id`` after ``steps`` env steps of zero actions from seed 0."""
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, env.action_space.dtype)  # every id's is a Box
    for _ in range(steps):
        env.step(action)
    frame = env.render()
    env.close()
    cv2.imwrite(str(path), np.asarray(frame)[:, :, ::-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if a page's text differs from what it would be")
    args = parser.parse_args(argv)
    PAGES.mkdir(exist_ok=True)
    stale = []
    ids = sorted(k for k in gym.registry if k.startswith("Animat/"))
    for env_id in ids:
        path = PAGES / f"{slug(env_id)}.md"
        text = page(env_id)
        if args.check:
            if not path.is_file() or path.read_text() != text:
                stale.append(path.name)
            continue
        path.write_text(text)
        picture(env_id, PAGES / f"{slug(env_id)}.png")
    index = "# Environments\n\n" + "\n".join(f"- [{i}]({slug(i)}.md)" for i in ids) + "\n"
    if args.check:
        if (PAGES / "index.md").read_text() != index:
            stale.append("index.md")
        if stale:
            print(f"out of date: {', '.join(stale)} (run python docs/scripts/gen_env_pages.py)")
        return 1 if stale else 0
    (PAGES / "index.md").write_text(index)
    return 0


if __name__ == "__main__":
    sys.exit(main())
