"""PPO checkpoints are data, written whole before they replace the last: a planted pickle in a
run folder never runs, a save that dies midway loses nothing, and an older version's pickled
checkpoint loads only when the caller says it trusts the folder."""

import json
import pickle
import shutil
from types import SimpleNamespace

import pytest
import torch

from animat.learners.logger import Logger, MemorySink
from animat.learners.ppo import checkpoint as ppo_checkpoint
from animat.learners.registry import make_learner
from animat.learners.storage.files import CorruptFile, read_json
from animat.learners.storage.pickles import UntrustedPickle
from tests.support.cli import animat, write_config
from tests.support.faults import Crash, CrashingSink, Planted

PARAMS = {"n_envs": 4, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "eval_every": 64,
          "checkpoint_every": 64, "policy_kwargs": "dict(net_arch=[16])",
          "normalize": "{'norm_obs': True, 'norm_reward': False}"}
CONFIG = {"env": {"id": "Animat/FishSwim-v0", "kwargs": {"duration": 0.5}},
          "learner": {"name": "ppo", "params": PARAMS}, "budget": {"env_steps": 192},
          "eval": {"metric": "eval/return"}}


def _learner():
    return make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, PARAMS, seed=0)


def test_a_checkpoint_is_data_and_one_folder(tmp_path):
    _learner().learn(192, tmp_path)
    saved = ppo_checkpoint.latest(tmp_path)
    assert sorted(p.name for p in (tmp_path / "ppo").iterdir()) == ["latest.json", saved.name]
    assert sorted(p.name for p in saved.iterdir()) == ["normalize.npz", "optimizer.pt",
                                                       "policy.pt", "resume.json", "state.json"]
    state = torch.load(saved / "policy.pt", weights_only=True)  # tensors only
    assert all(isinstance(v, torch.Tensor) for v in state.values())
    assert read_json(saved / "state.json")["num_timesteps"] == 192


def test_a_planted_pickle_in_a_run_folder_never_runs(tmp_path):
    """In each file a run folder's checkpoint reads (the weights, the normalisation's .npz),
    under animat eval, run --resume and compare (eval plays the policy back without reading
    the optimiser's state: a planted optimizer.pt is not opened there)."""
    folder = tmp_path / "run"
    animat("run", write_config(tmp_path / "ppo.yaml", CONFIG), "--out", folder, "--quiet")
    status = json.loads((folder / "result.json").read_text())
    saved = ppo_checkpoint.latest(folder / "checkpoints")
    marker = tmp_path / "pwned"
    commands = {"done": ["eval", folder, "--episodes", "1"],  # what each may open
                "failed": ["run", "--resume", folder, "--quiet"]}
    for name in ("policy.pt", "optimizer.pt", "normalize.npz"):
        original = (saved / name).read_bytes()
        (saved / name).write_bytes(pickle.dumps(Planted(marker), protocol=2))
        for run_status, command in commands.items():
            (folder / "result.json").write_text(json.dumps({**status, "status": run_status}))
            refused = animat(*command, check=False)
            if name == "optimizer.pt" and run_status == "done":
                assert refused.returncode == 0  # played back from the policy alone
                continue
            code = 2 if command[0] == "eval" else 1  # the folder given; the run's failure
            assert refused.returncode == code and len(refused.stderr.strip().splitlines()) == 1
            assert f"{saved / name}: not " in refused.stderr and "\x1b" not in refused.stderr
        assert animat("compare", folder, check=False).returncode == 0
        assert not marker.exists()
        (saved / name).write_bytes(original)
    (folder / "result.json").write_text(json.dumps(status))
    animat("eval", folder, "--episodes", "1")  # the genuine checkpoint loads


def test_a_checkpoint_that_is_not_one_is_named_in_one_line(tmp_path):
    """A state.json short of a field, a resume.json whose observation does not fit the envs,
    a pointer out of the checkpoints, and another folder beside them."""
    _learner().learn(128, tmp_path)
    saved = ppo_checkpoint.latest(tmp_path)
    state = read_json(saved / "state.json")
    (saved / "state.json").write_text(json.dumps({k: v for k, v in state.items()
                                                  if k != "n_updates"}))
    with pytest.raises(CorruptFile, match="state.json: not a checkpoint's state"):
        _learner().learn(256, tmp_path)
    (saved / "state.json").write_text(json.dumps(state))
    resume = json.loads((saved / "resume.json").read_text())
    memory = resume["run"]["last_obs"][""]["memory"]
    memory["shape"], memory["data"] = [2, 150], memory["data"][:300]
    (saved / "resume.json").write_text(json.dumps(resume))
    with pytest.raises(CorruptFile, match="resume.json: not this run's state .*observation"):
        _learner().learn(256, tmp_path)
    pointer = tmp_path / "ppo" / "latest.json"
    for name in ("..", "save-000001.partial", "elsewhere"):
        pointer.write_text(json.dumps({"folder": name}))
        with pytest.raises(CorruptFile, match="names no checkpoint of this run"):
            ppo_checkpoint.latest(tmp_path)
    (tmp_path / "ppo" / "save-old").mkdir()
    pointer.unlink()
    assert _learner().learn(128, tmp_path / "fresh").env_steps == 128
    shutil.copytree(tmp_path / "ppo" / "save-old", tmp_path / "fresh" / "ppo" / "save-old")
    assert _learner().learn(192, tmp_path / "fresh").env_steps == 192  # saved beside it


def test_a_save_that_dies_midway_leaves_the_last_checkpoint_whole(tmp_path, monkeypatch):
    learner = _learner()
    learner.learn(128, tmp_path)
    before = ppo_checkpoint.latest(tmp_path)
    real_save, calls = torch.save, []

    def dying(obj, path, *args, **kwargs):
        calls.append(path)
        if len(calls) == 2:  # the policy written, the optimiser not: a kill here
            raise KeyboardInterrupt
        return real_save(obj, path, *args, **kwargs)

    monkeypatch.setattr(torch, "save", dying)
    with pytest.raises(KeyboardInterrupt):
        _learner().learn(256, tmp_path)
    monkeypatch.setattr(torch, "save", real_save)
    assert ppo_checkpoint.latest(tmp_path) == before  # still the complete one
    assert read_json(before / "state.json")["num_timesteps"] == 128
    resumed = _learner().learn(256, tmp_path)
    assert resumed.env_steps == 256
    assert [p.name for p in (tmp_path / "ppo").iterdir() if p.name != "latest.json"] == [
        ppo_checkpoint.latest(tmp_path).name]  # the half-written one is gone


def test_an_older_pickled_checkpoint_needs_trust_and_a_corrupt_pointer_is_named(tmp_path):
    folder = tmp_path / "run"
    animat("run", write_config(tmp_path / "ppo.yaml", CONFIG), "--out", folder, "--quiet")
    checkpoints = folder / "checkpoints"
    (checkpoints / "model.zip").write_bytes(b"an older version's pickled model")
    (checkpoints / "ppo" / "latest.json").unlink()
    with pytest.raises(UntrustedPickle, match="pass --trust-pickles"):
        _learner().agent({}, folder)
    refused = animat("eval", folder, "--episodes", "1", check=False)
    assert refused.returncode == 1 and "--trust-pickles" in refused.stderr
    (checkpoints / "ppo" / "latest.json").write_text(json.dumps({"folder": "../../elsewhere"}))
    with pytest.raises(CorruptFile, match="names no checkpoint of this run"):
        ppo_checkpoint.latest(checkpoints)
    (checkpoints / "ppo" / "latest.json").write_text('{"folder": "save-0')
    with pytest.raises(CorruptFile, match="not valid JSON"):
        ppo_checkpoint.latest(checkpoints)


def _numbers(sink: MemorySink, after: int) -> list:
    """What a run logged after env step ``after``, but the wall-clock ``time/*``."""
    return [r for r in sink.records if r[2] > after and not r[0].startswith("time/")]


# the fish's native batch (normalised), the pursuit's native batch of worlds (pixels, a Dict
# space, the state replayed from how the episodes began; and its compact pixels stacked over
# frames, through RetinaCNN), and single envs replayed (the living world, its oracle's vector)
PIXELS = {**PARAMS, "policy": "MultiInputPolicy", "n_envs": 2, "n_steps": 8, "batch_size": 16,
          "eval_every": 32, "checkpoint_every": 16,
          "policy_kwargs": "dict(net_arch=[8], features_extractor_kwargs={'cnn_output_dim': 8})"}
COMPACT = {"duration": 0.6, "frames": 3, "sensors": [
    {"name": "pixels", "levels": [0, 3], "size": 16}, "gaze", "proprioception"]}
RETINA_CNN = {**PIXELS, "policy_kwargs": "dict(features_extractor_class=RetinaCNN, net_arch=[8]"
              ", features_extractor_kwargs=dict(cnn_output_dim=8, channels=(4, 4, 4)))"}
FUSED_ADAM = RETINA_CNN["policy_kwargs"].replace(
    "dict(", "dict(optimizer_kwargs=dict(eps=1e-5, fused=True), ", 1)
RESUMED = {"native": ("Animat/FishSwim-v0", {"duration": 0.5}, PARAMS, 192, [64, 100, 130]),
           "pursuit": ("Animat/FishPursuit-v0", {"duration": 0.6}, PIXELS, 64, [16, 40]),
           "compact pixels": ("Animat/FishPursuit-v0", COMPACT, RETINA_CNN, 64, [16, 40]),
           "updated on two threads by fused Adam": (
               "Animat/FishPursuit-v0", COMPACT, {**RETINA_CNN, "update_threads": 2,
                                                  "policy_kwargs": FUSED_ADAM}, 64, [16, 40]),
           "replayed": ("Animat/MarineWorld-v0", {"duration": 0.6}, {
               **PIXELS, "policy": "MlpPolicy", "policy_kwargs": "dict(net_arch=[8])"}, 64,
               [16, 40])}


@pytest.mark.parametrize("kind", RESUMED)
def test_a_crashed_ppo_run_resumes_to_the_same_floats(tmp_path, kind):
    """Killed anywhere (here: in a rollout, in an evaluation, at the end), a run resumed from
    its last checkpoint logs and ends with exactly the uninterrupted run's numbers: the envs'
    state, the random generators and SB3's pending records are in the checkpoint."""
    env_id, env_kwargs, params, budget, crashes = RESUMED[kind]

    def run(folder, sink):
        learner = make_learner("ppo", env_id, env_kwargs, params, seed=3, logger=Logger([sink]))
        return learner.learn(budget, folder)

    whole_sink = MemorySink()
    whole = run(None, whole_sink)
    for crash in crashes:
        folder = tmp_path / f"crash{crash}"
        with pytest.raises(Crash):
            run(folder, CrashingSink(crash))
        saved = read_json(ppo_checkpoint.latest(folder) / "state.json")["num_timesteps"]
        assert saved <= crash
        sink = MemorySink()
        resumed = run(folder, sink)
        assert resumed.metrics == whole.metrics  # bit for bit
        assert resumed.env_steps == whole.env_steps == budget
        assert _numbers(sink, saved) == _numbers(whole_sink, saved)


def test_a_step_is_evaluated_once_and_the_last_with_the_policy_returned():
    """A budget that ends on an evaluation step: the step's eval/* are logged once, by the
    evaluation of the policy the run returns (not also by the one before its last update)."""
    sink = MemorySink()
    learner = make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, PARAMS, seed=0,
                           logger=Logger([sink]))
    result = learner.learn(192)
    assert sink.series("eval/return")[-1:] == [(192, result.metrics["eval/return"])]
    steps = [step for step, _ in sink.series("eval/return")]
    assert steps == [64, 128, 192]


def test_a_checkpoint_without_its_resume_state_goes_on_and_says_so(tmp_path, capsys):
    """An older version's checkpoint (no resume.json) resumes from fresh episodes, with a
    one-line warning naming the checkpoint."""
    _learner().learn(128, tmp_path)
    saved = ppo_checkpoint.latest(tmp_path)
    (saved / ppo_checkpoint.RESUME).unlink()
    capsys.readouterr()
    result = _learner().learn(256, tmp_path)
    warning = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(warning) == 1 and f"{saved}: no resume.json" in warning[0]
    assert read_json(ppo_checkpoint.latest(tmp_path) / "state.json")["num_timesteps"] == 256
    assert result.metrics


def test_a_run_plays_back_from_its_policy_and_statistics_alone(tmp_path):
    """What a shipped run folder keeps of a PPO checkpoint (the policy's weights, the
    observation statistics, the state; no optimiser, no resume state) plays the same episodes
    as the whole checkpoint."""
    from animat.experiments.evaluate import evaluate

    folder = tmp_path / "run"
    animat("run", write_config(tmp_path / "ppo.yaml", CONFIG), "--out", folder, "--quiet")
    whole = evaluate(folder, episodes=2)["metrics"]
    saved = ppo_checkpoint.latest(folder / "checkpoints")
    for name in ("optimizer.pt", "resume.json"):
        (saved / name).unlink()
    assert evaluate(folder, episodes=2)["metrics"] == whole


def test_truncated_normalisation_statistics_are_named_in_one_line(tmp_path):
    import numpy as np

    path = tmp_path / "normalize.npz"
    np.savez(path, **{"obs:mean": np.zeros(3), "obs:var": np.ones(3)})
    path.write_bytes(path.read_bytes()[:40])  # a zip cut short
    with pytest.raises(CorruptFile, match="normalize.npz: not the run's normalisation") as error:
        ppo_checkpoint._restore_stats(None, path)
    assert len(str(error.value).splitlines()) == 1


def test_weights_behind_a_link_are_refused_not_read(tmp_path):
    from animat.learners.storage.files import UnsafeFile

    (tmp_path / "outside.pt").write_bytes(b"x")
    (tmp_path / "save").mkdir()
    (tmp_path / "save" / "policy.pt").symlink_to(tmp_path / "outside.pt")
    with pytest.raises(UnsafeFile, match="policy.pt: is a symbolic link"):
        ppo_checkpoint.restore(SimpleNamespace(policy=None), None, tmp_path / "save",
                               with_optimizer=False)
