"""An older version's checkpoint format, a pickle: written only for a run it began and
resumed with ``--trust-pickles``, read back finding each class where it is now
(:data:`animat.learners.storage.migration.MOVED`),
and refused (:class:`UntrustedPickle`) unless the caller trusts the folder. New runs write
data (:mod:`animat.learners.storage.checkpoint_data`)."""

from __future__ import annotations

import os
import pickle
from pathlib import Path
from typing import Any

from .files import CorruptFile, atomic_write, open_read
from .migration import module_now


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


class _Unpickler(pickle.Unpickler):
    """Reads checkpoints written before the code moved under ``animat.`` (their ``learners.*``
    and ``envs.*`` classes are this package's) and before the learners' rooms
    (:func:`animat.learners.storage.migration.module_now`)."""

    def find_class(self, module: str, name: str):
        return super().find_class(module_now(module, name), name)
