"""Torch's OpenMP runtime loads before Numba starts its threads wherever animat may learn with
torch, and a script that loaded them the other way round is told (each case in a new
interpreter: which runtime loaded first is a property of the process)."""

import subprocess
import sys

STEP_THE_PURSUIT = ("import numpy as np, gymnasium as gym, animat; "
                    "env = gym.make_vec('Animat/FishPursuit-v0', num_envs=2); env.reset(seed=0); "
                    "env.step(np.zeros((2, 7), np.float32)); ")


def _python(code: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=600, check=True)


def test_torch_loads_first_unless_numba_has_started():
    done = _python(
        "import sys; from animat.learners.ppo.threads import load_torch_first, numba_started, "
        "torch_loaded_late; "
        "load_torch_first(); print('torch' in sys.modules, numba_started(), torch_loaded_late())")
    assert done.stdout.split() == ["True", "False", "False"]
    late = _python(
        "import sys; from animat.learners.ppo.threads import load_torch_first, "
        "torch_loaded_late; " + STEP_THE_PURSUIT +
        "late = torch_loaded_late(); load_torch_first(); print(late, 'torch' in sys.modules)")
    assert late.stdout.split() == ["True", "False"]  # too late to help: left to the user


def test_the_learning_commands_load_torch_before_they_run():
    """``animat run`` (and eval, sweep, tune, bench --learners) has torch loaded before its
    handler builds or steps an env."""
    done = _python(
        "import sys; import animat.experiments.cli as cli; "
        "from animat.learners.ppo.threads import numba_started; "
        "seen = lambda args: print('torch' in sys.modules, numba_started()) or 0; "
        "cli.cmd_run = cli.cmd_list = seen; "
        "cli.main(['list']); cli.main(['run', 'any.yaml'])")
    assert done.stdout.split() == ["False", "False", "True", "False"]


def test_ppo_learning_on_two_threads_after_numba_started_says_to_import_torch_first():
    code = ("from animat.learners.registry import make_learner; " + STEP_THE_PURSUIT +
            "make_learner('ppo', 'Animat/FishSwim-v0', {}, {'update_threads': %d})")
    warned = _python(code % 2).stderr.strip().splitlines()
    assert len(warned) == 1 and warned[0].startswith("animat: warning: Numba's threads started")
    assert warned[0].endswith("import torch before the first env step")
    assert _python(code % 1).stderr == ""  # one thread contends with nothing
