"""PPO's hyperparameters take rl-baselines3-zoo's own values as its YAML files write them."""

import pytest
import torch.nn as nn

from animat.learners.ppo.zoo import normalize_kwargs, policy_kwargs, schedule
from animat.learners.registry import make_learner

ZOO = {  # rl-baselines3-zoo's hyperparams/ppo.yml style, as written there
    "n_envs": 2, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "gamma": 0.999,
    "learning_rate": "lin_3e-4", "clip_range": "lin_0.2",
    "normalize": "{'norm_obs': True, 'norm_reward': False}",
    "policy_kwargs": "dict(log_std_init=-2, ortho_init=False, activation_fn=nn.Tanh, "
                     "net_arch=dict(pi=[32, 32], vf=[32, 32]))",
}


def test_the_zoo_value_forms_parse_to_what_sb3_takes():
    kwargs = policy_kwargs(ZOO["policy_kwargs"])
    assert kwargs["activation_fn"] is nn.Tanh and kwargs["net_arch"] == {"pi": [32, 32],
                                                                          "vf": [32, 32]}
    assert kwargs["log_std_init"] == -2 and kwargs["ortho_init"] is False
    rate = schedule("lin_3e-4")
    assert rate(1.0) == pytest.approx(3e-4) and rate(0.5) == pytest.approx(1.5e-4)
    assert schedule(1e-3) == 1e-3
    assert normalize_kwargs(ZOO["normalize"]) == {"norm_obs": True, "norm_reward": False}
    assert normalize_kwargs(True) == {} and normalize_kwargs(False) is None


def test_ppo_learns_with_zoo_values_and_uses_them(tmp_path):
    from animat.learners.ppo import checkpoint as ppo_checkpoint

    learner = make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, ZOO)
    result = learner.learn(64, tmp_path)
    assert result.env_steps == 64
    model = learner._model(learner._venv())  # rebuilt from the params, then given the weights
    ppo_checkpoint.restore(model, learner._venv(), ppo_checkpoint.latest(tmp_path))
    assert isinstance(model.policy.mlp_extractor.policy_net[1], nn.Tanh)
    assert model.lr_schedule(0.5) == pytest.approx(1.5e-4)
    assert model.gamma == 0.999


@pytest.mark.parametrize("params, message", [
    ({"learning_rate": "fast"}, "learning_rate: use a number or lin_<x>"),
    ({"policy_kwargs": "dict(activation_fn=os.system)"}, "is not allowed here"),
    ({"policy_kwargs": "__import__('os')"}, "is not allowed here"),
    ({"normalize": {"norm_everything": True}}, "unknown VecNormalize keys"),
    ({"n_timesteps": 1e6}, "n_timesteps is the run's budget here"),
    ({"n_epoch": 3}, "n_epoch: unknown parameter"),
    ({"n_envs": 0}, "n_envs: Input should be greater than or equal to 1"),
])
def test_bad_ppo_values_are_named(params, message):
    with pytest.raises(ValueError, match=message):
        make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, params)


def test_a_resumed_ppo_run_collects_exactly_its_budget(tmp_path, monkeypatch):
    """Checkpoints fall between rollouts, so the resumed run neither overruns its budget nor
    differs in length from the uninterrupted one."""
    from animat.learners.ppo import learner as ppo

    params = {"n_envs": 4, "n_steps": 16, "batch_size": 32, "n_epochs": 1, "eval_every": 1000,
              "checkpoint_every": 100}
    save = ppo.PPOLearner.save_checkpoint

    class Killed(Exception):
        pass

    def save_then_die(folder, model, venv, state, start):
        save(folder, model, venv, state, start)
        raise Killed

    monkeypatch.setattr(ppo.PPOLearner, "save_checkpoint", staticmethod(save_then_die))
    with pytest.raises(Killed):
        make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, params).learn(320, tmp_path)
    monkeypatch.setattr(ppo.PPOLearner, "save_checkpoint", staticmethod(save))
    from animat.learners.ppo.checkpoint import latest
    from animat.learners.storage.files import read_json

    assert read_json(latest(tmp_path) / "state.json")["num_timesteps"] % 64 == 0  # whole rollouts
    resumed = make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, params).learn(
        320, tmp_path)
    assert resumed.env_steps == 320


def test_torch_updates_on_update_threads_and_steps_the_envs_on_torch_threads(monkeypatch):
    """Torch's threads switch between the phases: ``update_threads`` while SB3 trains (the
    policy's ``evaluate_actions``), ``torch_threads`` while it acts in a rollout (its
    ``forward``) and once the run is done; unset, ``update_threads`` is ``torch_threads`` and
    the run's hyperparameters do not name it."""
    import torch
    from stable_baselines3.common.policies import ActorCriticPolicy

    seen: list[tuple[str, int]] = []

    def spy(name, method):
        def spied(self, *args, **kwargs):
            phase = (name, torch.get_num_threads())
            if not seen or seen[-1] != phase:
                seen.append(phase)
            return method(self, *args, **kwargs)
        return spied

    monkeypatch.setattr(ActorCriticPolicy, "forward", spy("act", ActorCriticPolicy.forward))
    monkeypatch.setattr(ActorCriticPolicy, "evaluate_actions",
                        spy("train", ActorCriticPolicy.evaluate_actions))
    before = torch.get_num_threads()
    try:
        params = {**ZOO, "torch_threads": 1, "update_threads": 2, "eval_every": 10**6}
        result = make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, params).learn(96)
        assert seen == [("act", 1), ("train", 2)] * 3
        assert torch.get_num_threads() == 1
        assert result.artefacts["hyperparameters"]["update_threads"] == 2
        seen.clear()
        unset = make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5}, ZOO).learn(64)
        assert set(seen) == {("act", 1), ("train", 1)}
        assert "update_threads" not in unset.artefacts["hyperparameters"]
    finally:
        torch.set_num_threads(before)


@pytest.mark.parametrize("threads", [0, -1, 1.5, "two"])
def test_update_threads_must_be_a_whole_number_of_threads(threads):
    with pytest.raises(ValueError, match="update_threads"):
        make_learner("ppo", "Animat/FishSwim-v0", {"duration": 0.5},
                     {**ZOO, "update_threads": threads})
