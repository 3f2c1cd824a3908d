"""The paper's learners (simulated annealing, FFT abstraction, basic training, macro
controllers) and the baselines (CMA-ES, PPO), by name in :mod:`animat.learners.registry`.

Rooms: :mod:`.optimizers`, :mod:`.controllers`, :mod:`.ppo`, :mod:`.scorers`, :mod:`.storage`,
:mod:`.skills`; beside them the interface (:mod:`.base`), the black-box loop and the learners on
it. May import :mod:`animat.envs` (its public names); never :mod:`animat.experiments`.
"""
