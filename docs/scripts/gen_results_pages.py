"""Write the results pages (``docs/results.md``, the index, and a page per experiment) from the
run folders shipped under ``results/``: each page is its template (``results_pages/<page>.md``:
a title, a one-line summary for the index and the hand-written text) with every ``@table``
line replaced by what that command prints, and the command under it.

    python docs/scripts/gen_results_pages.py            # docs/results.md and every page
    python docs/scripts/gen_results_pages.py --check    # exit 1 if a page is out of date

A ``@table`` line names one command, as a reader would type it from the checkout:
``python -m animat.experiments.figures.<table> ARGS`` (the table modules' ``main``) or
``animat compare ARGS``. The tables read each folder's ``result.json``, ``eval.json``,
``artefacts.json`` and repertoire; nothing is played again (``rescore_table``, which plays every
agent, is named on the index, not run). In the index's template, ``@page <name>.md`` is that
page's line: its title, linked, and its summary; every page has one.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import shlex
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
TEMPLATES = Path(__file__).resolve().parent / "results_pages"
INDEX = "results.md"
REGENERATE = "Regenerate: `python docs/scripts/gen_results_pages.py`"
TABLES = "animat.experiments.figures."  # the modules a @table may name after python -m


def entry_point(command: str):
    """The ``main`` a template's command runs and the arguments it passes; a ValueError for a
    command that is not a table module's or ``animat compare``."""
    words = shlex.split(command)
    if words[:2] == ["python", "-m"] and len(words) > 2 and words[2].startswith(TABLES):
        return importlib.import_module(words[2]).main, words[3:]
    if words[:2] == ["animat", "compare"]:
        from animat.experiments.cli import main

        return main, words[1:]
    raise ValueError(f"not a table command: {command!r} (python -m {TABLES}<table> ... or "
                     "animat compare ...)")


def table(command: str) -> str:
    """What ``command`` prints, run from the checkout's root (its paths are relative to it); a
    RuntimeError naming the command if it fails."""
    main, args = entry_point(command)
    printed = io.StringIO()
    with contextlib.chdir(ROOT), contextlib.redirect_stdout(printed):
        code = main(args)
    if code not in (None, 0):
        raise RuntimeError(f"{command!r} exited {code}")
    return printed.getvalue().strip()


def split(template: str) -> tuple[str, str, list[str]]:
    """A template's title (its first line, ``# ...``), its summary (the second, ``summary:
    ...``) and the rest of its lines."""
    lines = template.splitlines()
    if len(lines) < 2 or not lines[0].startswith("# ") or not lines[1].startswith("summary: "):
        raise ValueError("a template starts with '# Title' then 'summary: one line'")
    return lines[0][2:], lines[1].removeprefix("summary: "), lines[2:]


def index_line(name: str, templates: dict[str, str]) -> str:
    """The index's line for the page ``name``: its title, linked, and its summary."""
    if name not in templates or name == INDEX:
        raise ValueError(f"@page {name}: no such page among the templates in {TEMPLATES}")
    title, summary, _ = split(templates[name])
    return f"- [{title}]({name}): {summary}"


def render(name: str, templates: dict[str, str]) -> str:
    """The page ``name``: its title, the line that says how to regenerate it, then its text
    with each ``@table`` replaced by the command's output and the command, and each ``@page``
    by that page's line of the index."""
    title, _, lines = split(templates[name])
    out = [f"# {title}", "", REGENERATE]
    for line in lines:
        if line.startswith("@table "):
            command = line.removeprefix("@table ").strip()
            out += [table(command), "", f"Printed by `{command}`"]
        elif line.startswith("@page "):
            out.append(index_line(line.removeprefix("@page ").strip(), templates))
        else:
            out.append(line)
    return "\n".join(out).rstrip() + "\n"


def pages() -> dict[str, str]:
    """Every results page's name (``docs/<name>``) and text, the index first."""
    templates = {path.name: path.read_text() for path in sorted(TEMPLATES.glob("*.md"))}
    if INDEX not in templates:
        raise FileNotFoundError(f"no {INDEX} among the templates in {TEMPLATES}")
    listed = {line.removeprefix("@page ").strip() for line in templates[INDEX].splitlines()
              if line.startswith("@page ")}
    unlisted = sorted(set(templates) - listed - {INDEX})
    if unlisted:
        raise ValueError(f"the index ({INDEX}) has no @page line for {', '.join(unlisted)}")
    order = [INDEX, *(name for name in templates if name != INDEX)]
    return {name: render(name, templates) for name in order}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if a page's text differs from what it would be")
    args = parser.parse_args(argv)
    stale = []
    for name, text in pages().items():
        path = DOCS / name
        if args.check:
            if not path.is_file() or path.read_text() != text:
                stale.append(name)
            continue
        path.write_text(text)
    if stale:
        print(f"out of date: {', '.join(stale)} (run python docs/scripts/gen_results_pages.py)")
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main())
