"""A run folder returned by a task: unpacked as data only, put in place of the prepared one
without losing it when the return is bad."""

import io
import json
import tarfile

import pytest

from animat.experiments.executors import pack, place, unpack
from animat.experiments.launch.config import validate
from animat.experiments.launch.lock import RunError
from animat.experiments.sweep import prepare
from tests.experiments.test_cli import TINY


def _prepared(tmp_path):
    return prepare(validate(TINY, "test"), [0], tmp_path / "runs", ["test"])[0]


def _archive(*members) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w") as archive:
        for info, data in members:
            archive.addfile(info, io.BytesIO(data) if data is not None else None)
    return buffer.getvalue()


def _file(name: str, data: bytes):
    info = tarfile.TarInfo(name)
    info.size = len(data)
    return info, data


def test_a_returned_folder_replaces_the_prepared_one_result_last(tmp_path):
    folder = _prepared(tmp_path)
    finished = tmp_path / "finished"
    finished.mkdir()
    for entry in folder.iterdir():
        (finished / entry.name).write_bytes(entry.read_bytes())
    (finished / "scalars.csv").write_text("step,tag,value\n1,eval/return,2.0\n")
    status = json.loads((finished / "result.json").read_text())
    (finished / "result.json").write_text(json.dumps({**status, "status": "done"}))
    assert place(pack(finished), folder)["status"] == "done"
    assert (folder / "scalars.csv").read_text().endswith("2.0\n")
    assert [p.name for p in folder.parent.iterdir()] == [folder.name]  # no staging left


@pytest.mark.parametrize("member", ["escape", "link", "absolute", "not a result"])
def test_a_bad_returned_archive_is_refused_and_the_prepared_folder_kept(tmp_path, member):
    folder = _prepared(tmp_path)
    before = {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()}
    done = json.dumps({"status": "done"}).encode()
    if member == "link":
        info = tarfile.TarInfo("result.json")
        info.type, info.linkname = tarfile.SYMTYPE, "/etc/passwd"
        data, error = _archive((info, None)), "could not be unpacked"
    elif member == "escape":
        data = _archive(_file("../outside.txt", b"x"), _file("result.json", done))
        error = "could not be unpacked"
    elif member == "absolute":  # the data filter takes the leading / off: inside the folder
        name = str(tmp_path / "outside.txt")
        data, error = _archive(_file(name, b"x"), _file("result.json", b"{}")), "not a run's"
    else:
        data, error = _archive(_file("result.json", b"[1, 2]")), "not a run's"
    with pytest.raises(RunError, match=error):
        place(data, folder)
    assert {p.name: p.read_bytes() for p in folder.iterdir() if p.is_file()} == before
    assert not (tmp_path / "runs" / "outside.txt").exists()
    assert not (tmp_path / "outside.txt").exists()


def test_a_returned_archive_without_a_result_leaves_the_folder_as_prepared(tmp_path):
    folder = _prepared(tmp_path)
    before = (folder / "result.json").read_bytes()
    with pytest.raises(RunError, match="no result.json"):
        place(_archive(_file("scalars.csv", b"")), folder)
    assert (folder / "result.json").read_bytes() == before
    assert not (folder / "scalars.csv").exists()
    unpack(pack(folder), tmp_path / "copy")  # and a folder packs and unpacks whole
    assert (tmp_path / "copy" / "result.json").read_bytes() == before
