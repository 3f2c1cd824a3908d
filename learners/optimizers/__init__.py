"""Ask/tell optimisers with explicit params and state: simulated annealing (the paper's),
CMA-ES, and a coordinate search over discrete genes; :mod:`animat.learners.blackbox` runs any
of them in one loop. Each is a module that is an :class:`Optimizer`: frozen params and state
go in, new state comes out, nothing is kept between calls.

Pure NumPy (and pycma): imports no env.
"""

from __future__ import annotations

from . import annealing, cmaes, coordinate
from .protocol import Optimizer

# the package's optimisers by name, each checked against the protocol (mypy)
OPTIMIZERS: dict[str, Optimizer] = {"annealing": annealing, "cmaes": cmaes,
                                    "coordinate": coordinate}

__all__ = ["OPTIMIZERS", "Optimizer", "annealing", "cmaes", "coordinate"]
