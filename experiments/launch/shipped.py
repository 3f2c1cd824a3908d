"""What the package ships beside its code: the configs and the learned repertoires; and what
the repository ships beside them: the run folders of the results the docs quote
(``results/``, :func:`is_shipped_result`).

In a source checkout they are the top-level folders ``configs/`` and ``repertoires/``; in an
installed wheel, the package data ``animat/configs/`` and ``animat/repertoires/``. Either way
they sit beside the ``experiments`` package's folder (two folders above this module), so one
rule finds them, and a shipped config's relative paths (``../repertoires/fish.json``)
resolve against its folder in both.
"""

from __future__ import annotations

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]  # the checkout, or the installed animat/ folder
CONFIGS = ROOT / "configs"
REPERTOIRES = ROOT / "repertoires"
RESULTS = ROOT / "results"  # in a source checkout only


def is_shipped_result(folder: str | Path) -> bool:
    """Whether ``folder`` is (inside) the repository's ``results/``: a quoted result's run
    folder, which ``animat eval`` re-scores without writing into."""
    return Path(folder).resolve().is_relative_to(RESULTS.resolve())


def shipped_configs() -> list[str]:
    """Every shipped config's name: its path under the configs folder without ``.yaml``
    (``quickstart``, ``fish_swim/tune_ppo``), sorted."""
    if not CONFIGS.is_dir():
        return []
    return sorted(p.relative_to(CONFIGS).with_suffix("").as_posix()
                  for p in CONFIGS.rglob("*.yaml"))


def describe_config(name: str, width: int = 72) -> str:
    """A shipped config's description: its first line, a comment (``# Swim by CMA-ES ...``),
    cut to ``width`` characters (with an ellipsis); empty for a config that opens otherwise."""
    first = (CONFIGS / f"{name}.yaml").read_text(encoding="utf-8").split("\n", 1)[0]
    if not first.startswith("#"):
        return ""
    text = first.lstrip("#").strip()
    return text if len(text) <= width else text[:width - 1].rstrip() + "…"


def find_config(name: str | Path) -> Path:
    """The config a user names: a file that exists (relative to the current directory), else
    the shipped config of that name (``quickstart`` or ``quickstart.yaml``,
    ``fish_swim/tune_ppo``). A name that is neither is returned as given, for the reader to
    refuse with the file's name."""
    path = Path(name)
    if path.is_file():
        return path
    relative = path.as_posix().removeprefix("configs/")
    for candidate in (CONFIGS / relative, CONFIGS / f"{relative}.yaml"):
        if not path.is_absolute() and candidate.is_file():
            return candidate
    return path
