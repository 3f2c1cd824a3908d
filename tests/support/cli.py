"""The launcher as the tests drive it: the repository's root, the tiny config (annealing on a
half-second swim, seconds to run), ``animat ARGS`` run in this process with its exit status
and output, and a config written as YAML."""

import io
import os
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path
from types import SimpleNamespace

import yaml

from animat.experiments import cli

ROOT = Path(__file__).resolve().parents[2]
TINY = {
    "env": {"id": "Animat/FishSwim-v0", "kwargs": {"duration": 0.5}},
    "learner": {"name": "annealing", "params": {"chains": 8, "nodes": 4, "period": 0.5}},
    "budget": {"env_steps": 3200},
    "seed": 0,
    "eval": {"metric": "eval/speed_bl_per_s"},
}


def animat(*args, cwd=None, check=True):
    """``animat ARGS`` in this process, from ``cwd``: its exit status and output."""
    out, err, here = io.StringIO(), io.StringIO(), os.getcwd()
    os.chdir(cwd or ROOT)
    try:
        with redirect_stdout(out), redirect_stderr(err):
            try:
                code = cli.main([str(a) for a in args])
            except SystemExit as stop:  # argparse's usage errors
                code = stop.code if isinstance(stop.code, int) else 1
    finally:
        os.chdir(here)
    result = SimpleNamespace(returncode=code or 0, stdout=out.getvalue(), stderr=err.getvalue())
    if check and result.returncode != 0:
        raise AssertionError(f"animat {args} failed:\n{result.stdout}\n{result.stderr}")
    return result


def write_config(path, data):
    path.write_text(yaml.safe_dump(data))
    return path
