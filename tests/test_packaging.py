"""What the package declares is what its code needs: the wheel built from the tree holds every
file of code, every shipped config and repertoire and ``py.typed``; every module imports under
``animat`` from its own file; and every third-party import is a declared dependency (an
optional one only in an extra, and only where its absence is handled)."""

import ast
import importlib
import shutil
import subprocess
import sys
import tomllib
import zipfile
from importlib import metadata
from pathlib import Path

from tests.support.packaging import CODE, SKIP, clean_env, module_names

ROOT = Path(__file__).resolve().parents[1]
# the imports that an extra provides, and the modules that import them (each handles its
# absence: the benchmark runs without Swimmer-v5, the sweep says to install the extra)
OPTIONAL = {"mujoco": ("bench", {"experiments/bench/physics.py"}),
            "ray": ("ray", {"experiments/executors.py"})}
DATA = {"animat/configs": "configs", "animat/repertoires": "repertoires"}


def build_wheel(folder: Path) -> Path:
    """The wheel of a copy of the tree (no build/ of an older tree can leak in), built with
    this interpreter's setuptools when it is new enough, else in pip's isolated build env."""
    source, dist = folder / "source", folder / "dist"
    shutil.copytree(ROOT, source, ignore=SKIP)
    try:
        import setuptools

        isolated = int(setuptools.__version__.split(".")[0]) < 77
    except ImportError:
        isolated = True
    flags = [] if isolated else ["--no-build-isolation"]
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", *flags, "-w",
                    str(dist), str(source)], check=True, capture_output=True, cwd=folder,
                   env=clean_env(), timeout=600)
    return next(dist.glob("artificial_animals-*.whl"))


def _requirement_name(requirement: str) -> str:
    return requirement.split(";")[0].split("[")[0].split("<")[0].split(">")[0].split("=")[0] \
        .split("~")[0].split("!")[0].strip().lower().replace("_", "-")


def _third_party_imports() -> dict[str, set[str]]:
    """{top-level module: files importing it} over the package's code."""
    found: dict[str, set[str]] = {}
    for folder in CODE.values():
        for path in (ROOT / folder).rglob("*.py"):
            for node in ast.walk(ast.parse(path.read_text())):
                names = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                         [node.module] if isinstance(node, ast.ImportFrom) and node.level == 0
                         else [])
                for name in names:
                    top = name.split(".")[0]
                    if top not in sys.stdlib_module_names and top != "animat":
                        found.setdefault(top, set()).add(path.relative_to(ROOT).as_posix())
    return found


def test_every_third_party_import_is_a_declared_dependency():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    required = {_requirement_name(r) for r in project["dependencies"]}
    extras = {name: {_requirement_name(r) for r in reqs}
              for name, reqs in project["optional-dependencies"].items()}
    distributions = metadata.packages_distributions()
    for module, files in _third_party_imports().items():
        names = {d.lower().replace("_", "-") for d in distributions.get(module, [])}
        assert names, f"{module} (imported by {sorted(files)}) is not installed"
        if module in OPTIONAL:
            extra, allowed = OPTIONAL[module]
            assert names & extras[extra], f"{module} is not in the {extra!r} extra"
            assert files <= allowed, f"optional {module} imported by {sorted(files - allowed)}"
        else:
            assert names & required, f"{module} (imported by {sorted(files)}) is not declared"


def test_every_module_of_the_tree_imports_under_animat_from_its_own_file():
    modules = module_names()
    for name, path in modules.items():
        assert Path(importlib.import_module(name).__file__).resolve() == path.resolve(), name
    assert len(modules) > 60


def test_the_wheel_holds_every_file_of_code_every_shipped_file_and_py_typed(tmp_path):
    names = set(zipfile.ZipFile(build_wheel(tmp_path)).namelist())
    wanted = {"animat/py.typed"}
    for name, folder in CODE.items():
        prefix = name.replace(".", "/")
        wanted |= {f"{prefix}/{p.relative_to(ROOT / folder).as_posix()}"
                   for p in (ROOT / folder).rglob("*.py")}
    for prefix, folder in DATA.items():
        wanted |= {f"{prefix}/{p.relative_to(ROOT / folder).as_posix()}"
                   for p in (ROOT / folder).rglob("*") if p.is_file()}
    assert "animat/envs/world/life.py" in wanted and "animat/configs/fish_swim/tune_ppo.yaml" \
        in wanted
    assert not wanted - names, sorted(wanted - names)


def test_python_inside_a_checkout_without_an_install_says_what_to_do():
    """Without site-packages (so no editable install maps envs/ into animat.*), ``import
    animat`` from the checkout names the fix in one line instead of Python's "circular
    import"."""
    done = subprocess.run([sys.executable, "-S", "-c", "import animat"], cwd=ROOT,
                          capture_output=True, text=True, timeout=120, env=clean_env())
    last = done.stderr.strip().splitlines()[-1]
    assert done.returncode != 0 and "circular" not in done.stderr
    assert last.startswith("ImportError: animat is imported from") and "pip install -e ." in last
