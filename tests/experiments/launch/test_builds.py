"""The env built once per purpose: ``animat run`` of a black-box config builds one single env to
check the config (and read the metrics it reports) and one vector env to learn on; what the
learner needs of the env's shape (an episode's length, the action's) it reads from the registry
(:func:`animat.envs.registration.timing`, :func:`~animat.envs.registration.action_size_of`),
and the folder made from the config just checked is not checked by building again."""

from collections import Counter

import pytest

from animat.envs.core import env as core_env
from tests.support.cli import TINY, animat, write_config


@pytest.fixture
def builds(monkeypatch) -> Counter:
    """How many ``BodyEnv`` and ``BodyVectorEnv`` are made while the test runs, by class."""
    made: Counter = Counter()
    for cls in (core_env.BodyEnv, core_env.BodyVectorEnv):
        def counted(self, *args, _cls=cls, _init=cls.__init__, **kwargs):
            made[_cls.__name__] += 1
            _init(self, *args, **kwargs)

        monkeypatch.setattr(cls, "__init__", counted)
    return made


def test_a_black_box_run_builds_one_env_to_check_and_one_vector_env_to_learn(tmp_path, builds):
    for water in (None, {"model": "resistive"}):  # a recorded water is checked without a build
        builds.clear()
        kwargs = {**TINY["env"]["kwargs"], **({"water": water} if water else {})}
        config = write_config(tmp_path / "tiny.yaml", {**TINY, "env": {**TINY["env"],
                                                                       "kwargs": kwargs}})
        folder = tmp_path / f"run_{len(kwargs)}"
        animat("run", config, "--out", folder, "--quiet", "--threads", "1")
        assert builds == Counter(BodyEnv=1, BodyVectorEnv=1)
        assert "water:" in (folder / "config.yaml").read_text()  # what the folder records
