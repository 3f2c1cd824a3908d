"""The architecture as a test (docs/architecture.md): every ``animat`` import (at the top,
inside a function or under ``TYPE_CHECKING``) is read with ``ast`` and checked against the
one-way order, no circle of files, no module imports a private name of another room or reads
``obj._x`` where only another room defines ``_x``, no module imports its own top-level package
absolutely (relative imports inside each of ``envs``, ``learners``, ``experiments``), and no
folder holds more than 12 modules. Of the tests, no test module (``test_*.py``) imports
another: what several share is in ``tests/support/``.

The order: ``experiments`` -> ``learners`` -> ``envs``; inside each package a room (a folder,
or a module at the package's top) imports only rooms of a lower floor (:data:`LEVELS`), or a
room of its own floor where :data:`SHARED` says so (``envs``' ``core`` and ``tasks``: the core
steps a task, a task reads the core's world). What still breaks a rule would be listed in
:data:`KNOWN`, each with what must change; the test fails on anything new, and on a listed
exception that is gone (so that the list only shrinks).
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {"envs": 1, "learners": 2, "experiments": 3}
# each package's rooms (a folder, or a module at its top; "" its __init__) on floors: a room
# imports only rooms of a lower floor, or a room it shares a floor with where SHARED says so
LEVELS = {
    "envs": {"checks": 0, "bodies": 1, "physics": 2, "motor": 3, "render": 3, "vision": 4,
             "core": 5, "tasks": 5, "world": 6, "registration": 7, "": 8},
    "learners": {"storage": 0, "validation": 0, "logger": 1, "optimizers": 1, "rollout": 2,
                 "controllers": 3, "base": 3, "agents": 4, "blackbox_run": 4, "blackbox": 5,
                 "ppo": 5, "macro": 6, "skills": 7, "scorers": 8, "stroke": 8, "switching": 8,
                 "registry": 9, "": 10},
    "experiments": {"launch": 0, "biology": 1, "evaluate": 1, "executors": 1, "parser": 1,
                    "bench": 2, "demo": 2, "figures": 2, "sweep": 2, "tune": 2, "compare": 3,
                    "fingerprint": 3, "cli": 4, "__main__": 5, "": 6},
}
SHARED = {("envs", "core"), ("envs", "tasks")}  # the core steps a task, a task reads the core
MAX_MODULES = 12
KNOWN: set[str] = set()


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(["animat", *(parts[:-1] if parts[-1] == "__init__" else parts)])


def _room(module: str) -> str:
    """``<package>.<room>``: the folder or top-level module of its package a module is in
    (``<package>.`` for the package's own __init__)."""
    parts = module.split(".")
    return f"{parts[1]}.{parts[2] if len(parts) > 2 else ''}"


def _absolute(path: Path, node: ast.ImportFrom) -> str:
    """The module a ``from ... import`` in ``path`` names, relative imports resolved."""
    if not node.level:
        return node.module or ""
    module = _module(path).split(".")
    package = module if path.name == "__init__.py" else module[:-1]
    base = package[:len(package) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


def _absolute_inside(path: Path) -> list[str]:
    """Absolute imports of ``path``'s own top-level package (relative ones are the rule, so
    that tools follow the folders without the install's mapping)."""
    top = f"animat.{_module(path).split('.')[1]}"
    return [f"absolute: {_module(path)} -> {node.module}"
            for node in ast.walk(ast.parse(path.read_text()))
            if isinstance(node, ast.ImportFrom) and not node.level and node.module
            and (node.module == top or node.module.startswith(top + "."))]


def _is_module(module: str) -> bool:
    """Whether dotted ``animat.<...>`` names a module or package of this repository."""
    path = ROOT.joinpath(*module.split(".")[1:])
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def _imports(path: Path):
    """(imported module, names) of every ``animat`` import in ``path``, at the top, inside a
    function or under ``TYPE_CHECKING`` alike (relative ones resolved; ``from package import
    module`` is an import of that module)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and _absolute(path, node).startswith("animat."):
            base, names = _absolute(path, node), []
            for alias in node.names:
                if _is_module(f"{base}.{alias.name}"):
                    yield f"{base}.{alias.name}", []
                else:
                    names.append(alias.name)
            if names:
                yield base, names
        elif isinstance(node, ast.Import):
            yield from ((a.name, []) for a in node.names if a.name.startswith("animat."))


def _file_of(module: str) -> str:
    """The module a dotted import lands in: ``module`` itself, or the nearest package or
    module above it that is a file (``animat.envs.core.Batch`` -> ``animat.envs.core``)."""
    while not _is_module(module):
        module = module.rsplit(".", 1)[0]
    return module


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The circles of ``graph`` (module -> modules it imports): each strongly connected set
    of more than one module, sorted (Tarjan's algorithm, without recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                circle = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    circle.append(member)
                    if member == node:
                        break
                if len(circle) > 1:
                    found.append(sorted(circle))
    return sorted(found)


def _private_names(source: str) -> set[str]:
    """The private names (``_x``, not dunder) ``source`` defines: functions, classes, module
    and class variables, and attributes it assigns (``self._x = ...``)."""
    names = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            names.add(node.id)
        elif (isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store)
              and isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
            names.add(node.attr)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return {n for n in names if n.startswith("_") and not n.startswith("__")}


def _private_reaches(me: str, source: str, others: set[str], own: set[str]) -> list[str]:
    """``obj._x`` read in module ``me`` (its ``source``; not on ``self`` or ``cls``) where
    ``_x`` is a private name defined in another room (``others``) and not in this one
    (``own``): a reach into that room's internals."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if (isinstance(node, ast.Attribute) and node.attr in others and node.attr not in own
                and not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls"))):
            found.append(f"private: {me} reaches .{node.attr}")
    return found


def _broken(me: str, target: str, names: list[str]) -> list[str]:
    """The rules ``me`` importing ``names`` of ``target`` breaks."""
    found = []
    mine, theirs = _room(me), _room(target)
    (package, room), (their_package, their_room) = mine.split("."), theirs.split(".")
    if PACKAGES[package] < PACKAGES[their_package]:
        found.append(f"backward: {me} -> {target}")
    elif package == their_package and room != their_room:
        a, b = LEVELS[package][room], LEVELS[package][their_room]
        shared = (package, room) in SHARED and (package, their_room) in SHARED
        if b > a or (b == a and not shared):
            found.append(f"order: {me} -> {target}")
    if mine != theirs:
        found += [f"private: {me} -> {target}.{n}" for n in names if n.startswith("_")]
    return found


def _sources() -> list[Path]:
    return [path for package in PACKAGES for path in sorted((ROOT / package).rglob("*.py"))]


def _violations() -> set[str]:
    found, graph = set(), {}
    private: dict[str, set[str]] = {}
    for path in _sources():
        private.setdefault(_room(_module(path)), set()).update(_private_names(path.read_text()))
    for path in _sources():
        me, room = _module(path), _room(_module(path))
        graph[me] = set()
        for target, names in _imports(path):
            found.update(_broken(me, target, names))
            if _file_of(target) != me:
                graph[me].add(_file_of(target))
        found.update(_absolute_inside(path))
        others = set().union(*(names for r, names in private.items() if r != room))
        found.update(_private_reaches(me, path.read_text(), others, private[room]))
    found.update(f"circle: {' -> '.join(circle)}" for circle in _circles(graph))
    for package in PACKAGES:
        for folder in [ROOT / package, *(p for p in (ROOT / package).rglob("*") if p.is_dir())]:
            count = len(list(folder.glob("*.py")))
            if count > MAX_MODULES:
                name = folder.relative_to(ROOT).as_posix()
                found.add(f"crowded: {name} ({count} modules)")
    return found


def _test_modules_imported(me: str, source: str) -> list[str]:
    """The test modules (last dotted part ``test_...``) that the source of test module ``me``
    (dotted, e.g. ``tests.learners.test_params``) imports: ``import tests.x.test_y``, ``from
    tests.x.test_y import ...``, ``from tests.x import test_y`` and relative imports."""
    package = me.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            found += [module, *(f"{module}.{alias.name}" for alias in node.names)]
    return [name for name in found if name.split(".")[-1].startswith("test_")]


def test_imports_run_one_way_and_folders_stay_small():
    found = _violations()
    assert found - KNOWN == set(), "new: " + "; ".join(sorted(found - KNOWN))
    assert KNOWN - found == set(), "mended, take off KNOWN: " + "; ".join(sorted(KNOWN - found))


def test_the_checks_catch_what_they_say():
    assert _broken("animat.envs.physics.forces", "animat.learners.base", []) == [
        "backward: animat.envs.physics.forces -> animat.learners.base"]
    assert _broken("animat.envs.bodies.fish", "animat.envs.motor.fish", []) == [
        "order: animat.envs.bodies.fish -> animat.envs.motor.fish"]
    assert _broken("animat.envs.core.batch", "animat.envs.tasks.base", []) == []
    assert _broken("animat.learners.ppo.learner", "animat.envs.render.raster", ["_ray"]) == [
        "private: animat.learners.ppo.learner -> animat.envs.render.raster._ray"]
    assert _broken("animat.envs.render.seaworld", "animat.envs.render.raster", ["_ray"]) == []
    assert _broken("animat.learners.storage.files", "animat.learners.blackbox_run", []) == [
        "order: animat.learners.storage.files -> animat.learners.blackbox_run"]
    assert _broken("animat.experiments.figures.curves", "animat.experiments.compare", []) == [
        "order: animat.experiments.figures.curves -> animat.experiments.compare"]
    assert _broken("animat.learners.macro", "animat.learners.controllers.tent", []) == []
    assert _broken("animat.learners.stroke", "animat.learners.switching", []) == [
        "order: animat.learners.stroke -> animat.learners.switching"]  # one floor, not shared
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}) == [
        ["a", "b", "c"]]
    assert _circles({"a": {"b"}, "b": set()}) == []
    assert _file_of("animat.envs.core.batch.BodyBatch") == "animat.envs.core.batch"
    assert _private_names("def _f(): pass\nclass A:\n    _k: int = 1\n    def g(self):\n"
                          "        self._x = 1\n        self.__y = 2\n        other._z = 3\n"
                          ) == {"_f", "_k", "_x"}
    reach = "def f(env):\n    return env.unwrapped.core._triangles(), self._own\n"
    assert _private_reaches("m", reach, {"_triangles", "_own"}, set()) == [
        "private: m reaches ._triangles"]
    assert _private_reaches("m", reach, {"_triangles"}, {"_triangles"}) == []
    relative = ast.parse("from ..tasks.base import Task\nfrom . import sensors").body
    batch, init = ROOT / "envs" / "core" / "batch.py", ROOT / "envs" / "core" / "__init__.py"
    assert _absolute(batch, relative[0]) == "animat.envs.tasks.base"
    assert _absolute(batch, relative[1]) == "animat.envs.core"
    assert _absolute(init, relative[1]) == "animat.envs.core"
    assert _absolute_inside(ROOT / "envs" / "core" / "batch.py") == []
    me = "tests.learners.ppo.test_checkpoint"
    assert _test_modules_imported(me, "from tests.x.test_y import a") == ["tests.x.test_y"]
    assert _test_modules_imported(me, "import tests.x.test_y as y") == ["tests.x.test_y"]
    assert _test_modules_imported(me, "from tests.x import test_y, z") == ["tests.x.test_y"]
    assert _test_modules_imported(me, "from .test_y import a") == ["tests.learners.ppo.test_y"]
    assert _test_modules_imported(me, "from .. import test_y") == ["tests.learners.test_y"]
    assert _test_modules_imported(me, "from ..support import faults") == []
    assert _test_modules_imported(me, "from tests.support.cli import animat") == []


def test_no_test_module_imports_another_test_module():
    """A test module is not a library: one that imports another depends on that module's
    helpers staying as they are, runs its module-level code, and would run any ``test_`` name
    it takes from it twice. Shared helpers live in ``tests/support/``."""
    found = []
    for path in sorted((ROOT / "tests").rglob("test_*.py")):
        me = ".".join(path.relative_to(ROOT).with_suffix("").parts)
        found += [f"{path.relative_to(ROOT).as_posix()} imports {module}"
                  for module in _test_modules_imported(me, path.read_text())]
    assert found == [], "move what is shared to tests/support/: " + "; ".join(found)
