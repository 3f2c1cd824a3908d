"""``animat.learners.register_learner``: a plain call and a decorator; a name taken, a class that
is no learner, each refused in one line; and a user's learner on a user's env id, both
registered in this process, named by a config that the launcher's Python API
(``animat.experiments.run_experiment``) checks against the registries as they are when it is
called and runs. Every test runs inside the registries' restore
(:func:`tests.support.registries.restored_registries`, the fixture ``registries_restored``)."""

from pathlib import Path

import numpy as np
import pytest

import animat  # noqa: F401
from animat.envs import register_body, register_env, register_task
from animat.experiments.launch.config import config_from_data
from animat.experiments.launch.config_yaml import ConfigError
from animat.learners import LEARNERS, make_learner, register_learner
from animat.learners.base import Learner
from animat.learners.blackbox import AnnealingLearner
from animat.learners.validation import DRIVES, check_drives
from tests.support.bodies import eel_body
from tests.support.registries import DiveTask

USER_ID = "UserAnimals/EelDive-v0"
pytestmark = pytest.mark.usefixtures("registries_restored")


def _user_env() -> None:
    """The eel diving (the body and task of tests/envs/test_registration_api.py, from
    :mod:`tests.support`), half a second an episode, as :data:`USER_ID`."""
    register_body("eel", eel_body)
    register_task("dive", DiveTask)
    register_env(USER_ID, task="dive", body="eel", duration=0.5)


class EelAnnealing(AnnealingLearner):
    """The package's annealing under a user's name: a learner of the user's module."""


def test_a_learner_registered_by_call_or_decorator_is_made_by_name():
    assert register_learner("eel_annealing", EelAnnealing) is EelAnnealing
    assert register_learner("eel_annealing", EelAnnealing) is EelAnnealing
    assert EelAnnealing.name == "eel_annealing"  # its own name, not its parent's
    assert AnnealingLearner.name == "annealing" and LEARNERS["annealing"] is AnnealingLearner
    learner = make_learner("eel_annealing", "Animat/FishSwim-v0", {}, {"chains": 4})
    assert isinstance(learner, EelAnnealing) and set(DRIVES) == set(LEARNERS)

    @register_learner("eel_annealing_2")
    class Again(AnnealingLearner):
        pass

    assert LEARNERS["eel_annealing_2"] is Again and Again.name == "eel_annealing_2"


class Abstract(Learner):
    """Learns nothing: no ``learn``."""


class Named(EelAnnealing):
    name = "mine"


@pytest.mark.parametrize("name, cls, message", [
    ("cmaes", EelAnnealing, "learner name 'cmaes' is taken \\(by CMAESLearner\\)"),
    ("eel", object, "not a subclass of animat.learners.base.Learner"),
    ("eel", EelAnnealing("Animat/FishSwim-v0"), "not a subclass of animat.learners.base"),
    ("eel", Abstract, "it does not implement learn"),
    ("eel", Named, "the class is named 'mine'"),
    ("", EelAnnealing, "the name must be a non-empty string"),
])
def test_a_learner_is_refused_in_one_line(name, cls, message):
    before = dict(LEARNERS)
    with pytest.raises(ValueError, match=message) as error:
        register_learner(name, cls)
    assert "\n" not in str(error.value) and LEARNERS == before


def test_the_learners_of_the_body_envs_drive_a_user_env_id_from_its_registration_on():
    with pytest.raises(ValueError, match="learner 'annealing' drives"):
        check_drives("annealing", USER_ID)
    _user_env()
    check_drives("annealing", USER_ID)
    check_drives("ppo", USER_ID)
    with pytest.raises(ValueError, match="learner 'active_vision' drives the pursuit"):
        check_drives("active_vision", USER_ID)


def test_a_config_is_checked_against_the_registries_as_they_are_when_it_is_read():
    data = {"env": {"id": USER_ID}, "learner": {"name": "eel_annealing"},
            "budget": {"env_steps": 1000}}
    with pytest.raises(ConfigError, match=f"env.id: unknown env id '{USER_ID}'"):
        config_from_data(data, "<test>", Path.cwd())
    _user_env()
    with pytest.raises(ConfigError, match="learner.name: unknown learner 'eel_annealing'"):
        config_from_data(data, "<test>", Path.cwd())
    register_learner("eel_annealing", EelAnnealing)
    config = config_from_data(data, "<test>", Path.cwd(), ["seed=3"])
    assert config.learner.name == "eel_annealing" and config.seed == 3


def test_the_launcher_runs_a_user_learner_on_a_user_env_from_a_mapping_or_a_file(tmp_path):
    from animat.experiments import run_experiment
    from animat.experiments.evaluate import load
    from animat.experiments.launch.lock import RunError

    _user_env()
    register_learner("eel_annealing", EelAnnealing)
    steps = 10  # env steps an episode: 0.5 s of 0.05 s
    config = {"env": {"id": USER_ID, "kwargs": {"weight": 2.0}},
              "learner": {"name": "eel_annealing",
                          "params": {"chains": 4, "nodes": 4, "period": 0.5, "start_states": 2}},
              "budget": {"env_steps": 4 * 2 * steps * 2}, "seed": 0,
              "eval": {"metric": "eval/depth_bl"}}
    folder, result = run_experiment(config, out=tmp_path / "run", progress=False)
    assert folder == tmp_path / "run" and result["status"] == "done"
    assert result["env_steps"] == 4 * 2 * steps * 2
    assert np.isfinite(result["metrics"]["eval/depth_bl"])
    assert "name: eel_annealing" in (folder / "config.yaml").read_text()
    assert load(folder).env_id == USER_ID
    (tmp_path / "eel.yaml").write_text((folder / "config.yaml").read_text())
    again, result = run_experiment(tmp_path / "eel.yaml", ["seed=1"], tmp_path / "again",
                                   threads=1, progress=False)
    assert result["status"] == "done" and "seed: 1" in (again / "config.yaml").read_text()
    with pytest.raises(RunError, match="threads must be an integer of at least 1"):
        run_experiment(config, threads=0)
    with pytest.raises(ConfigError, match="budget.env_steps: "):
        run_experiment({**config, "budget": {"env_steps": 1}}, out=tmp_path / "small")
    assert not (tmp_path / "small").exists()
