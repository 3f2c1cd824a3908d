"""What an older version's run folders need to be read today, in one place at the storage
edge: the fields a checkpoint written before them takes (:data:`BEFORE_FIELDS`), the shape of a
black-box run checkpointed before its dataclasses (:func:`run_fields`), and where the classes an
older pickle names are now (:data:`MOVED`). The optimisers and the learners keep no code for
old runs; they call these.
"""

from __future__ import annotations

import dataclasses
from typing import Any

# Fields a checkpoint written before they existed takes, by class name: what its run did then
# (the annealing cooled by stages before it learned to cool over the budget).
BEFORE_FIELDS: dict[str, dict[str, Any]] = {"AnnealingParams": {"schedule": "stages"}}

# modules an older version's pickled checkpoints name, and where they are now; a
# "<module>.<Class>" key: that class alone moved out of the module (the rest stayed)
MOVED = {"animat.learners.annealing": "animat.learners.optimizers.annealing",
         "animat.learners.cmaes": "animat.learners.optimizers.cmaes",
         "animat.learners.abstraction": "animat.learners.controllers.abstraction",
         "animat.learners.controller": "animat.learners.controllers.tent",
         "animat.learners.scorers.active_vision": "animat.learners.scorers.pursuit",
         "animat.learners.scorers.behaviours": "animat.learners.scorers.living_world",
         **{f"animat.learners.blackbox.{name}": "animat.learners.blackbox_run"
            for name in ("Phase", "Run")},
         **{f"animat.learners.blackbox.{name}": "animat.learners.controllers.periodic"
            for name in ("ControllerParams", "PeriodicPlayer")},
         "animat.learners.blackbox.ResultFrom": "animat.learners.controllers.report",
         "animat.learners.repertoire": "animat.learners.controllers.repertoire",
         "animat.learners.skills.repertoire": "animat.learners.controllers.repertoire",
         **{f"animat.learners.repertoire.{name}": "animat.learners.skills.basic_training"
            for name in ("BasicTrainingParams", "BasicTrainingLearner")}}


def fields_written_before(name: str, fields: dict[str, Any]) -> dict[str, Any]:
    """``fields`` of a ``name`` object as a checkpoint holds them, with each field an older
    version did not write set as its run had it (:data:`BEFORE_FIELDS`)."""
    return {**BEFORE_FIELDS.get(name, {}), **fields}


def as_before_schedules(params: Any) -> Any:
    """Optimiser ``params`` (a dataclass) as a run checkpointed before schedules existed had
    them (the annealing's: stages)."""
    return dataclasses.replace(params, **fields_written_before(type(params).__name__, {}))


def run_fields(saved: dict[str, Any]) -> dict[str, Any]:
    """A black-box run checkpointed as a dict, before its dataclasses: ``phases`` (each a dict
    of ``params``, ``state``, ``best``, ``support``, ``start``), ``env_steps``, ``wall`` and
    ``rounds``; a dict from before phases holds one phase's params and state at its top."""
    phases = saved.get("phases") or [{"params": saved["params"], "state": saved["state"],
                                      "best": saved.get("best")}]
    return {"phases": [{"params": p["params"], "state": p["state"], "best": p.get("best"),
                        "support": p.get("support"), "start": p.get("start")} for p in phases],
            "env_steps": saved["env_steps"], "wall": saved["wall"], "rounds": saved["rounds"]}


def module_now(module: str, name: str) -> str:
    """Where class ``name`` of ``module``, as an older pickle names it, is now: under
    ``animat.`` (before the code moved there) and in the room it moved to (:data:`MOVED`)."""
    if module.split(".")[0] in ("envs", "learners", "experiments"):
        module = f"animat.{module}"
    return MOVED.get(f"{module}.{name}", MOVED.get(module, module))
