"""PPO (stable-baselines3), the modern baseline: the learner (what SB3 is handed as it learns
in :mod:`.hooks`), its checkpoints as data, the VecEnvs whose state is saved with them,
torch's threads beside the envs' (:mod:`.threads`), glibc's malloc set to keep what each
minibatch frees (:mod:`.allocator`),
rl-baselines3-zoo's hyperparameter forms.

May import :mod:`animat.envs` and the learners' interface (:mod:`animat.learners.base`,
validation, storage, rollout, agents, logger).
"""
