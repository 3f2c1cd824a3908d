"""A run folder returned by a task: read as untrusted data (each member checked before anything
is written), put in place of the prepared one without losing it when the return is bad, and
nothing outside the folder read, written or truncated, whatever the Python's tarfile filter
lets through."""

import io
import json
import os
import tarfile

import pytest

from animat.experiments.launch import archive as archive_module
from animat.experiments.launch.archive import pack, place, unpack
from animat.experiments.launch.config import validate
from animat.experiments.launch.lock import RunError
from animat.experiments.sweep import prepare
from tests.support.cli import TINY

DONE = json.dumps({"status": "done"}).encode()


def _prepared(tmp_path):
    return prepare(validate(TINY, "test"), [0], tmp_path / "runs", ["test"])[0]


def _member(name: str, kind=tarfile.REGTYPE, link: str = "", data: bytes = b""):
    info = tarfile.TarInfo(name)
    info.type, info.linkname = kind, link
    info.mode = 0o777 if kind == tarfile.DIRTYPE else 0o644
    info.size = len(data) if kind == tarfile.REGTYPE else 0
    return info, data


def _file(name: str, data: bytes):
    return _member(name, data=data)


def _archive(*members) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as archive:
        for info, data in members:
            archive.addfile(info, io.BytesIO(data) if info.size else None)
    return buffer.getvalue()


def _path_max_chain(dest: str) -> bytes:
    """CVE-2025-4517's archive: a chain of links whose expansion passes PATH_MAX, where
    ``os.path.realpath`` (and so the ``data`` filter, before CPython 3.11.13) stops resolving,
    then a hard link through it to ``../flag`` beside ``dest``, overwritten by the next member."""
    steps = "abcdefghijklmnop"
    width = (os.pathconf("/", "PC_PATH_MAX") - len(dest) - 1) // (len(steps) + 1)
    members, path = [], ""
    for step in steps:
        members += [_member(os.path.join(path, "d" * width), tarfile.DIRTYPE),
                    _member(os.path.join(path, step), tarfile.SYMTYPE, "d" * width)]
        path = os.path.join(path, "d" * width)
    link = os.path.join(*steps, "l" * 254)
    members += [_member(link, tarfile.SYMTYPE, os.path.join(*[".."] * len(steps))),
                _member("escape", tarfile.SYMTYPE, os.path.join(link, "..")),
                _member("flaglink", tarfile.LNKTYPE, os.path.join("escape", "flag")),
                _file("flaglink", b"overwritten"), _file("result.json", DONE)]
    return _archive(*members)


def test_the_path_max_chain_escapes_the_data_filter_alone_on_an_unfixed_python(tmp_path):
    """What the archive below is: on this machine's Python (3.11.7), tarfile's data filter alone
    lets it overwrite a file outside the destination."""
    (tmp_path / "flag").write_text("original")
    dest = tmp_path / "dest"
    dest.mkdir()
    try:
        with tarfile.open(fileobj=io.BytesIO(_path_max_chain(str(dest)))) as archive:
            archive.extractall(dest, filter="data")
    except tarfile.TarError:
        pytest.skip("this Python's data filter refuses the chain (CVE-2025-4517 fixed)")
    assert (tmp_path / "flag").read_text() == "overwritten"


def test_the_path_max_chain_changes_nothing_outside_the_extraction(tmp_path, monkeypatch):
    """The chain built for the very folder it is extracted into (where, with the members'
    checks taken out, it overwrites ``flag`` beside it on an unfixed Python)."""
    staging = tmp_path / "staging"

    def mkdtemp(dir, prefix):
        staging.mkdir()
        return str(staging)

    monkeypatch.setattr(archive_module.tempfile, "mkdtemp", mkdtemp)
    (tmp_path / "flag").write_text("original")
    with pytest.raises(RunError, match="is a link; a run folder holds only"):
        unpack(_path_max_chain(str(staging)), tmp_path / "copy")
    assert (tmp_path / "flag").read_text() == "original"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["flag"]


def test_the_path_max_chain_returned_to_place_keeps_the_prepared_folder(tmp_path):
    folder = _prepared(tmp_path)
    flag, sibling = folder.parent / "flag", _prepared(tmp_path / "other")
    flag.write_text("original")
    before = {p: p.read_bytes() for p in [*folder.iterdir(), *sibling.iterdir()] if p.is_file()}
    with pytest.raises(RunError, match="is a link; a run folder holds only"):
        place(_path_max_chain(str(folder.parent / f".{folder.name}.xxxxxxxx")), folder)
    assert flag.read_text() == "original"
    assert {p: p.read_bytes() for p in before} == before
    assert sorted(p.name for p in folder.parent.iterdir()) == sorted(["flag", folder.name])


def test_a_returned_folder_replaces_the_prepared_one_result_last(tmp_path):
    folder = _prepared(tmp_path)
    finished = tmp_path / "finished"
    finished.mkdir()
    for entry in folder.iterdir():
        (finished / entry.name).write_bytes(entry.read_bytes())
    (finished / "scalars.csv").write_text("step,tag,value\n1,eval/return,2.0\n")
    (finished / "tb").mkdir()
    (finished / "tb" / "events").write_bytes(b"e")
    status = json.loads((finished / "result.json").read_text())
    (finished / "result.json").write_text(json.dumps({**status, "status": "done"}))
    assert place(pack(finished), folder)["status"] == "done"
    assert (folder / "scalars.csv").read_text().endswith("2.0\n")
    assert (folder / "tb" / "events").read_bytes() == b"e"
    assert [p.name for p in folder.parent.iterdir()] == [folder.name]  # no staging left


BAD = {  # member(s) -> what the refusal says
    "escape": ([_file("../outside.txt", b"x")], "not a relative, normalised path"),
    "absolute": ([_file("/tmp/outside.txt", b"x")], "not a relative, normalised path"),
    "dot-dot inside": ([_file("tb/../../outside.txt", b"x")], "not a relative, normalised"),
    "symlink": ([_member("result.json", tarfile.SYMTYPE, "/etc/passwd")], "is a link"),
    "lock link": ([_member(".lock", tarfile.SYMTYPE, "config.yaml")], "is a link"),
    "lock file": ([_file(".lock", b"")], "the folder's lock file"),
    "hard link": ([_member("notes", tarfile.LNKTYPE, "config.yaml")], "is a link"),
    "character device": ([_member("zero", tarfile.CHRTYPE)], "a device or FIFO"),
    "block device": ([_member("disk", tarfile.BLKTYPE)], "a device or FIFO"),
    "fifo": ([_member("result.json", tarfile.FIFOTYPE)], "a device or FIFO"),
    "sparse": ([_member("big", tarfile.GNUTYPE_SPARSE)], "of tar type"),
    "twice": ([_file("scalars.csv", b"a"), _file("scalars.csv", b"b")], "is named twice"),
    "deep": ([_file("/".join(["d"] * 40), b"x")], "nested deeper than 32"),
    "long name": ([_file("n" * 300, b"x")], "a name over 255"),
    "not a result": ([], "not a run's"),
    "a changed config": ([_file("config.yaml", b"env: {}\n")], "config.yaml differs"),
    "a file for a folder": ([_file("checkpoints", b"x")], "is a file where the prepared"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_returned_archive_is_refused_and_nothing_is_written(tmp_path, case):
    folder = _prepared(tmp_path)
    (folder / "checkpoints").mkdir()
    members, error = BAD[case]
    result = _file("result.json", b"[1, 2]" if case == "not a result" else DONE)
    before = {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}
    with pytest.raises(RunError, match=error) as refused:
        place(_archive(*members, result), folder)
    assert len(str(refused.value).splitlines()) == 1 and str(folder) in str(refused.value)
    assert {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()} == before
    assert sorted(p.name for p in folder.parent.iterdir()) == [folder.name]
    assert not (tmp_path / "outside.txt").exists() and not os.path.exists("/tmp/outside.txt")


@pytest.mark.parametrize("bound", ["MEMBER_BYTES", "ARCHIVE_BYTES", "ARCHIVE_MEMBERS"])
def test_an_archive_past_a_bound_is_refused(tmp_path, monkeypatch, bound):
    monkeypatch.setattr(archive_module, bound, 2)
    folder = _prepared(tmp_path)
    with pytest.raises(RunError, match="bytes|members"):
        place(_archive(_file("a", b"xy"), _file("b", b"z"), _file("result.json", DONE)), folder)


def test_a_compressed_archive_is_refused(tmp_path):
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz") as archive:
        info, data = _file("result.json", DONE)
        archive.addfile(info, io.BytesIO(data))
    with pytest.raises(RunError, match="could not be unpacked"):
        unpack(buffer.getvalue(), tmp_path / "copy")
    assert list(tmp_path.iterdir()) == []


def test_a_returned_archive_without_a_result_leaves_the_folder_as_prepared(tmp_path):
    folder = _prepared(tmp_path)
    before = (folder / "result.json").read_bytes()
    with pytest.raises(RunError, match="no result.json"):
        place(_archive(_file("scalars.csv", b"")), folder)
    assert (folder / "result.json").read_bytes() == before
    assert not (folder / "scalars.csv").exists()
    unpack(pack(folder), tmp_path / "copy")  # and a folder packs and unpacks whole
    assert (tmp_path / "copy" / "result.json").read_bytes() == before
    assert oct((tmp_path / "copy").stat().st_mode & 0o777) == oct(0o755)
