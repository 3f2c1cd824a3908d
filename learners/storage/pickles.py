"""An older version's checkpoint format, a pickle: written only for a run it began and
resumed with ``--trust-pickles``, read back finding each class where it is now (:data:`MOVED`),
and refused (:class:`UntrustedPickle`) unless the caller trusts the folder. New runs write
data (:mod:`animat.learners.storage.checkpoint_data`)."""

from __future__ import annotations

import os
import pickle
from pathlib import Path
from typing import Any

from .files import CorruptFile, atomic_write, open_read


class UntrustedPickle(RuntimeError):
    """A run folder's checkpoint is a pickle (an older version's), and the caller has not said
    it trusts the folder (``--trust-pickles``)."""

    def __init__(self, path: str | Path) -> None:
        super().__init__(f"{path}: a checkpoint of an older version, saved with pickle: loading "
                         f"it can run any code its writer put in it; pass --trust-pickles if you "
                         f"trust where this run folder came from")


def save_checkpoint(path: str | Path, payload: Any) -> None:
    """Pickle ``payload`` to ``path`` atomically: an older version's checkpoint format, still
    written for a run begun by it and resumed with ``--trust-pickles`` (new runs write data:
    :mod:`animat.learners.storage.checkpoint_data`)."""
    atomic_write(path, lambda file: pickle.dump(payload, file), binary=True)


def load_checkpoint(path: str | Path) -> Any | None:
    """The payload pickled at ``path``, or None when there is none. Unpickling runs whatever
    code the file's writer put in it: only for folders the caller trusts (``--trust-pickles``)."""
    path = Path(path)
    if not os.path.lexists(path):
        return None
    with open_read(path, "pickle") as file:
        try:
            return _Unpickler(file).load()
        except (pickle.UnpicklingError, EOFError, ValueError, AttributeError, ImportError,
                IndexError, TypeError) as error:
            raise CorruptFile(path, f"cannot be read back ({type(error).__name__}: "
                                    f"{error})") from None


# modules an older version's pickled checkpoints name, and where they are now; a
# "<module>.<Class>" key: that class alone moved out of the module (the rest stayed)
MOVED = {"animat.learners.annealing": "animat.learners.optimizers.annealing",
         "animat.learners.cmaes": "animat.learners.optimizers.cmaes",
         "animat.learners.abstraction": "animat.learners.controllers.abstraction",
         "animat.learners.controller": "animat.learners.controllers.tent",
         "animat.learners.scorers.active_vision": "animat.learners.scorers.pursuit",
         "animat.learners.scorers.behaviours": "animat.learners.scorers.living_world",
         **{f"animat.learners.blackbox.{name}": "animat.learners.blackbox_run"
            for name in ("Phase", "Run")},
         **{f"animat.learners.blackbox.{name}": "animat.learners.controllers.periodic"
            for name in ("ControllerParams", "PeriodicPlayer")},
         "animat.learners.blackbox.ResultFrom": "animat.learners.controllers.report",
         "animat.learners.repertoire": "animat.learners.controllers.repertoire",
         "animat.learners.skills.repertoire": "animat.learners.controllers.repertoire",
         **{f"animat.learners.repertoire.{name}": "animat.learners.skills.basic_training"
            for name in ("BasicTrainingParams", "BasicTrainingLearner")}}


class _Unpickler(pickle.Unpickler):
    """Reads checkpoints written before the code moved under ``animat.`` (their ``learners.*``
    and ``envs.*`` classes are this package's) and before the learners' rooms (:data:`MOVED`)."""

    def find_class(self, module: str, name: str):
        if module.split(".")[0] in ("envs", "learners", "experiments"):
            module = f"animat.{module}"
        module = MOVED.get(f"{module}.{name}", MOVED.get(module, module))
        return super().find_class(module, name)
