"""Black-box checkpoints are data: written as JSON and read back without pickle, bit for bit;
a file naming a type it may not hold is refused; an older version's pickled checkpoint is read
only when the caller trusts the folder."""

import json
import pickle

import numpy as np
import pytest

from animat.learners.blackbox_run import CHECKPOINT_TYPES
from animat.learners.registry import make_learner
from animat.learners.storage import checkpoint_data
from animat.learners.storage.files import CorruptFile
from animat.learners.storage.pickles import UntrustedPickle, save_checkpoint
from tests.support.cli import TINY, animat, write_config
from tests.support.faults import Planted

ENV, KWARGS = "Animat/FishSwim-v0", {"duration": 0.5}
REFINE = {"nodes": 4, "checkpoint_every": 1, "refine": {"share": 0.4}}


@pytest.mark.parametrize("name, params", [("annealing", {"chains": 8}),
                                          ("cmaes", {"popsize": 8})])
def test_a_run_round_trips_as_data_bit_for_bit(tmp_path, name, params):
    make_learner(name, ENV, KWARGS, {**REFINE, **params}, seed=2).learn(4800, tmp_path)
    path = tmp_path / "checkpoint.json"
    text = path.read_text()
    run = checkpoint_data.load(path, CHECKPOINT_TYPES)
    assert len(run.phases) == 2 and run.phases[1].support is not None  # learned, refined
    checkpoint_data.save(tmp_path / "again.json", run)
    assert (tmp_path / "again.json").read_text() == text
    assert not (tmp_path / "checkpoint.pkl").exists()


def test_annealing_params_from_before_schedules_keep_the_stages_they_ran_with(tmp_path):
    from animat.learners.optimizers.annealing import AnnealingParams

    data = checkpoint_data.to_data(AnnealingParams(chains=8))
    del data["schedule"], data["rounds"]  # as a checkpoint written before them
    assert checkpoint_data.from_data(data, CHECKPOINT_TYPES).schedule == "stages"
    old = AnnealingParams(chains=8)
    state = dict(vars(old))
    del state["schedule"], state["rounds"]
    unpickled = AnnealingParams.__new__(AnnealingParams)
    unpickled.__setstate__(state)  # what pickle does with an older version's params
    assert unpickled.schedule == "stages" and unpickled.chains == 8


def test_a_run_from_before_schedules_refines_with_the_stages_it_learned_with(tmp_path):
    """Killed before its refinement, a run checkpointed before schedules existed resumes with
    stages in both phases, whatever its config's default."""
    params = {**REFINE, "chains": 8, "schedule": "stages", "period": 0.5}
    make_learner("annealing", ENV, KWARGS, params, seed=2).learn(960, tmp_path)
    path = tmp_path / "checkpoint.json"
    data = json.loads(path.read_text())
    run = data["run"]
    run["phases"], run["env_steps"], run["rounds"] = run["phases"][:1], 320, 1  # killed there
    del run["phases"][0]["params"]["schedule"], run["phases"][0]["params"]["rounds"]
    path.write_text(json.dumps(data))
    unpinned = {k: v for k, v in params.items() if k != "schedule"}
    make_learner("annealing", ENV, KWARGS, unpinned, seed=2).learn(4800, tmp_path)
    run = checkpoint_data.load(path, CHECKPOINT_TYPES)
    assert len(run.phases) == 2
    assert [phase.params.schedule for phase in run.phases] == ["stages", "stages"]


def test_a_checkpoint_naming_another_type_or_an_object_array_is_refused(tmp_path):
    path = tmp_path / "checkpoint.json"
    for run in ({"__type__": "Popen", "args": ["touch", str(tmp_path / "pwned")]},
                {"__array__": "|O", "shape": [1], "data": ["x"]}):
        path.write_text(json.dumps({"format": checkpoint_data.FORMAT, "run": run}))
        with pytest.raises(CorruptFile, match="cannot be read back"):
            checkpoint_data.load(path, CHECKPOINT_TYPES)
    assert checkpoint_data.from_data(checkpoint_data.to_data(np.array([np.inf, np.nan])), {})[0] \
        == np.inf


def test_an_older_pickled_checkpoint_is_read_only_when_trusted(tmp_path):
    data = json.loads(json.dumps(TINY))
    data["learner"]["params"]["checkpoint_every"] = 1
    config = write_config(tmp_path / "tiny.yaml", data)
    folder = tmp_path / "run"
    animat("run", config, "--out", folder, "--quiet")
    checkpoints, marker = folder / "checkpoints", tmp_path / "pwned"
    status = json.loads((folder / "result.json").read_text())
    (folder / "result.json").write_text(json.dumps({**status, "status": "failed"}))
    (checkpoints / "checkpoint.json").unlink()
    (checkpoints / "checkpoint.pkl").write_bytes(pickle.dumps(Planted(marker)))
    refused = animat("run", "--resume", folder, check=False)
    assert refused.returncode == 1 and "pass --trust-pickles" in refused.stderr
    assert not marker.exists()
    with pytest.raises(UntrustedPickle):
        make_learner("annealing", ENV, KWARGS, TINY["learner"]["params"])._saved(checkpoints)
    learner = make_learner("annealing", ENV, KWARGS, {**TINY["learner"]["params"],
                                                      "checkpoint_every": 1})
    genuine = tmp_path / "genuine"
    learner.learn(1600, genuine)
    # what an older version wrote: a pickle of the run
    save_checkpoint(checkpoints / "checkpoint.pkl", checkpoint_data.load(
        genuine / "checkpoint.json", CHECKPOINT_TYPES))
    animat("run", "--resume", folder, "--trust-pickles", "--quiet")
    assert json.loads((folder / "result.json").read_text())["status"] == "done"
    assert not (checkpoints / "checkpoint.json").exists()  # a trusted older run goes on pickling


def test_a_cma_es_replay_that_asks_other_candidates_is_refused_and_old_states_still_tell(
        tmp_path):
    from animat.learners.optimizers import cmaes

    make_learner("cmaes", ENV, KWARGS, {"nodes": 4, "popsize": 8, "checkpoint_every": 1},
                 seed=2).learn(1600, tmp_path)
    state = checkpoint_data.load(tmp_path / "checkpoint.json", CHECKPOINT_TYPES).phases[0].state
    assert len(state.asked) == len(state.told) > 1
    cmaes.strategy(state)  # replays as the run asked
    state.es, state.options = None, {**state.options, "seed": state.options["seed"] + 1}
    with pytest.raises(ValueError, match="does not replay"):
        cmaes.strategy(state)
    old = object.__new__(cmaes.CMAESState)  # an older version's pickled state: only its es
    params = cmaes.CMAESParams(popsize=4)
    old.es = cmaes.init(params, np.full(3, 0.5), 0).es
    candidates, old = cmaes.ask(params, old)
    cmaes.tell(params, old, candidates, np.arange(4.0))
    assert not hasattr(old, "told")


def test_an_older_pickle_naming_a_module_before_the_move_still_loads(tmp_path):
    """A trusted older checkpoint names ``learners.annealing`` (before the package moved under
    ``animat.`` and the optimisers into their room): the unpickler finds the class where it is
    now."""
    from animat.learners.optimizers.annealing import AnnealingParams
    from animat.learners.storage.pickles import load_checkpoint

    text = pickle.dumps(AnnealingParams(chains=3), protocol=2)
    assert b"animat.learners.optimizers.annealing" in text
    old = text.replace(b"animat.learners.optimizers.annealing", b"learners.annealing")
    (tmp_path / "checkpoint.pkl").write_bytes(old)
    assert load_checkpoint(tmp_path / "checkpoint.pkl") == AnnealingParams(chains=3)
