"""The architecture as a test (docs/architecture.md): every ``animat`` import is read with
``ast`` and checked against the one-way order, no module imports a private name of another
room, no module imports its own top-level package absolutely (relative imports inside each of
``envs``, ``learners``, ``experiments``), and no folder holds more than 12 modules. Of the
tests, no test module (``test_*.py``) imports another: what several share is in
``tests/support/``.

The order: ``experiments`` -> ``learners`` -> ``envs``; inside ``envs`` a room imports only
rooms of a lower level (or its own): ``registration`` 7, ``world`` 6, ``core`` and ``tasks`` 5
(each reads the other: the core steps a task, a task reads the core's world), ``vision`` 4,
``motor`` and ``render`` 3, ``physics`` 2, ``bodies`` 1, ``checks`` 0. What still breaks a rule
is listed in :data:`KNOWN`, each with what must change; the test fails on anything new, and on
a listed exception that is gone (so that the list only shrinks).
"""

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {"envs": 1, "learners": 2, "experiments": 3}
LEVELS = {"checks": 0, "bodies": 1, "physics": 2, "motor": 3, "render": 3, "vision": 4,
          "core": 5, "tasks": 5, "world": 6, "registration": 7, "": 8}
MAX_MODULES = 12
KNOWN: set[str] = set()


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(["animat", *(parts[:-1] if parts[-1] == "__init__" else parts)])


def _room(module: str) -> str:
    """``envs.<room>`` inside envs (``envs.`` for its own __init__), else the package."""
    parts = module.split(".")
    return f"envs.{parts[2] if len(parts) > 2 else ''}" if parts[1] == "envs" else parts[1]


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


def _imports(path: Path):
    """(imported module, names) of every ``animat`` import in ``path`` (relative ones
    resolved)."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and _absolute(path, node).startswith("animat."):
            yield _absolute(path, node), [alias.name for alias in node.names]
        elif isinstance(node, ast.Import):
            yield from ((a.name, []) for a in node.names if a.name.startswith("animat."))


def _broken(me: str, target: str, names: list[str]) -> list[str]:
    """The rules ``me`` importing ``names`` of ``target`` breaks."""
    found = []
    mine, theirs = _room(me), _room(target)
    if PACKAGES[mine.split(".")[0]] < PACKAGES[theirs.split(".")[0]]:
        found.append(f"backward: {me} -> {target}")
    elif mine.startswith("envs.") and theirs.startswith("envs.") and mine != theirs:
        a, b = LEVELS[mine[5:]], LEVELS[theirs[5:]]
        if b > a or (b == a and a != LEVELS["core"]):
            found.append(f"order: {me} -> {target}")
    if mine != theirs:
        found += [f"private: {me} -> {target}.{n}" for n in names if n.startswith("_")]
    return found


def _violations() -> set[str]:
    found = set()
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            for target, names in _imports(path):
                found.update(_broken(_module(path), target, names))
            found.update(_absolute_inside(path))
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
