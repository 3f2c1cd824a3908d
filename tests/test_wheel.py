"""The package as a user installs it: a wheel built from the tree, installed into a clean venv
(no system site packages, nothing of this checkout on its path), used from a directory outside
the checkout: every module imports from the wheel, every registered env makes and steps,
``animat list`` names them and the shipped configs, and ``animat run`` of a shipped config by
name (the quickstart) and by its checkout path (a fish macro config, whose repertoire path is
relative to the config's folder) finish at a small budget. The unrelated ``envs`` package of the
package index installs beside it (a top-level ``envs`` of ours would have overwritten it).

Slow (it installs torch and the rest into the venv, and Numba compiles the kernels afresh):
``python -m pytest -m slow`` runs it, and ``.ci/run`` does; the default suite deselects it
(``addopts``), so ``pytest tests/test_wheel.py`` alone runs nothing without ``-m slow``. The
wheel's contents are checked in the default suite (``tests/test_packaging.py``).
"""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.support.packaging import SKIP, clean_env, module_names

ROOT = Path(__file__).resolve().parents[1]
SMOKE = """
import importlib, json, sys
import gymnasium as gym
for name in json.loads(sys.argv[1]):
    module = importlib.import_module(name)
    assert "site-packages" in module.__file__, (name, module.__file__)
import animat, envs
assert hasattr(envs, "Env") and "site-packages" in envs.__file__  # the index's envs, not fish
ids = sorted(k for k in gym.registry if k.startswith("Animat/"))
for env_id in ids:
    env = gym.make(env_id)
    env.reset(seed=0)
    env.step(env.action_space.sample())
    env.close()
print(json.dumps(ids))
"""
def _run(args: list, cwd: Path, timeout: float = 1800) -> str:
    done = subprocess.run([str(a) for a in args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout, env=clean_env())
    assert done.returncode == 0, f"{args}:\n{done.stdout[-2000:]}\n{done.stderr[-3000:]}"
    return done.stdout


@pytest.mark.slow
def test_the_wheel_installs_into_a_clean_venv_and_runs_from_outside_the_checkout(tmp_path):
    source = tmp_path / "source"
    shutil.copytree(ROOT, source, ignore=SKIP)  # no build/ left over from an older tree
    _run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "-w", tmp_path / "dist",
          source], tmp_path)
    wheel = next((tmp_path / "dist").glob("artificial_animals-*.whl"))
    venv, outside = tmp_path / "venv", tmp_path / "elsewhere"
    outside.mkdir()
    _run([sys.executable, "-m", "venv", venv], tmp_path)
    python, animat = venv / "bin" / "python", venv / "bin" / "animat"
    _run([python, "-m", "pip", "install", "--quiet", "torch==2.13.*"], outside)
    _run([python, "-m", "pip", "install", "--quiet", wheel, "envs==1.4"], outside)
    assert _run([python, "-c", "import sys; print(sys.flags.no_site, sys.path)"], outside) \
        .find(str(ROOT)) < 0  # the checkout is not on the venv's path

    ids = json.loads(_run([python, "-c", SMOKE, json.dumps(sorted(module_names()))],
                          outside).splitlines()[-1])
    assert len(ids) == 14
    listed = _run([animat, "list"], outside)
    assert all(env_id in listed for env_id in ids)
    assert all(name in listed for name in
               ("quickstart", "fish_swim/tune_ppo", "fish_swim/tuned_ppo"))
    for config, out in (("quickstart", "quick"), ("configs/fish_reach/macro.yaml", "reach")):
        _run([animat, "run", config, "--set", "budget.env_steps=20000", "--out", f"runs/{out}",
              "--quiet"], outside)
        result = json.loads((outside / "runs" / out / "result.json").read_text())
        assert result["status"] == "done" and 0 < result["env_steps"] <= 20_000
