"""The paper's 10-fish scenario through the launcher: ``animat run
configs/marine_world/behaviours.yaml`` runs 4 seeded minutes of the world with every fish on its
behaviours, logs the world's figures with the shared tags, and no fish hits an obstacle while
food is eaten."""

import csv
import json
from pathlib import Path

from tests.support.cli import animat

ROOT = Path(__file__).resolve().parents[2]
TAGS = ("eval/food_eaten", "eval/obstacle_collisions", "eval/fish_collisions",
        "eval/school_cohesion_bl", "eval/catches", "eval/matings")


def test_the_ten_fish_scenario_runs_a_minute_without_obstacle_collisions_and_fish_eat(tmp_path):
    out = tmp_path / "run"
    animat("run", ROOT / "configs" / "marine_world" / "behaviours.yaml", "--out", out, "--quiet")
    result = json.loads((out / "result.json").read_text())
    metrics = result["metrics"]
    assert result["status"] == "done" and result["env_steps"] == 4 * 1200
    assert metrics["eval/obstacle_collisions"] == 0.0, metrics
    assert metrics["eval/food_eaten"] - metrics["eval/food_eaten_std"] > 5.0, metrics
    with open(out / "scalars.csv") as file:
        logged = {row[1] for row in csv.reader(file)}
    assert set(TAGS) <= logged, logged


def test_the_world_in_the_paper_s_water_runs_without_obstacle_collisions_and_fish_eat(tmp_path):
    """The same scenario in the paper's (resistive) water, the fishes' MCs calibrated for it
    (measured: 20.0 +- 1.2 food eaten, 0 obstacle collisions, 13.0 fish collisions; the default
    reactive water 25.5, 0 and 20.0)."""
    out = tmp_path / "run"
    animat("run", ROOT / "configs" / "marine_world" / "behaviours.yaml", "--set",
           "env.kwargs={duration: 60.0, water: {model: resistive}}", "--out", out, "--quiet")
    metrics = json.loads((out / "result.json").read_text())["metrics"]
    assert metrics["eval/obstacle_collisions"] == 0.0, metrics
    assert metrics["eval/food_eaten"] - metrics["eval/food_eaten_std"] > 5.0, metrics


def test_the_behaviours_learner_refuses_an_env_whose_fish_do_not_live_by_behaviours(tmp_path):
    result = animat("run", ROOT / "configs" / "marine_world" / "behaviours.yaml", "--set",
                    "env.id=Animat/FishSwim-v0", "--set", "env.kwargs={}", "--out",
                    tmp_path / "run", check=False)
    assert result.returncode != 0 and "behaviour" in result.stderr, result.stderr
