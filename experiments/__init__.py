"""The experiment launcher ``animat`` (:mod:`animat.experiments.cli`) and what it runs.

Rooms: :mod:`.launch` (configs, run folders, progress, shipped files), :mod:`.figures` (the
paper's figures, the stunts, the world's video, the abstraction table) and :mod:`.bench` (the
benchmarks); beside them the commands: ``cli`` (and its ``parser``), ``sweep``, ``tune``,
``compare``, ``evaluate``, ``demo`` and ``fingerprint``. Imports run one way: experiments ->
learners -> envs.

:func:`run_experiment` (:mod:`.launch.execute`) is ``animat run`` from Python, in the caller's
process, where what the caller registered is known (docs/tutorials/extending.md); imported when
first asked for, so that the commands that do not run one do not import the learners.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .launch.execute import run_experiment

__all__ = ["run_experiment"]


def __getattr__(name: str) -> Any:
    """:func:`run_experiment`, from :mod:`.launch.execute` (imported when first asked for)."""
    if name == "run_experiment":
        from .launch.execute import run_experiment

        return run_experiment
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
