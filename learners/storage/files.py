"""Run-folder files written and read safely: :func:`atomic_write` (a reader or a crash never
sees half a file, a failure leaves no temporary file), :func:`read_json` and
:class:`CorruptFile` (a file that cannot be read back, named in one line)."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path


class CorruptFile(ValueError):
    """A file of a run folder that cannot be read back (truncated, empty, not what it should
    be): its path and what is wrong, in one line."""

    def __init__(self, path: str | Path, problem: str) -> None:
        super().__init__(f"{path}: {problem} (the file is truncated or corrupt)")


def read_json(path: str | Path) -> dict:
    """A JSON object from ``path``; CorruptFile naming it when it is not one (FileNotFoundError
    when it is missing)."""
    try:
        data = json.loads(Path(path).read_text())
    except json.JSONDecodeError as error:
        raise CorruptFile(path, f"not valid JSON ({error.msg} at line {error.lineno})") from None
    except (UnicodeDecodeError, RecursionError) as error:
        raise CorruptFile(path, f"not JSON text ({type(error).__name__})") from None
    if not isinstance(data, dict):
        raise CorruptFile(path, f"holds a JSON {type(data).__name__}, not an object")
    return data


TMP_SUFFIX = ".tmp"  # atomic_write's temporary files: <name><random>.tmp beside the file


def atomic_write(path: str | Path, write, binary: bool = False, replace: bool = True) -> None:
    """Write a file atomically: ``write(file)`` fills a temporary file beside ``path``, which
    then replaces it, so a reader (or a crash) never sees half a file, and a failure (a full
    disk) leaves no temporary file behind. With ``replace`` False an existing ``path`` is left
    as it is (FileExistsError), even one made meanwhile. An OS error that names no file (a
    write on a full disk) is raised naming ``path``."""
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=TMP_SUFFIX)
    except OSError as error:  # named by the file it was for, not a temporary name
        raise _naming(error, path, always=True) from None
    try:
        with os.fdopen(handle, "wb" if binary else "w") as file:
            write(file)
            file.flush()
            os.fsync(file.fileno())
        os.chmod(tmp, 0o644)
        if replace:
            os.replace(tmp, path)
        else:
            _place_new(tmp, path)
    except OSError as error:
        raise _naming(error, path) from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def _naming(error: OSError, path: Path, always: bool = False) -> OSError:
    """``error``, or the same error (its subclass, by errno) naming ``path`` where it named no
    file (or ``always``): what a one-line report of it needs."""
    if error.errno is None or (error.filename is not None and not always):
        return error
    return OSError(error.errno, error.strerror, str(path))


def _place_new(tmp: str, path: Path) -> None:
    """Give the complete file ``tmp`` the name ``path`` only if no file has it (FileExistsError
    otherwise): a hard link where the file system has them, else claim the name, then fill it."""
    try:
        os.link(tmp, path)  # fails if path exists: no check-then-write race
    except FileExistsError:
        raise
    except OSError:
        os.close(os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644))
        os.replace(tmp, path)
