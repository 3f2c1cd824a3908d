"""A run folder beside a file outside it, which nothing may change."""

import pytest


@pytest.fixture
def folder(tmp_path):
    """A run folder (``run/``, holding a result.json) beside ``outside/notes.txt``."""
    (tmp_path / "outside").mkdir()
    (tmp_path / "outside" / "notes.txt").write_text("my notes\n")
    (tmp_path / "run").mkdir()
    (tmp_path / "run" / "result.json").write_text('{"status": "done"}')
    return tmp_path / "run"


@pytest.fixture
def outside(folder):
    """The file outside the run folder."""
    return folder.parent / "outside" / "notes.txt"
