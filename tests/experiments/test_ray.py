"""Sweeps as Ray tasks, on a local single-node cluster the test starts."""

from pathlib import Path

import pytest

from animat.experiments.launch.config import validate
from animat.experiments.sweep import prepare, run_ray

ray = pytest.importorskip("ray")


def test_ray_sweep_runs_every_seed_into_its_folder(tmp_path):
    config = validate({
        "env": {"id": "Animat/FishSwim-v0", "kwargs": {"duration": 0.5}},
        "learner": {"name": "annealing", "params": {"chains": 8, "nodes": 4, "period": 0.5}},
        "budget": {"env_steps": 400}, "seed": 0}, "test")
    folders = prepare(config, [0, 1], tmp_path, ["test"])
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        results = run_ray(folders)
    finally:
        ray.shutdown()
    assert [r["status"] for r in results] == ["done", "done"]
    for folder in folders:
        assert (Path(folder) / "tb").exists() and (Path(folder) / "scalars.csv").exists()
