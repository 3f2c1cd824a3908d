"""One way to open a run folder's files: no link followed anywhere in the path, nothing but a
regular file opened (a FIFO without blocking), no write through a hard link, reads bounded
per kind; atomic writes that replace a link rather than follow it."""

import os
import threading

import pytest

from animat.learners.storage import files
from animat.learners.storage.files import (
    CorruptFile,
    UnsafeFile,
    atomic_write,
    make_dirs,
    open_file,
    read_bytes,
    read_json,
    read_text,
)


def test_a_regular_file_reads_and_writes_as_before(folder):
    assert read_json(folder / "result.json") == {"status": "done"}
    atomic_write(folder / "a" / "b.json", lambda file: file.write("{}"))
    assert read_text(folder / "a" / "b.json") == "{}"
    assert oct((folder / "a" / "b.json").stat().st_mode & 0o777) == oct(0o644)
    with pytest.raises(FileNotFoundError):
        read_bytes(folder / "missing.json", "json")


@pytest.mark.parametrize("reader", [lambda p: read_json(p), lambda p: read_text(p),
                                    lambda p: os.close(open_file(p, os.O_RDWR))])
def test_a_link_is_refused_at_the_file_and_on_the_way(folder, outside, reader):
    (folder / "linked.json").symlink_to(outside)
    (folder / "tb").symlink_to(folder.parent / "outside")
    with pytest.raises(UnsafeFile, match="linked.json: is a symbolic link"):
        reader(folder / "linked.json")
    with pytest.raises(UnsafeFile, match="tb: is a symbolic link"):
        reader(folder / "tb" / "notes.txt")
    assert outside.read_text() == "my notes\n"


def test_a_fifo_and_a_device_are_refused_without_blocking(folder):
    os.mkfifo(folder / "fifo")
    result = {}
    reader = threading.Thread(target=lambda: result.update(error=_error(folder / "fifo")))
    reader.start()
    reader.join(timeout=10)
    assert not reader.is_alive() and "is a FIFO, not a regular file" in result["error"]
    assert "is a character device" in _error("/dev/zero")
    assert "is a folder" in _error(folder)


def _error(path) -> str:
    try:
        read_bytes(path, "json")
    except UnsafeFile as error:
        return str(error)
    return ""


def test_a_file_with_another_hard_link_is_never_written_in_place(folder, outside):
    os.link(outside, folder / ".lock")
    with pytest.raises(UnsafeFile, match="other hard link"):
        open_file(folder / ".lock", os.O_RDWR | os.O_CREAT)
    os.close(open_file(folder / ".lock"))  # read, it is a plain file
    assert outside.read_text() == "my notes\n"


def test_a_read_stops_at_its_kind_s_bound(folder, monkeypatch):
    monkeypatch.setitem(files.LIMITS, "json", 8)
    with pytest.raises(UnsafeFile, match=r"result.json: holds 18 bytes, more than a json file "
                                         r"may \(8\)"):
        read_json(folder / "result.json")


def test_atomic_write_replaces_a_link_and_makes_no_folder_through_one(folder, outside):
    (folder / "config.yaml").symlink_to(outside)
    atomic_write(folder / "config.yaml", lambda file: file.write("mine"))
    assert not (folder / "config.yaml").is_symlink()
    assert (folder / "config.yaml").read_text() == "mine"
    (folder / "checkpoints").symlink_to(folder.parent / "outside")
    with pytest.raises(UnsafeFile, match="checkpoints: is a symbolic link"):
        atomic_write(folder / "checkpoints" / "x.json", lambda file: file.write("x"))
    with pytest.raises(UnsafeFile, match="checkpoints: is a symbolic link"):
        make_dirs(folder / "checkpoints" / "ppo")
    assert sorted(os.listdir(folder.parent / "outside")) == ["notes.txt"]
    assert outside.read_text() == "my notes\n"


def test_a_non_utf8_file_is_corrupt_and_named(folder):
    (folder / "result.json").write_bytes(b"\xff\xfe{}")
    with pytest.raises(CorruptFile, match="result.json: not JSON text"):
        read_json(folder / "result.json")


def test_weights_and_arrays_are_read_only_from_stored_zips(folder):
    import zipfile

    with zipfile.ZipFile(folder / "policy.pt", "w", zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("bomb.npy", b"\0" * (1 << 20))  # a MiB in a kilobyte
    with pytest.raises(UnsafeFile, match=r"holds a compressed member \('bomb.npy'\)"):
        files.open_stored_zip(folder / "policy.pt", "weights")
    with zipfile.ZipFile(folder / "stats.npz", "w", zipfile.ZIP_STORED) as archive:
        archive.writestr("mean.npy", b"\0" * 64)
    files.open_stored_zip(folder / "stats.npz", "arrays").close()


def test_json_with_a_huge_integer_is_named(folder):
    (folder / "result.json").write_text('{"status": ' + "9" * 5000 + "}")
    with pytest.raises(CorruptFile, match="result.json: not a run's JSON"):
        read_json(folder / "result.json")
