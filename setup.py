"""Build script: the package list is found in the tree, not written out.

Everything else is in ``pyproject.toml``. The repository's top-level folders install under one
import namespace: ``envs/`` as ``animat.envs``, ``learners/`` as ``animat.learners``,
``experiments/`` as ``animat.experiments``; every folder below them with an ``__init__.py`` is
a subpackage. The shipped configs and repertoires are package data, ``animat.configs`` and
``animat.repertoires`` (:mod:`animat.experiments.launch.shipped` finds them installed or in a
checkout).
"""

from pathlib import Path

from setuptools import setup

ROOT = Path(__file__).resolve().parent
CODE = {"animat": "animat", "animat.envs": "envs", "animat.learners": "learners",
        "animat.experiments": "experiments"}
DATA = {"animat.configs": ("configs", "*.yaml"), "animat.repertoires": ("repertoires", "*.json")}


def code_packages() -> list[str]:
    """Every folder with an ``__init__.py`` under the code folders, as a dotted name."""
    found = []
    for name, folder in CODE.items():
        for init in sorted((ROOT / folder).rglob("__init__.py")):
            found.append(".".join((name, *init.parent.relative_to(ROOT / folder).parts)))
    return found


def data_packages() -> dict[str, str]:
    """{package: pattern} for every folder of shipped data, subfolders included."""
    found = {}
    for name, (folder, pattern) in DATA.items():
        for sub in sorted(p for p in [ROOT / folder, *(ROOT / folder).rglob("*")] if p.is_dir()):
            if any(sub.glob(pattern)):
                found[".".join((name, *sub.relative_to(ROOT / folder).parts))] = pattern
    return found


DATA_PACKAGES = data_packages()
setup(
    packages=code_packages() + list(DATA_PACKAGES),
    package_dir={**CODE, **{name: folder for name, (folder, _) in DATA.items()}},
    package_data={"animat": ["py.typed"], **{name: [p] for name, p in DATA_PACKAGES.items()}},
)
