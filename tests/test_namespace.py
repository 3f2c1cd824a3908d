"""The project installs under one namespace, ``animat``, beside the unrelated ``envs`` package of
the package index (which a top-level ``envs`` of ours would have overwritten)."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CHECK = """
import envs, gymnasium as gym
import animat
from animat.experiments.evaluate import load
print(envs.__file__)
print(animat.envs.__file__)
print(type(gym.make("Animat/FishSwim-v0").unwrapped).__module__)
print(hasattr(envs, "Env"))  # the index's envs: environment variables, not fish
"""


def test_the_project_installs_beside_the_unrelated_envs_package(tmp_path):
    venv = tmp_path / "venv"
    # the machine's pip, setuptools and dependencies are seen; what is installed lands in the venv
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip",
                    str(venv)], check=True)
    python = str(venv / "bin" / "python")
    download = subprocess.run([python, "-m", "pip", "download", "--quiet", "--no-deps", "-d",
                               str(tmp_path / "wheels"), "envs==1.4"], capture_output=True,
                              text=True)
    if download.returncode != 0:
        pytest.skip(f"the package index is not reachable: {download.stderr.strip()[-200:]}")
    wheel = next((tmp_path / "wheels").glob("envs-*.whl"))
    # built in pip's isolated build env (setuptools from the index: the machine's own may be
    # older than the pyproject needs)
    subprocess.run([python, "-m", "pip", "install", "--quiet", "--no-deps", str(wheel),
                    str(ROOT)], check=True, cwd=tmp_path)
    out = subprocess.run([python, "-c", CHECK], cwd=tmp_path, check=True, capture_output=True,
                         text=True).stdout.splitlines()
    site = str(venv / "lib")
    assert out[0].startswith(site) and out[0].endswith("envs/__init__.py")  # the index's
    assert out[1].startswith(site) and out[1].endswith("animat/envs/__init__.py")  # ours
    assert out[2] == "animat.envs.fish_env" and out[3] == "True"
