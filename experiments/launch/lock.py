"""A run folder's lock: one process makes or runs a folder at a time.

``fcntl.flock`` on the folder's ``.lock`` file, taken without waiting and released by the
kernel when the process ends however it ends, so a killed run leaves no stale lock (opened as
every run-folder file is: a planted link, FIFO or hard link there is refused, never written);
:func:`lock_held` asks, for an instant, whether a process holds it (what tells a killed run
from a running one). What cannot be locked, or written, is a :class:`RunError` in one line.
"""

from __future__ import annotations

import errno
import fcntl
import os
import time
from contextlib import contextmanager
from pathlib import Path

from animat.learners.storage.files import UnsafeFile, open_file


class RunError(RuntimeError):
    """A run-folder problem (exists already, nothing to resume, ...)."""


LOCK_NAME = ".lock"
# OS errors that say a place cannot hold a run folder (what the user chose), not that the
# disk failed while working: a read-only file system, no permission, a file in the path
UNWRITABLE = {errno.EROFS, errno.EACCES, errno.EPERM, errno.ENOTDIR, errno.EEXIST,
              errno.ENOENT, errno.ENAMETOOLONG, errno.ELOOP}


@contextmanager
def run_lock(folder: Path):
    """Hold the run folder's exclusive lock for the ``with`` block: ``fcntl.flock`` on its
    ``.lock`` file, taken without waiting (RunError in one line if another process holds it)
    and released by the kernel when this process ends however it ends, so a killed run leaves
    no stale lock. Held while a folder is made and while it runs: one run per folder. A folder
    that cannot be written (read-only) or a file system without locks is a RunError too."""
    try:
        handle = open_file(Path(folder) / LOCK_NAME, os.O_RDWR | os.O_CREAT)
    except OSError as error:
        if error.errno not in UNWRITABLE:
            raise  # a full disk: the OS error itself
        raise RunError(f"{folder}: cannot write into the run folder ({error.strerror}); a run "
                       f"needs its folder writable") from None
    try:
        _lock_exclusive(handle, folder)
        try:
            os.ftruncate(handle, 0)
            os.write(handle, f"{os.getpid()}\n".encode())  # who holds it, for a person to read
        except OSError:  # a full disk: the lock holds without the note
            pass
        yield
    finally:
        os.close(handle)  # the only descriptor: closing it releases the lock


NO_LOCKS = {errno.ENOLCK, errno.EOPNOTSUPP, errno.ENOTSUP, errno.ENOSYS}  # flock: no locks here


LOCK_TRIES = 10  # a reader's shared lock (lock_held) lasts an instant: a few tries 10 ms apart


def _lock_exclusive(handle: int, folder: Path) -> None:
    """``flock`` the open lock file exclusively (a few short tries, so that a reader asking
    :func:`lock_held` at that instant does not refuse a run); RunError in one line if another
    process holds it or the file system has no locks (some network file systems)."""
    try:
        for attempt in range(LOCK_TRIES):
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
                return
            except BlockingIOError:
                if attempt == LOCK_TRIES - 1:
                    raise
                time.sleep(0.01)
    except BlockingIOError:
        raise RunError(f"{folder}: another process is making or running this run (one run "
                       f"per folder)") from None
    except OSError as error:
        if error.errno not in NO_LOCKS:
            raise
        raise RunError(f"{folder}: the file system does not support file locks (flock: "
                       f"{error.strerror}), which keep one run per folder; put the run folder "
                       f"on a local disk (--out)") from None


def lock_held(folder: Path) -> bool | None:
    """Whether a process holds the run folder's lock (is making or running it): True or
    False, or None when the lock cannot tell (no lock file: an older folder; a file system
    without locks). Takes a shared lock on a read-only descriptor for an instant, so it writes
    nothing and works on a read-only folder; what a recorded pid cannot tell across hosts or
    after the pid is reused."""
    try:
        handle = open_file(Path(folder) / LOCK_NAME)
    except (OSError, UnsafeFile):
        return None
    try:
        fcntl.flock(handle, fcntl.LOCK_SH | fcntl.LOCK_NB)
        return False
    except BlockingIOError:
        return True
    except OSError:
        return None
    finally:
        os.close(handle)  # releases the shared lock, if taken


def folder_busy(folder: Path) -> bool:
    """Whether another process holds the run folder's lock (:func:`lock_held`; False when it
    cannot tell)."""
    return lock_held(folder) is True
