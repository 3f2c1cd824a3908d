"""A run folder as a whole, as untrusted input: its own path (:func:`run_folder`: the parents
resolved once, the folder itself no link), every entry below it without following a link or
recursing (:func:`walk`, :func:`check_tree`: nothing but folders and regular files, at most
:data:`MAX_TREE_DEPTH` deep), and the files of one of its folders (:func:`listing`). The files
themselves are opened by :mod:`.files`.
"""

from __future__ import annotations

import fnmatch
import os
import stat
from collections.abc import Iterator
from pathlib import Path

from .files import UnsafeFile, describe, open_dir, open_read


def run_folder(path: str | Path) -> Path:
    """A run folder's path as every file of it is then opened: its parents resolved once (where
    the user keeps runs may be a link), the folder itself no link (UnsafeFile: a shared folder
    replaced by a link would lead everything written into it elsewhere)."""
    path = Path(path)
    if os.path.islink(path):
        raise UnsafeFile(path, f"is a symbolic link (to {os.readlink(path)}); a run folder is "
                               "used where it is: name the folder itself")
    return Path(os.path.realpath(path.parent)) / path.name


def listing(folder: str | Path, pattern: str, kind: str) -> list[Path]:
    """The files of ``folder`` whose names match ``pattern`` (``fnmatch``), sorted, each
    checked to be a regular file within the bound of ``kind`` (UnsafeFile otherwise, and for a
    ``folder`` reached through a link); none when ``folder`` does not exist. For readers that
    open files by their paths (TensorBoard's)."""
    try:
        walked = open_dir(folder)
    except FileNotFoundError:
        return []
    try:
        handle = os.open(".", os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC, dir_fd=walked)
    finally:
        os.close(walked)
    try:
        names = sorted(fnmatch.filter(os.listdir(handle), pattern))
    finally:
        os.close(handle)
    paths = [Path(folder) / name for name in names]
    for path in paths:
        open_read(path, kind).close()
    return paths


MAX_TREE_DEPTH = 32  # folders below a run folder: its deepest (a skill's PPO save) is 4


def walk(folder: str | Path) -> Iterator[tuple[Path, os.stat_result]]:
    """Every entry below ``folder`` with its own ``lstat``, no link followed, the folders
    walked without recursion; UnsafeFile for folders nested past :data:`MAX_TREE_DEPTH`. An
    entry gone since it was listed (a temporary file renamed) is passed over."""
    pending = [(Path(folder), 0)]
    while pending:
        here, depth = pending.pop()
        with os.scandir(here) as entries:
            for entry in entries:
                try:
                    info = entry.stat(follow_symlinks=False)
                except FileNotFoundError:
                    continue
                yield Path(entry.path), info
                if stat.S_ISDIR(info.st_mode):
                    if depth + 1 >= MAX_TREE_DEPTH:
                        raise UnsafeFile(entry.path, f"is nested more than {MAX_TREE_DEPTH} "
                                                     "folders deep in a run folder")
                    pending.append((Path(entry.path), depth + 1))


def check_tree(folder: str | Path, writing: bool = False) -> None:
    """UnsafeFile naming the first entry below ``folder`` that is neither a folder nor a regular
    file (a link, a FIFO, a device, a socket), or, ``writing`` (a run that appends to its
    files), a regular file with another hard link: what a run folder received from someone
    else is asked before anything in it is read or written."""
    for path, info in walk(folder):
        if stat.S_ISDIR(info.st_mode) or (stat.S_ISREG(info.st_mode)
                                          and (info.st_nlink == 1 or not writing)):
            continue
        problem = (f"has {info.st_nlink - 1} other hard link(s)" if stat.S_ISREG(info.st_mode)
                   else f"is {describe(info.st_mode)}")
        raise UnsafeFile(path, f"{problem}; a run folder holds only folders and regular files"
                               + (" of its own" if writing else ""))
