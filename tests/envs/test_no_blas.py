"""The simulator needs no BLAS: with SciPy made unimportable, every compiled kernel (the fused
physics step, the beach ball's contact, the rasterizer and the retinas) compiles and runs.

Numba compiles ``@`` and ``np.dot`` on arrays to calls into SciPy's BLAS, and SciPy is no
dependency of this project: a kernel that used them failed on a fresh install with
``ImportError: scipy 0.16+ is required for linear algebra``. The check runs in a fresh process
with an empty Numba cache, so that nothing compiled where SciPy was present can hide it."""

import os
import subprocess
import sys

import pytest

SCRIPT = """
import sys
sys.modules["scipy"] = None  # any import of scipy now raises ImportError
try:
    import scipy  # noqa: F401
    raise SystemExit("scipy is still importable")
except ImportError:
    pass
import gymnasium as gym
import numpy as np
import animat  # noqa: F401

env = gym.make("Animat/DolphinNoseBall-v0", render_mode="rgb_array")
env.reset(seed=0)
_, _, _, _, info = env.step(env.action_space.sample())
frame = env.render()
vec = gym.make_vec("Animat/FishSwim-v0", num_envs=64)  # the threaded batch kernel
vec.reset(seed=0)
obs, *_ = vec.step(vec.action_space.sample())
pursuit = gym.make("Animat/FishPursuit-v0")  # the retinas
eyes, _ = pursuit.reset(seed=0)
eyes, *_ = pursuit.step(pursuit.action_space.sample())
assert np.isfinite(info["com"]).all() and np.isfinite(obs).all()
print(frame.shape, obs.shape, eyes["left_eye"].shape, int(eyes["left_eye"].std() > 0))
"""


@pytest.mark.slow  # a fresh process compiles every kernel: 97 s
def test_physics_and_rendering_run_with_scipy_unimportable(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    done = subprocess.run([sys.executable, "-c", SCRIPT], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.split() == ["(360,", "480,", "3)", "(64,", "150)", "(64,", "64,", "12)",
                                   "1"]
