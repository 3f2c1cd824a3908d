"""The experiment launcher ``animat`` (:mod:`animat.experiments.cli`): configs, run folders, sweeps,
comparisons and the benchmark."""
