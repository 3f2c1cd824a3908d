"""Checkpoints as data: a learner's progress (e.g. a black-box learner's
:class:`~animat.learners.blackbox_run.Run`) written as JSON and read back without pickle.

The progress is a tree of a few known classes (for a black-box run: the run, its phases, the
optimisers' params and states, an FFT abstraction), NumPy arrays and plain values.
:func:`to_data` writes an object whose class reads itself back (``from_dict``) as
``{"__type__": name, "data": its to_dict()}``, another dataclass as ``{"__type__": name,
...fields}``, each array as ``{"__array__": dtype, "shape", "data"}`` and a tuple as
``{"__tuple__": [...]}``; floats go through ``repr`` and come back bit for bit (``inf`` and
``nan`` included). :func:`from_data` builds only the classes its caller names (the writer's
own table, e.g. :data:`animat.learners.blackbox_run.CHECKPOINT_TYPES`): a file that names
anything else is refused, so a checkpoint planted in a shared run folder cannot run code.
"""

from __future__ import annotations

import dataclasses
import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from .files import CorruptFile, atomic_write, read_bytes
from .migration import fields_written_before

FORMAT = "artificial-animals black-box checkpoint 1"


def to_data(value: Any) -> Any:
    """``value`` as JSON-able data (see the module's docstring)."""
    if hasattr(type(value), "from_dict") and hasattr(value, "to_dict"):
        return {"__type__": type(value).__name__, "data": value.to_dict()}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = {f.name: to_data(getattr(value, f.name)) for f in dataclasses.fields(value)
                  if f.metadata.get("checkpoint", True)}
        return {"__type__": type(value).__name__, **fields}
    if isinstance(value, np.ndarray):
        return {"__array__": value.dtype.str, "shape": list(value.shape),
                "data": value.ravel().tolist()}
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, tuple):
        return {"__tuple__": [to_data(v) for v in value]}
    if isinstance(value, list):
        return [to_data(v) for v in value]
    if isinstance(value, dict):
        if not all(isinstance(k, str) for k in value):
            raise TypeError(f"a checkpoint's mapping keys must be strings: {list(value)[:3]}")
        return {k: to_data(v) for k, v in value.items()}
    if value is None or isinstance(value, bool | int | float | str):
        return value
    raise TypeError(f"a checkpoint cannot hold a {type(value).__name__}")


def from_data(data: Any, types: dict[str, type]) -> Any:
    """The value :func:`to_data` wrote, building no class but ``types`` (name: class);
    ValueError for a type it does not know."""
    if isinstance(data, list):
        return [from_data(v, types) for v in data]
    if not isinstance(data, dict):
        return data
    if "__array__" in data:
        dtype = np.dtype(data["__array__"])
        if dtype.kind not in "biuf":
            raise ValueError(f"an array of dtype {dtype} in a checkpoint")
        return np.array(data["data"], dtype=dtype).reshape(data["shape"])
    if "__tuple__" in data:
        return tuple(from_data(v, types) for v in data["__tuple__"])
    if "__type__" in data:
        name = data["__type__"]
        if name not in types:
            raise ValueError(f"a checkpoint names the type {name!r}, which it may not hold")
        if hasattr(types[name], "from_dict"):
            return types[name].from_dict(data["data"])
        fields = fields_written_before(name, {k: from_data(v, types) for k, v in data.items()
                                              if k != "__type__"})
        return types[name](**fields)
    return {k: from_data(v, types) for k, v in data.items()}


def save(path: str | Path, run, kind: str = FORMAT) -> None:
    """Write ``run`` (any value :func:`to_data` takes) to ``path`` atomically, as JSON marked
    as a ``kind`` of checkpoint (default: a black-box learner's)."""
    text = json.dumps({"format": kind, "run": to_data(run)})
    atomic_write(path, lambda file: file.write(text))


def load(path: str | Path, types: dict[str, type], kind: str = FORMAT):
    """The value saved at ``path`` as a ``kind`` of checkpoint, building no class but
    ``types`` (e.g. :data:`animat.learners.blackbox_run.CHECKPOINT_TYPES`), or None when there
    is none; CorruptFile naming the file when it is not one of these checkpoints."""
    path = Path(path)
    if not os.path.lexists(path):
        return None
    raw = read_bytes(path, "json")  # a link, a FIFO or a huge file: UnsafeFile naming it
    try:
        data = json.loads(raw.decode())
        if not isinstance(data, dict) or data.get("format") != kind:
            raise ValueError(f"not a checkpoint of the format {kind!r}")
        return from_data(data["run"], types)
    except (ValueError, TypeError, KeyError, RecursionError) as error:  # (and JSON, Unicode)
        raise CorruptFile(path, f"cannot be read back ({type(error).__name__}: "
                                f"{str(error)[:200]})") from None
