"""Run-folder files opened, read and written one way, as untrusted input.

A run folder may come from someone else (``animat eval``, ``--resume``, a sweep's returned
archive), so every file of it is opened here: no link is followed anywhere in its path (each
folder is opened below the last with ``O_NOFOLLOW``), nothing but a regular file is opened (a
FIFO, a device or a folder is refused without blocking), a file opened for writing in place has
no other hard link, and a read stops at a bound per kind of file (:data:`LIMITS`). A refusal is
an :class:`UnsafeFile` naming the file in one line. Paths are taken as they are: callers resolve
the run folder's own path once (:func:`.tree.run_folder`), so a link found below it was planted.

:func:`atomic_write` writes through the same folder descriptors (a reader or a crash never sees
half a file, a failure leaves no temporary file); :func:`read_json` and :class:`CorruptFile` (a
file that cannot be read back, named in one line) read. :mod:`.tree` asks a whole folder.
"""

from __future__ import annotations

import json
import os
import secrets
import stat
import zipfile
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any, NoReturn

MiB = 1 << 20
# The most bytes a file of each kind is read up to: far above what a run writes, far below what
# a machine's memory holds.
LIMITS = {"json": 64 * MiB, "config": 1 * MiB, "text": 16 * MiB, "scalars": 512 * MiB,
          "events": 1024 * MiB, "weights": 1024 * MiB, "arrays": 256 * MiB,
          "pickle": 1024 * MiB}


class CorruptFile(ValueError):
    """A file of a run folder that cannot be read back (truncated, empty, not what it should
    be): its path and what is wrong, in one line."""

    def __init__(self, path: str | Path, problem: str) -> None:
        super().__init__(f"{path}: {problem} (the file is truncated or corrupt)")


class UnsafeFile(ValueError):
    """A run-folder path this code will not open: a link, not a regular file, another file's
    hard link, or larger than its kind's bound; its path and why, in one line."""

    def __init__(self, path: str | Path, problem: str) -> None:
        self.path = str(path)
        super().__init__(f"{path}: {problem}")


KINDS = {stat.S_IFIFO: "a FIFO", stat.S_IFCHR: "a character device", stat.S_IFBLK:
         "a block device", stat.S_IFSOCK: "a socket", stat.S_IFDIR: "a folder",
         stat.S_IFLNK: "a symbolic link"}


def describe(mode: int) -> str:
    """What a file of ``mode`` (``st_mode``) is, in words: a FIFO, a symbolic link, ..."""
    return KINDS.get(stat.S_IFMT(mode), "not a regular file")


def _refuse_link(name: str, parent: int, path: str, error: OSError) -> NoReturn:
    """UnsafeFile if ``name`` in the folder ``parent`` is a link (what made ``error``); else
    ``error`` again, naming ``path``."""
    try:
        link = stat.S_ISLNK(os.stat(name, dir_fd=parent, follow_symlinks=False).st_mode)
    except OSError:
        link = False
    if link:
        raise UnsafeFile(path, "is a symbolic link; a run folder's files are never followed "
                               "out of it") from None
    raise OSError(error.errno, error.strerror, path) from None


# A folder on the way is opened to be walked through, not read: O_PATH (Linux) needs only the
# permission to pass through it, as a plain path lookup does.
WALK = getattr(os, "O_PATH", os.O_RDONLY) | os.O_DIRECTORY | os.O_CLOEXEC


def open_dir(path: str | Path, create: bool = False) -> int:
    """A descriptor of the folder ``path`` (to open files below it, ``dir_fd``), opened
    component by component from the root with no link followed (UnsafeFile naming the first
    link met); ``create``: the missing folders made on the way. The caller closes it."""
    parts = Path(os.path.abspath(path)).parts
    handle = os.open("/", WALK)
    try:
        for depth, name in enumerate(parts[1:], start=2):
            here = str(Path(*parts[:depth]))
            try:
                if create:
                    try:
                        os.mkdir(name, 0o755, dir_fd=handle)
                    except FileExistsError:
                        pass
                child = os.open(name, WALK | os.O_NOFOLLOW, dir_fd=handle)
            except OSError as error:
                _refuse_link(name, handle, here, error)
            os.close(handle)
            handle = child
    except BaseException:
        os.close(handle)
        raise
    return handle


@contextmanager
def folder_of(path: str | Path, create: bool = False):
    """``(descriptor of path's folder, path's name)`` for the ``with`` block (:func:`open_dir`)."""
    handle = open_dir(Path(path).parent, create)
    try:
        yield handle, Path(path).name
    finally:
        os.close(handle)


def open_file(path: str | Path, flags: int = os.O_RDONLY, mode: int = 0o644) -> int:
    """A descriptor of the regular file ``path`` opened with ``flags`` (``os.O_*``), no link
    followed and nothing else opened, without blocking on a FIFO; opened for writing, it may
    have no other hard link (a write in place would change that other file). UnsafeFile naming
    it otherwise. The caller closes it."""
    with folder_of(path) as (parent, name):
        try:
            handle = os.open(name, flags | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, mode,
                             dir_fd=parent)
        except OSError as error:
            _refuse_link(name, parent, str(path), error)
    try:
        info = os.fstat(handle)
        if not stat.S_ISREG(info.st_mode):
            raise UnsafeFile(path, f"is {describe(info.st_mode)}, not a regular file")
        if flags & (os.O_WRONLY | os.O_RDWR) and info.st_nlink > 1:
            raise UnsafeFile(path, f"has {info.st_nlink - 1} other hard link(s); a run folder's "
                                   "file is never written through to another")
        os.set_blocking(handle, True)
    except BaseException:
        os.close(handle)
        raise
    return handle


def check_size(handle: int, path: str | Path, kind: str) -> int:
    """The open file's size, UnsafeFile if it is over :data:`LIMITS` for ``kind``."""
    size, limit = os.fstat(handle).st_size, LIMITS[kind]
    if size > limit:
        raise UnsafeFile(path, f"holds {size:,} bytes, more than a {kind} file may "
                               f"({limit:,}); not read")
    return size


def open_read(path: str | Path, kind: str) -> IO[bytes]:
    """The regular file ``path`` open for reading in binary (:func:`open_file`), UnsafeFile if
    it is larger than a ``kind`` file may be: for readers that take a file (numpy, torch)."""
    handle = open_file(path)
    try:
        check_size(handle, path, kind)
    except BaseException:
        os.close(handle)
        raise
    return os.fdopen(handle, "rb")


def open_stored_zip(path: str | Path, kind: str) -> IO[bytes]:
    """:func:`open_read`, for a zip archive whose members are stored, not compressed: what
    ``np.savez`` and ``torch.save`` write, and what unpacks to no more than the file's own
    bounded size (a compressed member could unpack to any size: UnsafeFile; not a zip:
    ``BadZipFile``)."""
    file = open_read(path, kind)
    try:
        with zipfile.ZipFile(file) as archive:
            members = archive.infolist()
        packed = [m.filename for m in members if m.compress_type != zipfile.ZIP_STORED]
        if packed:
            raise UnsafeFile(path, f"holds a compressed member ({packed[0][:80]!r}); a run "
                                   "writes its arrays and weights stored, not compressed")
        file.seek(0)
    except BaseException:
        file.close()
        raise
    return file


def read_bytes(path: str | Path, kind: str) -> bytes:
    """The bytes of the regular file ``path``, at most :data:`LIMITS` of ``kind`` (UnsafeFile
    for more, or a link, or not a regular file; FileNotFoundError when it is missing)."""
    with open_read(path, kind) as file:
        data = file.read(LIMITS[kind] + 1)
    if len(data) > LIMITS[kind]:  # it grew while read
        raise UnsafeFile(path, f"holds more than a {kind} file may ({LIMITS[kind]:,} bytes)")
    return data


def read_text(path: str | Path, kind: str = "text", follow_links: bool = False) -> str:
    """:func:`read_bytes` as UTF-8 text (CorruptFile naming the file if it is not);
    ``follow_links``: a file the user named, whose links are resolved first (still a regular
    file within the bound)."""
    if follow_links:
        path = os.path.realpath(path)
    try:
        return read_bytes(path, kind).decode()
    except UnicodeDecodeError:
        raise CorruptFile(path, "not UTF-8 text") from None


def read_json(path: str | Path, kind: str = "json") -> dict:
    """A JSON object from ``path`` (:func:`read_bytes`); CorruptFile naming it when it is not one
    (FileNotFoundError when it is missing)."""
    raw = read_bytes(path, kind)
    try:
        data = json.loads(raw.decode())
    except UnicodeDecodeError:
        raise CorruptFile(path, "not JSON text (not UTF-8)") from None
    except json.JSONDecodeError as error:
        raise CorruptFile(path, f"not valid JSON ({error.msg} at line {error.lineno})") from None
    except RecursionError:
        raise CorruptFile(path, "not JSON text (nested too deep)") from None
    except ValueError as error:  # an integer of more digits than Python converts
        raise CorruptFile(path, f"not a run's JSON ({' '.join(str(error).split())[:120]})"
                          ) from None
    if not isinstance(data, dict):
        raise CorruptFile(path, f"holds a JSON {type(data).__name__}, not an object")
    return data


def is_regular(path: str | Path) -> bool:
    """Whether ``path`` is a regular file, its own name no link (what a run folder's optional
    files are asked before they are read: a link there is then refused by the read)."""
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def make_dirs(path: str | Path) -> Path:
    """Make the folder ``path`` and its parents as needed, following no link (UnsafeFile for
    one on the way); returns ``path``."""
    os.close(open_dir(path, create=True))
    return Path(path)


TMP_SUFFIX = ".tmp"  # atomic_write's temporary files: <name><random>.tmp beside the file


def atomic_write(path: str | Path, write: Callable[[Any], object], binary: bool = False,
                 replace: bool = True) -> None:
    """Write a file atomically: ``write(file)`` fills a temporary file beside ``path``, which
    then replaces it (a link there is replaced, never followed), so a reader (or a crash) never
    sees half a file, and a failure (a full disk) leaves no temporary file behind. The folders
    on the way are made as needed, none through a link (UnsafeFile). With ``replace`` False an
    existing ``path`` is left as it is (FileExistsError), even one made meanwhile. An OS error
    that names no file (a write on a full disk) is raised naming ``path``."""
    path = Path(path)
    try:
        parent = open_dir(path.parent, create=True)
    except OSError as error:
        raise _naming(error, path, always=True) from None
    tmp = f"{path.name[:200]}{secrets.token_hex(4)}{TMP_SUFFIX}"
    try:
        handle = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW
                         | os.O_CLOEXEC, 0o644, dir_fd=parent)
        try:
            with os.fdopen(handle, "wb" if binary else "w") as file:
                write(file)
                file.flush()
                os.fchmod(file.fileno(), 0o644)  # as a plain file, whatever the umask
                os.fsync(file.fileno())
            if replace:
                os.replace(tmp, path.name, src_dir_fd=parent, dst_dir_fd=parent)
            else:
                _place_new(tmp, path.name, parent)
        finally:
            try:
                os.unlink(tmp, dir_fd=parent)
            except FileNotFoundError:
                pass
    except OSError as error:
        raise _naming(error, path, always=error.filename in (None, tmp)) from None
    finally:
        os.close(parent)


def _naming(error: OSError, path: Path, always: bool = False) -> OSError:
    """``error``, or the same error (its subclass, by errno) naming ``path`` where it named no
    file (or ``always``): what a one-line report of it needs."""
    if error.errno is None or (error.filename is not None and not always):
        return error
    return OSError(error.errno, error.strerror, str(path))


def _place_new(tmp: str, name: str, parent: int) -> None:
    """Give the complete file ``tmp`` the name ``name`` in the folder ``parent`` only if no
    file has it (FileExistsError otherwise): a hard link where the file system has them, else
    claim the name, then fill it."""
    try:
        os.link(tmp, name, src_dir_fd=parent, dst_dir_fd=parent, follow_symlinks=False)
    except FileExistsError:
        raise
    except OSError:
        os.close(os.open(name, os.O_CREAT | os.O_EXCL | os.O_WRONLY | os.O_NOFOLLOW, 0o644,
                         dir_fd=parent))
        os.replace(tmp, name, src_dir_fd=parent, dst_dir_fd=parent)
