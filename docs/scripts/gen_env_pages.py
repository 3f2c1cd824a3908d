"""Write one documentation page per registered ``Animat/...`` env, from its docstrings, its
registration and the env as built, with a picture of its first frames (as Gymnasium's
``docs/_scripts/gen_mds.py`` does for its envs).

    python docs/scripts/gen_env_pages.py            # docs/envs/*.md and their pictures
    python docs/scripts/gen_env_pages.py --check    # exit 1 if a page's text is out of date

The docstrings are reST; a page is Markdown, so :func:`markdown` converts them: roles
(``:class:`~animat.x.Y```) become links into the API reference (``[`Y`][animat.x.Y]``,
mkdocstrings' cross-references) where it documents the target, inline code otherwise (an
unresolved cross-reference fails ``mkdocs build --strict``); double-backtick literals single
ones; ``text <url>`_`` links Markdown links; section titles headings; simple and grid tables
Markdown tables; ``::`` literal blocks fenced code.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import inspect
import re
import sys
import textwrap
from functools import cache
from pathlib import Path

import cv2
import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)
from animat.envs.registration import ENVS, timing
from animat.envs.tasks import make_task

PAGES = Path(__file__).resolve().parents[1] / "envs"
API = PAGES.parent / "api"  # its pages name the documented modules as "::: animat.x.y"
SKIP_KWARGS = {"task", "body"}
INLINE = re.compile(r":(?:py:)?(?P<role>[a-z]+):`(?P<target>[^`]+)`"  # :role:`target`
                    r"|``(?P<literal>.+?)``"  # ``literal``
                    r"|`(?P<text>[^`<]+?)\s*<(?P<url>[^>`]+)>`__?")  # `text <url>`_
UNDERLINE = re.compile(r"([=\-~^\"'`#*+])\1{2,}")  # a section title's underline
SIMPLE_BORDER = re.compile(r"=+( +=+)+")  # a simple table's border, two columns or more
GRID_BORDER = re.compile(r"\+([-=]+\+)+")  # a grid table's border


def slug(env_id: str) -> str:
    """``Animat/FishSwim-v0`` -> ``FishSwim-v0``."""
    return env_id.split("/", 1)[1]


def described(env_id: str) -> str:
    """The env's own description: its task's docstring for the body envs, the env class's
    docstring otherwise (the first paragraphs, up to its argument lists)."""
    entry = ENVS[env_id]
    kwargs = dict(entry.get("kwargs", {}))
    if "task" in kwargs:
        task_kwargs = {k: v for k, v in kwargs.items() if k in {"part"}}
        source = type(make_task(kwargs["task"], **task_kwargs))
    else:
        module, name = entry["entry_point"].split(":")
        source = getattr(__import__(module, fromlist=[name]), name)
    return markdown(inspect.cleandoc(source.__doc__ or "").strip(), source)


@cache
def documented_modules() -> frozenset[str]:
    """The modules the API reference renders (``::: module`` lines of ``docs/api/*.md``)."""
    return frozenset(m for page in API.glob("*.md")
                     for m in re.findall(r"^::: *(\S+)", page.read_text(), re.MULTILINE))


def resolve(path: str, source: object) -> object | None:
    """The object ``path`` names, read as Sphinx reads it in ``source``'s docstring: a full
    dotted path, or a name in ``source`` (a class) or its module; None if none."""
    parts = path.split(".")
    if parts[0] == "animat":
        for cut in range(len(parts), 0, -1):
            try:
                obj: object = importlib.import_module(".".join(parts[:cut]))
            except ImportError:
                continue
            parts = parts[cut:]
            break
        else:
            return None
    else:
        scope = vars(sys.modules[source.__module__])
        owner = vars(source) if inspect.isclass(source) else {}
        if parts[0] not in owner and parts[0] not in scope:
            return None
        obj, parts = owner.get(parts[0], scope.get(parts[0])), parts[1:]
    for part in parts:
        if not hasattr(obj, part):
            return None
        obj = getattr(obj, part)
    return obj


def reference(obj: object) -> str | None:
    """The API reference's identifier of ``obj`` when it renders it (a documented module,
    or a public class, function or method with its own docstring in one, every enclosing
    class too), None otherwise."""
    if inspect.ismodule(obj):
        return obj.__name__ if obj.__name__ in documented_modules() else None
    if not (inspect.isclass(obj) or inspect.isroutine(obj)):
        return None  # data: whether it is rendered depends on a docstring it cannot show
    module, qualname = getattr(obj, "__module__", None), getattr(obj, "__qualname__", "")
    if module not in documented_modules() or "<" in qualname:
        return None
    holder: object = sys.modules[module]
    for part in qualname.split("."):
        holder = vars(holder).get(part) if hasattr(holder, "__dict__") else None
        if holder is None or part.startswith("_") or not has_docstring(holder):
            return None
    return f"{module}.{qualname}"


def has_docstring(obj: object) -> bool:
    """Whether ``obj``'s source has a docstring (mkdocstrings reads the source, and a
    dataclass's generated ``__doc__`` is not one)."""
    try:
        tree = ast.parse(textwrap.dedent(inspect.getsource(obj)))  # type: ignore[arg-type]
    except (OSError, TypeError, SyntaxError):
        return False
    node = tree.body[0]
    return isinstance(node, ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and bool(
        ast.get_docstring(node))


def role(target: str, source: object) -> str:
    """A reST role's target (``~a.b.C``, ``.C``, ``title <a.b.C>``) as Markdown."""
    explicit = re.fullmatch(r"(?P<title>.+?)\s*<(?P<path>[^>]+)>", target)
    path = (explicit["path"] if explicit else target).strip().lstrip(".")
    short = path.startswith("~")
    path = path.lstrip("~").removesuffix("()")
    shown = explicit["title"] if explicit else (path.rsplit(".", 1)[-1] if short else path)
    identifier = reference(resolve(path, source))
    return f"[`{shown}`][{identifier}]" if identifier else f"`{shown}`"


def inline(line: str, source: object) -> str:
    """One line's reST inline markup as Markdown."""
    def one(match: re.Match) -> str:
        if match["target"] is not None:
            return role(match["target"], source)
        if match["literal"] is not None:
            text = match["literal"]
            return f"`` {text} ``" if "`" in text else f"`{text}`"
        return f"[{match['text']}]({match['url']})"
    return INLINE.sub(one, line)


def markdown(text: str, source: object) -> str:
    """A reST docstring as Markdown (the module's docstring lists what is converted);
    headings start at level 3, under the page's "Description"."""
    lines, out, levels, k = text.splitlines(), [], {}, 0
    while k < len(lines):
        line, after = lines[k], lines[k + 1] if k + 1 < len(lines) else ""
        if SIMPLE_BORDER.fullmatch(line.strip()) or GRID_BORDER.fullmatch(line.strip()):
            k = table(lines, k, out, source)
        elif (line.strip() and UNDERLINE.fullmatch(after.strip())
              and len(after.strip()) >= len(line.strip())):
            level = levels.setdefault(after.strip()[0], min(3 + len(levels), 6))
            out.append("#" * level + " " + inline(line.strip(), source))
            k += 2
        elif line.rstrip().endswith("::"):
            k = literal_block(lines, k, out, source)
        else:
            out.append(inline(line, source))
            k += 1
    return "\n".join(out)


def literal_block(lines: list[str], k: int, out: list[str], source: object) -> int:
    """``text::`` then an indented block at ``lines[k]``: "text:" and fenced code; returns
    the index after it."""
    head = lines[k].rstrip()[:-2].rstrip()
    if head:
        out.append(inline(head + ":", source))
    indent = len(lines[k]) - len(lines[k].lstrip())
    end = k + 1
    while end < len(lines) and (not lines[end].strip()
                                or len(lines[end]) - len(lines[end].lstrip()) > indent):
        end += 1
    while end > k + 1 and not lines[end - 1].strip():
        end -= 1
    out.extend(["", "```", *inspect.cleandoc("\n".join(lines[k + 1:end])).splitlines(), "```"])
    return end


def table(lines: list[str], k: int, out: list[str], source: object) -> int:
    """A simple or grid table whose top border is ``lines[k]`` as a Markdown table; returns
    the index after it. A border of ``=`` inside the table ends its header rows."""
    border, grid = lines[k], lines[k].strip().startswith("+")
    edges = [m.start() for m in re.finditer(r"\+" if grid else r"=+", border)]
    rows: list[list[str]] = []
    header, joining, end = 0, False, k + 1
    while end < len(lines) and lines[end].strip():
        line = lines[end]
        if GRID_BORDER.fullmatch(line.strip()) or SIMPLE_BORDER.fullmatch(line.strip()):
            inside = end + 1 < len(lines) and bool(lines[end + 1].strip())  # not the bottom
            header = header or (len(rows) if "=" in line and inside else 0)
            joining = False
        else:
            cells = _cells(line, edges, grid)
            if rows and (joining if grid else not cells[0]):  # a row's next line
                rows[-1] = [f"{a} {b}".strip() for a, b in zip(rows[-1], cells)]
            else:
                rows.append(cells)
            joining = grid
        end += 1
    if not rows:
        return end
    head, body = (rows[:header], rows[header:]) if header else ([[""] * len(rows[0])], rows)
    titles = [" ".join(h[c] for h in head).strip() for c in range(len(head[0]))]
    for row in (titles, None, *body):
        out.append("|---" * len(titles) + "|" if row is None
                   else "| " + " | ".join(inline(c, source) for c in row) + " |")
    return end


def _cells(line: str, edges: list[int], grid: bool) -> list[str]:
    """A table line's cells: between the ``+`` of a grid table's border, or from each column's
    start in a simple table's."""
    line = line.ljust(edges[-1] + 1)
    if grid:
        return [line[a + 1:b].strip() for a, b in zip(edges, edges[1:])]
    return [line[a:b].strip() for a, b in zip(edges, [*edges[1:], len(line)])]


def page(env_id: str) -> str:
    """The Markdown page of ``env_id``."""
    env = gym.make(env_id)
    clock = timing(env_id)
    entry = ENVS[env_id]
    kwargs = {k: v for k, v in entry.get("kwargs", {}).items() if k not in SKIP_KWARGS}
    vector = "native (`gym.make_vec`)" if "vector_entry_point" in entry else "sync or async"
    rows = [("action space", f"`{env.action_space}`"),
            ("observation space", f"`{_short(env.observation_space)}`"),
            ("env step", f"{clock.dt:g} s"),
            ("episode", f"{clock.episode_steps} steps ({clock.episode_steps * clock.dt:g} s)"),
            ("vector env", vector),
            ("registered kwargs", f"`{kwargs}`" if kwargs else "none")]
    env.close()
    table = "\n".join(f"| {name} | {value} |" for name, value in rows)
    name = slug(env_id)
    return (f"# {env_id}\n\n![{env_id}]({name}.png)\n\n| | |\n|---|---|\n{table}\n\n"
            f"```python\nimport gymnasium as gym\nimport animat\n\nenv = gym.make(\"{env_id}\")\n"
            f"```\n\n## Description\n\n{described(env_id)}\n")


def _short(space) -> str:
    text = str(space)
    return text if len(text) <= 160 else text[:157] + "..."


def picture(env_id: str, path: Path, steps: int = 10) -> None:
    """A frame of ``env_id`` after ``steps`` env steps of zero actions from seed 0."""
    env = gym.make(env_id, render_mode="rgb_array")
    env.reset(seed=0)
    action = np.zeros(env.action_space.shape, env.action_space.dtype)  # every id's is a Box
    for _ in range(steps):
        env.step(action)
    frame = env.render()
    env.close()
    cv2.imwrite(str(path), np.asarray(frame)[:, :, ::-1])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="exit 1 if a page's text differs from what it would be")
    args = parser.parse_args(argv)
    PAGES.mkdir(exist_ok=True)
    stale = []
    ids = sorted(k for k in gym.registry if k.startswith("Animat/"))
    for env_id in ids:
        path = PAGES / f"{slug(env_id)}.md"
        text = page(env_id)
        if args.check:
            if not path.is_file() or path.read_text() != text:
                stale.append(path.name)
            continue
        path.write_text(text)
        picture(env_id, PAGES / f"{slug(env_id)}.png")
    index = "# Environments\n\n" + "\n".join(f"- [{i}]({slug(i)}.md)" for i in ids) + "\n"
    if args.check:
        if (PAGES / "index.md").read_text() != index:
            stale.append("index.md")
        if stale:
            print(f"out of date: {', '.join(stale)} (run python docs/scripts/gen_env_pages.py)")
        return 1 if stale else 0
    (PAGES / "index.md").write_text(index)
    return 0


if __name__ == "__main__":
    sys.exit(main())
