"""The README's examples run as written: every ``python`` block, in a fresh interpreter, from a
directory outside the checkout (the second block loads ``runs/try``, made first by a small
run); and its Quick start is the two one-line commands that ``.ci/run`` runs."""

import re
import subprocess
import sys
from pathlib import Path

import yaml

from tests.support.cli import TINY, animat

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def blocks(language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```", README, flags=re.S | re.M)


def quick_start() -> list[str]:
    """The Quick start's command lines (the first block under its heading)."""
    section = README.split("## Quick start", 1)[1]
    return re.search(r"```bash\n(.*?)```", section, flags=re.S).group(1).strip().splitlines()


def test_the_quick_start_is_clone_cd_then_two_commands_ci_runs():
    lines = quick_start()
    assert len(lines) == 3 and lines[0].startswith("git clone") and "&& cd " in lines[0]
    torch = 'pip install "torch==2.13.*" && '  # the CPU build first, then only what it needs
    assert lines[1].endswith(torch + "pip install -e . && animat run quickstart")
    assert torch + 'pip install -e ".[test,bench,ray]"' in lines[2]
    assert lines[1].endswith("animat run quickstart") and lines[2].endswith("python -m pytest -q")
    ci = (ROOT / ".ci" / "run").read_text()  # it reads the lines out of the README, as written
    assert "## Quick start" in ci and "README.md" in ci
    installs = [line.strip() for line in ci.splitlines() if "pip install" in line]
    assert all(line in README for line in installs)  # only what the README says to install


def test_every_python_example_runs_from_outside_the_checkout(tmp_path):
    config = tmp_path / "tiny.yaml"
    config.write_text(yaml.safe_dump(TINY))
    animat("run", config, "--out", tmp_path / "runs" / "try", "--quiet", cwd=tmp_path)
    examples = blocks("python")
    assert len(examples) >= 2
    for code in examples:
        done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                              text=True, timeout=600)
        assert done.returncode == 0, f"{code}\n{done.stderr[-2000:]}"


def test_the_readme_is_a_front_door_and_every_link_in_it_and_the_docs_resolves():
    """At most 150 lines (what it is, the Quick start, an example, what is inside, results,
    the docs, how to cite); every relative link of the README, the changelog and the docs'
    pages names a file that exists."""
    assert len(README.splitlines()) <= 150
    pages = [ROOT / "README.md", ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md"))]
    broken = [(page.name, link) for page in pages
              for link in re.findall(r"\]\(([^)\s]+)\)", page.read_text())
              if not link.startswith(("http", "#", "mailto"))
              and not (page.parent / link.split("#")[0]).exists()]
    assert broken == []
    for name in ("LICENSE", "CITATION.cff"):
        assert (ROOT / name).is_file()
