"""The paper's learners (simulated annealing, FFT abstraction, basic training, macro
controllers) and the baselines (CMA-ES, PPO), by name in :mod:`animat.learners.registry`."""
