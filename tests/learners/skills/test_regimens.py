"""The shipped regimens of basic training: every skill's learner builds from its params and
can spend a shipped config's share of the budget; the paper's-way regimens learn every skill
by annealing."""

import pytest

from animat.learners.registry import make_learner
from animat.learners.skills.regimens import REGIMENS


@pytest.mark.parametrize("name", sorted(REGIMENS))
def test_every_shipped_regimen_builds_and_affords_two_million_env_steps_a_skill(name):
    learner = make_learner("basic_training", "Animat/FishSwim-v0", {},
                           {"regimen": name, "annealing": {"chains": 64, "init": "half"}})
    learner.check_budget(2_000_000 * len(REGIMENS[name]))  # a bad param raised on building


def test_the_refined_turns_anneal_then_refine_on_their_worst_starts_and_the_swims_stay():
    fish, refined = REGIMENS["fish"], REGIMENS["fish_refined_turns"]
    assert [s["name"] for s in refined] == [s["name"] for s in fish]
    for plain, spec in zip(fish, refined):
        if spec["env_id"] == "Animat/FishTurn-v0":
            assert spec["env_kwargs"] == plain["env_kwargs"] and "learner" not in spec
            assert spec["params"]["refine"]["share"] == 0.5
            assert spec["params"]["worst_share"] == 0.5
        else:
            assert spec == plain


def test_the_dolphins_annealing_regimen_is_its_five_basic_tasks_all_annealed():
    skills = REGIMENS["dolphin_annealing"]
    assert [s["name"] for s in skills] == ["move_forward", "turn_down", "turn_up", "turn_left",
                                           "turn_right"]
    assert all("learner" not in s for s in skills)
    dolphin = {s["name"]: s for s in REGIMENS["dolphin"]}
    assert all(s["env_kwargs"] == dolphin[s["name"]]["env_kwargs"] for s in skills)
