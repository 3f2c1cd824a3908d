"""The experiment launcher ``animat`` (:mod:`experiments.cli`): configs, run folders, sweeps,
comparisons and the benchmark."""
