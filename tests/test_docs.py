"""The documentation site: every registered env has a page generated from its docstrings and
registration, and the pages are current; the site builds with warnings as errors (where the
``docs`` extra is installed: ``.ci/run`` installs it and builds the site too)."""

import re
import subprocess
import sys
from pathlib import Path

import gymnasium as gym
import pytest

import animat  # noqa: F401  (registers Animat/*)

ROOT = Path(__file__).resolve().parents[1]


def test_every_registered_env_has_a_current_page_with_a_picture():
    ids = sorted(k for k in gym.registry if k.startswith("Animat/"))
    for env_id in ids:
        name = env_id.split("/", 1)[1]
        assert (ROOT / "docs" / "envs" / f"{name}.md").is_file(), env_id
        assert (ROOT / "docs" / "envs" / f"{name}.png").stat().st_size > 1000, env_id
        assert f"envs/{name}.md" in (ROOT / "mkdocs.yml").read_text(), env_id
    check = subprocess.run([sys.executable, str(ROOT / "docs" / "scripts" / "gen_env_pages.py"),
                            "--check"], capture_output=True, text=True, timeout=600)
    assert check.returncode == 0, check.stdout + check.stderr


def test_the_site_builds_with_warnings_as_errors(tmp_path):
    pytest.importorskip("mkdocs", reason="the docs extra is not installed")
    build = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
                            str(tmp_path / "site")], cwd=ROOT, capture_output=True, text=True,
                           timeout=600)
    assert build.returncode == 0, build.stderr[-3000:]
    assert (tmp_path / "site" / "envs" / "FishSwim-v0" / "index.html").is_file()
    assert (tmp_path / "site" / "api" / "physics" / "index.html").stat().st_size > 20_000


def test_the_results_pages_are_current_and_the_readme_quotes_them():
    """Every results page is what ``docs/scripts/gen_results_pages.py`` makes of the shipped
    ``results/`` (its tables read the folders' files and play nothing: seconds), each is in the
    site's nav, and every figure of the README's Results section is on a page its line links."""
    script = ROOT / "docs" / "scripts" / "gen_results_pages.py"
    check = subprocess.run([sys.executable, str(script), "--check"], capture_output=True,
                           text=True, timeout=300)
    assert check.returncode == 0, check.stdout + check.stderr
    nav = (ROOT / "mkdocs.yml").read_text()
    for template in (script.parent / "results_pages").glob("*.md"):
        assert f"- {template.name}" in nav, template.name
    section = (ROOT / "README.md").read_text().split("\n## Results\n", 1)[1].split("\n## ", 1)[0]
    for item in section.split("\n- ")[1:]:
        linked = re.findall(r"\]\((docs/[^)#]+\.md)\)", item)
        assert linked, item
        pages = " ".join((ROOT / link).read_text() for link in linked)
        for figure in re.findall(r"\d+\.\d+(?: ± \d+\.\d+)?", item):
            assert figure in pages, (figure, item)
