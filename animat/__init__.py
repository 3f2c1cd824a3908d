"""artificial-animals: the artificial fish of Terzopoulos, Rabie & Grzeszczuk (1995).

One import namespace for the three parts of the repository (kept as its top-level folders
``envs/``, ``learners/`` and ``experiments/``): :mod:`animat.envs` (the world, bodies, eyes and
Gymnasium tasks), :mod:`animat.learners` (the paper's learners and the baselines) and
:mod:`animat.experiments` (the ``animat`` launcher). ``import animat`` registers the
``Animat/...`` environments with Gymnasium.
"""

from __future__ import annotations

import os
from importlib.util import find_spec

# Numba's threads and torch's run on two OpenMP runtimes (the system's libgomp and torch's
# own). By default an idle OpenMP thread spins for a while before it sleeps, so in a process
# that steps the envs and updates a network (PPO), each runtime's idle threads took the cores
# from the other's working ones. Read by each runtime as it loads (torch's on import, Numba's
# at its first parallel kernel); a value the user set is kept.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

try:
    from animat import envs  # noqa: F401  (registers Animat/FishSwim-v0, ...)
except ImportError:
    # Python inside a checkout finds this folder before an installed copy; without an editable
    # install nothing maps envs/, learners/ and experiments/ into animat.*, and Python's own
    # message ("circular import") would point the wrong way.
    if find_spec("animat.envs") is None:
        raise ImportError(
            f"animat is imported from {__file__}, a checkout's folder, and nothing installed "
            "maps its envs/, learners/ and experiments/ into animat.*: run `pip install -e .` "
            "in the checkout, or run Python from outside it") from None
    raise

__all__ = ["envs"]
