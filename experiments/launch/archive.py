"""A run folder packed for a task on another node and read back as data only.

:func:`pack` writes a folder as an uncompressed tar archive; :func:`unpack` reads one as
untrusted input on every Python the project accepts, without relying on tarfile's ``data``
filter alone (which let a chain of links escape before CPython 3.11.13 and 3.12.11,
CVE-2025-4517): every member is checked before anything is written (:func:`checked_members`:
regular files and folders only, relative normalised names, a bound on each file, on the whole
and on the count), then extracted with the ``data`` filter as a second wall into a fresh
temporary folder, which is given its name only when whole. :func:`place` puts a returned folder
in place of the prepared one, under its lock, the prepared one's own files kept and
``result.json`` last, so that a bad return leaves the folder as it was prepared.
"""

from __future__ import annotations

import io
import os
import posixpath
import shutil
import tarfile
import tempfile
from pathlib import Path

from animat.learners.storage.files import (
    LIMITS,
    UnsafeFile,
    read_bytes,
    read_json,
)
from animat.learners.storage.tree import MAX_TREE_DEPTH, run_folder

from .folders import read_status
from .lock import LOCK_NAME, RunError, run_lock

MEMBER_BYTES = max(LIMITS.values())  # no run-folder file is read past its kind's bound
ARCHIVE_BYTES = 4 * MEMBER_BYTES
ARCHIVE_MEMBERS = 100_000
KEPT = ("config.yaml", "command.txt", "versions.json")  # the driver's, which a run never rewrites


def pack(folder: Path) -> bytes:
    """A run folder as an uncompressed tar archive (its lock file left out)."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as archive:
        for path in sorted(Path(folder).iterdir()):
            if path.name != LOCK_NAME:
                archive.add(path, arcname=path.name)
    return buffer.getvalue()


def _member_problem(member: tarfile.TarInfo) -> str | None:
    """Why ``member`` may not be in a run folder's archive, or None."""
    if member.type not in (tarfile.REGTYPE, tarfile.AREGTYPE, tarfile.DIRTYPE):
        kind = ("a link" if member.issym() or member.islnk() else
                "a device or FIFO" if member.isdev() else f"of tar type {member.type!r}")
        return f"is {kind}; a run folder holds only regular files and folders"
    name = member.name.rstrip("/") if member.isdir() else member.name
    if (not name or name.startswith("/") or posixpath.normpath(name) != name
            or name == ".." or name.startswith("../") or "\\" in name):
        return "is not a relative, normalised path inside the folder"
    parts = name.split("/")
    if len(parts) > MAX_TREE_DEPTH or max(map(len, parts)) > 255:
        return f"is nested deeper than {MAX_TREE_DEPTH} folders or has a name over 255 characters"
    if name == LOCK_NAME:
        return "is the folder's lock file, which no archive carries"
    if member.size > MEMBER_BYTES:
        return f"holds {member.size:,} bytes, more than a run-folder file may ({MEMBER_BYTES:,})"
    return None


def checked_members(archive: tarfile.TarFile, where: Path) -> list[tarfile.TarInfo]:
    """Every member of ``archive``, each checked (:func:`_member_problem`), none named twice,
    within the bounds on the whole; RunError naming the first member at fault."""
    members: list[tarfile.TarInfo] = []
    names: set[str] = set()
    total = 0
    for member in archive:
        problem = _member_problem(member)
        name = member.name.rstrip("/")
        if problem is None and name in names:
            problem = "is named twice"
        total += member.size
        if problem is None and total > ARCHIVE_BYTES:
            problem = f"takes the archive past {ARCHIVE_BYTES:,} bytes"
        if problem is None and len(members) >= ARCHIVE_MEMBERS:
            problem = f"takes the archive past {ARCHIVE_MEMBERS:,} members"
        if problem:
            raise RunError(f"{where}: the returned run folder's member {member.name[:200]!r} "
                           f"{problem}; nothing was written")
        names.add(name)
        members.append(member)
    return members


def unpack(data: bytes, folder: Path, shown: Path | None = None) -> None:
    """Extract a :func:`pack` archive as the new folder ``folder`` (which must not exist): its
    members checked first (:func:`checked_members`), extracted beside it with the ``data``
    filter, then renamed into place whole. RunError in one line, naming ``shown`` (default
    ``folder``), for anything else, with nothing left behind."""
    folder = Path(folder)
    staging = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name[:100]}."))
    try:
        staging.chmod(0o755)  # a folder as any other, not the private one mkdtemp makes
        _extract(data, staging, shown or folder)
        os.rename(staging, folder)
    except OSError as error:
        raise RunError(f"{shown or folder}: the returned run folder could not be unpacked "
                       f"({error})") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _extract(data: bytes, into: Path, shown: Path) -> None:
    """Extract the archive ``data`` into the empty folder ``into``, its members checked first
    (:func:`checked_members`), the ``data`` filter the second wall; RunError naming ``shown``."""
    try:
        with tarfile.open(fileobj=io.BytesIO(data), mode="r:") as archive:
            members = checked_members(archive, shown)
            archive.extractall(into, members=members, filter="data")
    except (tarfile.TarError, OSError) as error:
        raise RunError(f"{shown}: the returned run folder could not be unpacked ({error})"
                       ) from None


def place(data: bytes, folder: Path) -> dict:
    """Put a finished run folder returned by a task (:func:`pack`) in place of the prepared
    ``folder``, under its lock: extracted beside it as :func:`unpack` extracts, checked (a
    run's ``result.json``, the prepared files unchanged), then moved in entry by entry, the
    ``result.json`` last; returns the folder's status."""
    folder = run_folder(folder)
    with run_lock(folder), tempfile.TemporaryDirectory(dir=folder.parent,
                                                       prefix=f".{folder.name}.") as scratch:
        returned = Path(scratch)
        _extract(data, returned, folder)
        _check_return(returned, folder)
        entries = sorted(returned.iterdir(), key=lambda p: p.name == "result.json")
        for entry in entries:
            _move(entry, folder / entry.name)
    return read_status(folder)


def _check_return(returned: Path, folder: Path) -> None:
    """RunError in one line unless ``returned`` holds a run's result.json (a JSON object with a
    ``status``), the prepared folder's own files unchanged, and no entry where the prepared
    folder has one of another kind; so a bad return never replaces what the driver wrote, nor
    stops half-way through the moves."""
    path = returned / "result.json"
    if not path.exists():
        raise RunError(f"{folder}: the returned run folder has no result.json")
    try:
        status = read_json(path).get("status")
    except (OSError, ValueError):
        status = None
    if not isinstance(status, str):
        raise RunError(f"{folder}: the returned result.json is not a run's (no status)")
    for name in KEPT:
        if (returned / name).exists() and _bytes(returned / name) != _bytes(folder / name):
            raise RunError(f"{folder}: the returned {name} differs from the prepared one")
    clash = _clash(returned, folder)
    if clash:
        raise RunError(f"{folder}: the returned {clash} is a file where the prepared folder "
                       "has a folder, or the other way round")


def _bytes(path: Path) -> bytes | None:
    """The regular file's bytes (within the bound of a text file), None for anything else."""
    try:
        return read_bytes(path, "text")
    except (OSError, UnsafeFile):
        return None


def _clash(returned: Path, prepared: Path) -> str | None:
    """The first entry of ``returned`` (its path below it) whose namesake in ``prepared`` is of
    another kind (a folder against a file or link), or None."""
    for entry in returned.iterdir():
        target = prepared / entry.name
        if not os.path.lexists(target):
            continue
        is_folder = target.is_dir() and not target.is_symlink()
        if entry.is_dir() != is_folder:
            return entry.name
        if is_folder and (below := _clash(entry, target)):
            return f"{entry.name}/{below}"
    return None


def _move(entry: Path, target: Path) -> None:
    """Move ``entry`` to ``target``: a folder into the folder there file by file (what a run
    adds to the folder the driver prepared); anything else by rename, which replaces a file
    or link at ``target`` rather than following it."""
    if entry.is_dir() and os.path.lexists(target):
        for child in entry.iterdir():
            _move(child, target / child.name)
    else:
        os.replace(entry, target)
