"""The package as the tree declares it: its code folders under their ``animat`` names, every
module of them by dotted name, what a copy of the tree leaves out (a venv, build output,
caches, runs), and an environment in which a new interpreter sees nothing of this checkout or
its venv (for building the wheel and using it from a clean venv)."""

import os
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
CODE = {"animat": "animat", "animat.envs": "envs", "animat.learners": "learners",
        "animat.experiments": "experiments"}
SKIP = shutil.ignore_patterns(".git", ".venv", "runs", "build", "dist", "*.egg-info",
                              "__pycache__", ".pytest_cache", ".ruff_cache", "videos")


def clean_env() -> dict[str, str]:
    """This process's environment without what would put the checkout or its venv on a new
    interpreter's path (pip's own settings, e.g. where the CPU torch lies, are kept)."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV",
                                                             "PYTHONHOME", "PIP_USER")}
    here = str(Path(sys.executable).parent)
    env["PATH"] = os.pathsep.join(p for p in env.get("PATH", "").split(os.pathsep) if p != here)
    return env


def module_names() -> dict[str, Path]:
    """{dotted name under animat: its file} for every module of the code folders."""
    found = {}
    for name, folder in CODE.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = path.relative_to(ROOT / folder).with_suffix("").parts
            parts = parts[:-1] if parts[-1] == "__init__" else parts
            if parts[-1:] != ("__main__",):
                found[".".join((name, *parts))] = path
    return found
