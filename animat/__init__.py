"""artificial-animals: the artificial fish of Terzopoulos, Rabie & Grzeszczuk (1995).

One import namespace for the three parts of the repository (kept as its top-level folders
``envs/``, ``learners/`` and ``experiments/``): :mod:`animat.envs` (the world, bodies, eyes and
Gymnasium tasks), :mod:`animat.learners` (the paper's learners and the baselines) and
:mod:`animat.experiments` (the ``animat`` launcher). ``import animat`` registers the
``Animat/...`` environments with Gymnasium.
"""

from __future__ import annotations

from importlib.util import find_spec

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
