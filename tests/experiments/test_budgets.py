"""Every shipped config runs at any budget a user sets: every budget inside a learner is a
share of ``budget.env_steps`` (refinement, skills, rounds), a population one round cannot
afford shrinks to what it can, and what cannot work at all is refused before a run folder
exists."""

import json
from pathlib import Path

import pytest

from animat.experiments.launch.config import ConfigError, load_config
from tests.support.cli import animat

ROOT = Path(__file__).resolve().parents[2]
CONFIGS = sorted((ROOT / "configs").rglob("*.yaml"))
# cheap enough to run at 20 k env steps in CI (the pursuit's PPO at 20 k takes minutes of
# rendering; it is validated at both budgets below); the active-vision pursuit scores its 16
# episodes whatever the budget (75 s), among the slow checks
CHEAP = ["quickstart.yaml", "fish_swim/annealing.yaml", "fish_swim/cmaes.yaml",
         "fish_swim/handmc.yaml", "fish_swim/ppo.yaml", "fish_reach/macro.yaml",
         "fish_basic_training/default.yaml",
         pytest.param("fish_pursuit/active_vision.yaml", marks=pytest.mark.slow),
         "dolphin/basic_training.yaml", "dolphin/leap_macro.yaml", "dolphin/nose_ball_macro.yaml",
         "dolphin/leap_ppo.yaml"]


@pytest.mark.parametrize("budget", [20_000, 600_000])
def test_every_shipped_config_validates_at_small_and_large_budgets(budget):
    for path in CONFIGS:
        assert load_config(path, [f"budget.env_steps={budget}"]).budget.env_steps == budget


def shipped_files() -> dict[str, bytes]:
    """Every shipped config and repertoire, by path: what no run may change."""
    return {p.relative_to(ROOT).as_posix(): p.read_bytes()
            for folder in ("configs", "repertoires") for p in sorted((ROOT / folder).rglob("*"))
            if p.is_file()}


@pytest.mark.parametrize("name", CHEAP)
def test_cheap_shipped_configs_run_at_20k_env_steps_and_change_no_shipped_file(tmp_path, name):
    out, before = tmp_path / "run", shipped_files()
    animat("run", ROOT / "configs" / name, "--out", out, "--quiet", "--set",
           "budget.env_steps=20000")
    result = json.loads((out / "result.json").read_text())
    assert result["status"] == "done" and 0 < result["env_steps"] <= 20_000
    assert shipped_files() == before


def test_a_budget_below_one_round_is_refused_in_one_line_with_no_folder(tmp_path):
    config = ROOT / "configs" / "fish_swim" / "annealing.yaml"
    with pytest.raises(ConfigError, match="budget.env_steps: 300 is less than one round"):
        load_config(config, ["budget.env_steps=300"])
    out = tmp_path / "run"
    result = animat("run", config, "--set", "budget.env_steps=300", "--out", out, check=False)
    assert result.returncode == 2 and len(result.stderr.strip().splitlines()) == 1
    assert not out.exists()
