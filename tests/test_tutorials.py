"""Every tutorial runs as written: each page of ``docs/tutorials/`` is played block by block, in
order, in a fresh interpreter whose working directory stands for the root of a clone (``configs``
and ``results`` are links to the checkout's, read only; ``runs/`` is made there). ``python``
blocks share one namespace (``__main__``'s), as in a notebook; each ``bash`` block runs with
``bash -e``, with the interpreter's ``bin/`` first on ``PATH`` (so ``animat`` is this one). A
page whose first line is ``<!-- slow -->`` runs only under ``pytest -m slow``."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = sorted((ROOT / "docs" / "tutorials").glob("*.md"))
BLOCK = re.compile(r"^```(python|bash)\n(.*?)^```", flags=re.S | re.M)

# The driver the page's blocks run in: python blocks exec'd in one namespace, bash blocks run.
DRIVER = """
import json as _json, subprocess as _subprocess, sys as _sys
for _number, (_language, _code) in enumerate(_json.load(_sys.stdin), 1):
    print(f"--- block {_number} ({_language})", flush=True)
    if _language == "python":  # in __main__, as a script or a notebook runs it (pickling works)
        exec(compile(_code, f"<block {_number}>", "exec"), _sys.modules["__main__"].__dict__)
    else:
        _subprocess.run(["bash", "-e", "-c", _code], check=True)
"""


def blocks(page: Path) -> list[tuple[str, str]]:
    """The page's ``python`` and ``bash`` blocks, in order, as (language, code)."""
    return BLOCK.findall(page.read_text())


def is_slow(page: Path) -> bool:
    return page.read_text().startswith("<!-- slow -->")


def params() -> list:
    return [pytest.param(page, id=page.stem, marks=[pytest.mark.slow] if is_slow(page) else [])
            for page in PAGES]


def test_there_are_tutorials_and_each_has_code():
    assert PAGES, "docs/tutorials/ holds no page"
    for page in PAGES:
        assert blocks(page), f"{page.name} has no python or bash block"
        assert f"tutorials/{page.name}" in (ROOT / "mkdocs.yml").read_text(), page.name


@pytest.mark.parametrize("page", params())
def test_the_tutorial_runs_as_written(page: Path, tmp_path: Path):
    for shared in ("configs", "results"):
        (tmp_path / shared).symlink_to(ROOT / shared, target_is_directory=True)
    env = dict(os.environ, PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
               MPLBACKEND="Agg")
    env.pop("PYTHONPATH", None)  # the installed package, as a reader has it
    run = subprocess.run([sys.executable, "-c", DRIVER], input=json.dumps(blocks(page)),
                         cwd=tmp_path, env=env, capture_output=True, text=True, timeout=1800)
    assert run.returncode == 0, f"{page.name}\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}"
