"""What an older version's run folders need, in one module: the fields a checkpoint written
before them takes, the dict-era black-box run, and where an old pickle's classes are now."""

from animat.learners.optimizers.annealing import AnnealingParams
from animat.learners.optimizers.cmaes import CMAESParams
from animat.learners.storage import migration


def test_params_from_before_schedules_get_the_stages_their_run_had():
    assert AnnealingParams().schedule == "budget"
    assert migration.as_before_schedules(AnnealingParams(chains=8)) == AnnealingParams(
        chains=8, schedule="stages")
    assert migration.as_before_schedules(CMAESParams()) == CMAESParams()  # nothing to add
    assert migration.fields_written_before("AnnealingParams", {"chains": 8}) == {
        "schedule": "stages", "chains": 8}
    assert migration.fields_written_before("AnnealingParams", {"schedule": "budget"}) == {
        "schedule": "budget"}  # what a checkpoint wrote stands


def test_a_run_checkpointed_before_phases_is_one_phase():
    old = {"params": "p", "state": "s", "best": None, "env_steps": 64, "wall": 1.5, "rounds": 2}
    fields = migration.run_fields(old)
    assert fields["phases"] == [{"params": "p", "state": "s", "best": None, "support": None,
                                 "start": None}]
    assert (fields["env_steps"], fields["wall"], fields["rounds"]) == (64, 1.5, 2)


def test_an_old_pickles_classes_are_found_where_they_are_now():
    assert migration.module_now("learners.annealing", "AnnealingParams") == (
        "animat.learners.optimizers.annealing")
    assert migration.module_now("animat.learners.blackbox", "Run") == (
        "animat.learners.blackbox_run")
    assert migration.module_now("animat.learners.blackbox", "BlackBoxLearner") == (
        "animat.learners.blackbox")  # only the classes that moved
    assert migration.module_now("animat.learners.skills.repertoire", "Skill") == (
        "animat.learners.controllers.repertoire")
