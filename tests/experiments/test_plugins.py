"""``animat --import MODULE``: a user's module (:mod:`tests.support.user_animals`, which registers
a body, a task, a sensor, an env id and a learner) named on the command line of a new process,
so that ``animat run`` runs a config of its pieces, ``animat eval`` re-scores the folder, and
``animat sweep --jobs 2`` runs its seeds in processes of their own; without it each refuses the
config in one line, and a module that is no module is refused in one line. A worker process
spawned afresh knows the registrations once it has imported the modules
(:func:`~animat.experiments.launch.plugins.with_imports`)."""

import json
import multiprocessing
import os
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest

from animat.experiments.launch.plugins import ImportRefused, import_modules, with_imports
from tests.support.cli import ROOT, write_config
from tests.support.registries import user_id_known

MODULE = "tests.support.user_animals"  # never imported by this process: its registrations
USER_ID = "UserAnimals/EelDive-v0"  # would outlive the test
STEPS = 10  # env steps of the eel's half-second episode
CONFIG = {"env": {"id": USER_ID, "kwargs": {"weight": 2.0}},
          "learner": {"name": "eel_annealing",
                      "params": {"chains": 4, "nodes": 4, "period": 0.5, "start_states": 2}},
          "budget": {"env_steps": 4 * 2 * STEPS * 2}, "seed": 0,
          "eval": {"metric": "eval/depth_bl"}}


def shell(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """``animat ARGS`` in a new process, as a shell runs it, with the checkout on PYTHONPATH
    (so that the test's module imports)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT),
               PATH=f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    return subprocess.run(["animat", *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=900)


def test_animat_run_and_eval_know_the_pieces_of_an_imported_module(tmp_path):
    write_config(tmp_path / "eel.yaml", CONFIG)
    refused = shell("run", "eel.yaml", "--quiet", cwd=tmp_path)
    assert refused.returncode == 2 and not (tmp_path / "runs").exists()
    line = refused.stderr.strip()
    assert "\n" not in line and f"env.id: unknown env id '{USER_ID}'" in line
    assert "animat --import MODULE" in line
    done = shell("--import", MODULE, "run", "eel.yaml", "--out", "run", "--quiet",
                 "--threads", "1", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    result = json.loads((tmp_path / "run" / "result.json").read_text())
    assert result["status"] == "done" and result["env_steps"] == CONFIG["budget"]["env_steps"]
    assert "name: eel_annealing" in (tmp_path / "run" / "config.yaml").read_text()
    again = shell("--import", MODULE, "eval", "run", "--episodes", "2", cwd=tmp_path)
    assert again.returncode == 0 and "eval/depth_bl" in again.stdout, again.stderr
    blind = shell("eval", "run", "--episodes", "2", cwd=tmp_path)
    assert blind.returncode == 2 and "unknown env id" in blind.stderr


def test_a_sweeps_processes_import_the_module_too(tmp_path):
    write_config(tmp_path / "eel.yaml", CONFIG)
    swept = shell("--import", MODULE, "sweep", "eel.yaml", "--seeds", "0,1", "--jobs", "2",
                  "--out", "sweep", cwd=tmp_path)
    assert swept.returncode == 0, swept.stderr
    statuses = [json.loads(p.read_text())["status"]
                for p in sorted((tmp_path / "sweep").rglob("result.json"))]
    assert statuses == ["done", "done"]


@pytest.mark.parametrize(("name", "message"), [
    ("no_such_module_here", "--import no_such_module_here: no module named "
                            "'no_such_module_here' (install it, or put its folder on "
                            "PYTHONPATH)"),
    ("my animals", "--import 'my animals': not a module name (dotted, like "
                   "my_package.animals)"),
    ("../my_animals", "--import '../my_animals': not a module name (dotted, like "
                      "my_package.animals)"),
])
def test_a_module_that_is_not_there_is_refused_in_one_line(tmp_path, name, message):
    with pytest.raises(ImportRefused, match="^" + message.replace("(", r"\(").replace(")", r"\)")):
        import_modules([name])
    refused = shell("--import", name, "list", cwd=tmp_path)
    assert refused.returncode == 2 and refused.stderr.strip() == f"animat: error: {message}"


def test_a_missing_module_inside_the_users_module_is_its_own_error(tmp_path, monkeypatch):
    (tmp_path / "broken_animals.py").write_text("import no_such_dependency_here\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with pytest.raises(ModuleNotFoundError, match="no_such_dependency_here"):
        import_modules(["broken_animals"])


def test_a_spawned_worker_knows_the_registrations_once_it_imports_the_modules():
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=1, mp_context=context) as pool:
        assert pool.submit(with_imports, (), user_id_known).result() is False
        assert pool.submit(with_imports, (MODULE,), user_id_known).result() is True
