"""The machine a run runs on: its CPUs, Numba's threads, and the versions a run folder records
(``versions.json``: Python, the packages, the git commit of the code and whether it has
uncommitted changes)."""

from __future__ import annotations

import os
import subprocess
import sys
from importlib import metadata
from pathlib import Path

PACKAGES = ("artificial-animals", "numpy", "numba", "gymnasium", "stable-baselines3", "torch",
            "cma", "tensorboard", "pydantic", "pyyaml", "ray")


def available_cpus() -> int:
    """CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def set_threads(threads: int | None) -> int:
    """Numba's threads for this run: ``threads`` (the CPUs it was given), else every CPU this
    process may use; never more than Numba started with. Returns the count set."""
    import numba

    count = max(1, min(int(threads or available_cpus()), numba.config.NUMBA_NUM_THREADS))
    numba.set_num_threads(count)
    return count


def source_revision() -> dict[str, object]:
    """The git commit of the code that runs, and whether it has uncommitted changes
    (``{}`` outside a git checkout: an installed wheel, even in a venv inside some
    repository, has no commit of its own)."""
    root = Path(__file__).resolve().parents[2]
    if not (root / ".git").exists():
        return {}
    try:
        commit = subprocess.run(["git", "-C", str(root), "rev-parse", "HEAD"], check=True,
                                capture_output=True, text=True, timeout=10).stdout.strip()
        changes = subprocess.run(["git", "-C", str(root), "status", "--porcelain",
                                  "--untracked-files=no"], check=True, capture_output=True,
                                 text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return {}
    return {"git_commit": commit, "git_dirty": bool(changes)}


def versions() -> dict[str, str]:
    found = {"python": sys.version.split()[0], **source_revision()}
    for name in PACKAGES:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            continue
    return found
