"""``animat sweep``: one run folder per seed, executed locally (one after the other, or
``--jobs N`` processes at once) or as Ray tasks (one CPU each) on an existing Ray cluster
(``--address``) or a local one (:func:`animat.experiments.executors.run_ray`, each folder
returned to this driver)."""

from __future__ import annotations

import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from .launch.config import ExperimentConfig, load_config
from .launch.execute import execute
from .launch.folders import create_run, default_run_dir, read_status
from .launch.machine import available_cpus
from .launch.plugins import import_flags


def parse_seeds(text: str) -> list[int]:
    """``0-4`` -> [0, 1, 2, 3, 4]; ``1,3,5`` -> [1, 3, 5]; ``7`` -> [7]."""
    seeds: list[int] = []
    try:
        for part in text.split(","):
            if "-" in part:
                low, high = (int(v) for v in part.split("-", 1))
                if high < low:
                    raise ValueError
                seeds.extend(range(low, high + 1))
            else:
                seeds.append(int(part))
    except ValueError:
        raise ValueError(f"--seeds {text!r}: use a range like 0-4 or a list like 1,3,5") from None
    if any(s < 0 for s in seeds):
        raise ValueError(f"--seeds {text!r}: seeds must be >= 0")
    return sorted(set(seeds))


def prepare(config: ExperimentConfig, seeds: list[int], parent: Path | None,
            command: list[str]) -> list[Path]:
    """A new run folder per seed (under ``parent`` when given, else under ``runs/``)."""
    folders = []
    for seed in seeds:
        seeded = config.model_copy(update={"seed": seed})
        folder = default_run_dir(seeded, Path(parent) if parent else Path("runs"))
        folders.append(create_run(seeded, folder, command))
    return folders


def run_local(folders: list[Path], jobs: int = 1, progress=None) -> list[dict]:
    """Execute the folders here: in this process (jobs = 1, with every CPU;
    ``progress(folder)`` may give each run a progress sink) or as ``jobs`` subprocesses
    sharing the CPUs out (each run's Numba threads: CPUs // jobs, at least 1)."""
    if jobs <= 1:
        return [_execute_one(folder, progress) for folder in folders]
    threads = max(1, available_cpus() // jobs)

    def one(folder: Path) -> dict:
        subprocess.run([sys.executable, "-m", "animat.experiments", *import_flags(), "run",
                        "--resume", str(folder),
                        "--quiet", "--threads", str(threads)], check=False,
                       stdout=subprocess.DEVNULL)
        return read_status(folder)

    with ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(one, folders))


def _execute_one(folder: Path, progress=None) -> dict:
    """One run in this process; a failure is recorded in its result.json (and the sweep goes
    on with the next seed)."""
    try:
        return execute(folder, progress(folder) if progress else None)
    except Exception:
        return read_status(folder)


def summary_table(folders: list[Path], results: list[dict], metric: str | None) -> str:
    """The sweep's outcome, one row per run: seed, status, the config's metric, env steps,
    wall seconds, the Ray node that ran it (a Ray sweep's) and the folder; then each failed
    run's one-line error."""
    metric = metric or "eval/return"
    nodes = any("node" in result for result in results)  # Ray's: which node ran it
    rows = [("seed", "status", metric, "env steps", "wall s") + (("node",) if nodes else ())
            + ("folder",)]
    errors = []
    for folder, result in zip(folders, results):
        seed = str(load_seed(folder))
        value = result.get("metrics", {}).get(metric)
        node = (str(result.get("node", "—"))[:8],) if nodes else ()
        rows.append((seed, result["status"], "—" if value is None else f"{value:.4g}",
                     f"{result.get('env_steps', 0):,}", f"{result.get('wall_seconds', 0.0):.1f}",
                     *node, str(folder)))
        if result["status"] != "done":
            error = str(result.get("error") or "no error recorded").splitlines()[0]
            errors.append(f"seed {seed} {result['status']}: {error}")
    widths = [max(len(row[k]) for row in rows) for k in range(len(rows[0]))]
    lines = ["  ".join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip()
             for row in rows]
    return "\n".join(lines + errors)


def load_seed(folder: Path) -> int:
    """The seed a run folder's config.yaml holds, read as every config is (YAML aliases
    refused, the config validated; ConfigError naming the file otherwise)."""
    return load_config(Path(folder) / "config.yaml", build=False, follow_links=False).seed
