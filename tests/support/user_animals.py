"""A user's module, as ``my_animals.py`` would be in a project of its own: importing it
registers a body (the eel), a task (a dive), a sensor (a depth gauge), an env id of the three
(:data:`USER_ID`) and a learner (``eel_annealing``), so that ``animat --import
tests.support.user_animals run CONFIG`` knows them (tests/experiments/test_plugins.py)."""

from animat.envs import register_body, register_env, register_sensor, register_task
from animat.learners import register_learner
from animat.learners.blackbox import AnnealingLearner
from tests.support.bodies import eel_body
from tests.support.registries import DiveTask
from tests.support.sensors import DepthGauge

USER_ID = "UserAnimals/EelDive-v0"


class EelAnnealing(AnnealingLearner):
    """The package's annealing under the user's name: a learner of the user's module."""


register_body("eel", eel_body)
register_task("dive", DiveTask)
register_sensor("depth", DepthGauge)
register_env(USER_ID, task="dive", body="eel", duration=0.5,
             sensors=["proprioception", "depth"])
register_learner("eel_annealing", EelAnnealing)
