"""artificial-animals: the artificial fish of Terzopoulos, Rabie & Grzeszczuk (1995).

One import namespace for the three parts of the repository (kept as its top-level folders
``envs/``, ``learners/`` and ``experiments/``): :mod:`animat.envs` (the world, bodies, eyes and
Gymnasium tasks), :mod:`animat.learners` (the paper's learners and the baselines) and
:mod:`animat.experiments` (the ``animat`` launcher). ``import animat`` registers the
``Animat/...`` environments with Gymnasium.
"""

from __future__ import annotations

from animat import envs  # noqa: F401  (registers Animat/FishSwim-v0, ...)

__all__ = ["envs"]
