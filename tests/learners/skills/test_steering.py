"""The closed-loop maneuver's rules (animat.learners.skills.steering): which skill each goal
chooses, how a turn goes on and ends, and what it plays."""

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from animat.learners.controllers.repertoire import Repertoire
from animat.learners.skills.steering import (
    REST,
    TABLE_SHAPE,
    SkillSteering,
    SteeringAgent,
    SteeringParams,
    repertoire_moves,
)

REPERTOIRE = Repertoire.load(Path(__file__).resolve().parents[3] / "repertoires"
                             / "fish_reactive.json")
DT = 0.05


def steering(**rules) -> SkillSteering:
    return SkillSteering(REPERTOIRE, SteeringParams(**rules), DT)


def name(index: int) -> str:
    return "rest" if index == REST else REPERTOIRE.names[index]


def bearing(deg: float, distance: float = 2.5) -> list[float]:
    return [distance * np.cos(np.radians(deg)), distance * np.sin(np.radians(deg)), 0.0]


def test_the_goal_chooses_the_skill():
    s = steering(turn_above_deg=30.0, arrive_bl=0.3, slow_within_bl=1.0, fast_beyond_bl=3.0)
    goals = np.array([bearing(0, 5.0), bearing(10, 2.0), bearing(-5, 0.8), bearing(0, 0.2),
                      bearing(100), bearing(-50), bearing(170), bearing(-160, 0.1)])
    s.reset(len(goals))
    assert [name(k) for k in s.choose(goals)] == [
        "swim_fast", "swim_medium", "swim_slow", "rest",
        "turn_left_90", "turn_right_45", "turn_left_180", "rest"]


def test_a_turn_under_way_goes_on_until_the_goal_is_within_turn_below():
    s = steering(turn_above_deg=40.0, turn_below_deg=10.0, interval_s=DT)
    s.reset(1)
    s.act(np.array([bearing(90)]))
    turn = s.skill[0]
    assert name(turn) == "turn_left_90"
    s.act(np.array([bearing(20)]))  # below turn_above, above turn_below: the turn goes on
    assert s.skill[0] == turn and s.clock[0] == 2
    s.act(np.array([bearing(5)]))  # below turn_below: a swim
    assert name(s.skill[0]).startswith("swim") and s.clock[0] == 1


def test_a_turn_played_to_its_end_rests_then_starts_again():
    s = steering(interval_s=1.0, turn_for_s=0.5)
    s.reset(1)
    goal = np.array([bearing(-90)])
    played = [s.act(goal)[0] for _ in range(20)]  # 1 s: decisions at steps 0 and 20
    assert name(s.skill[0]) == "turn_right_90"
    assert np.all(np.asarray(played[10:]) == -1.0)  # after 0.5 s of the turn: relaxed
    assert not np.all(np.asarray(played[:10]) == -1.0)
    s.act(goal)
    assert s.clock[0] == 1  # chosen again once it had played: from its beginning


def test_actions_are_the_skills_activations_as_the_env_plays_them():
    s = steering(interval_s=10.0)
    s.reset(2)
    goals = np.array([bearing(0, 5.0), bearing(0, 0.1)])
    actions = np.array([s.act(goals) for _ in range(30)])  # (T, B, A)
    assert actions.shape == (30, 2, 6) and actions.dtype == np.float32
    fast = REPERTOIRE["swim_fast"].controller
    expected = 2.0 * np.clip(fast(DT * np.arange(1, 31)), 0, 1) - 1
    np.testing.assert_allclose(actions[:, 0], expected, atol=1e-6)
    assert np.all(actions[:, 1] == -1.0)  # resting at the goal


def test_the_agent_steers_by_the_reach_envs_goal():
    env = gym.make("Animat/FishReach-v0", distance_bl=(3.0, 3.0), bearing_deg=(-90.0, -90.0))
    agent = SteeringAgent(SkillSteering(REPERTOIRE, SteeringParams(), env.unwrapped.dt))
    obs, _ = env.reset(seed=0)
    action, _ = agent.predict(obs)
    assert env.action_space.contains(action)
    assert name(agent.steering.skill[0]).startswith("turn_right")


@pytest.mark.parametrize("rules, message", [
    ({"turn_below_deg": 50.0, "turn_above_deg": 30.0}, "turn_below_deg <= turn_above_deg"),
    ({"arrive_bl": 2.0, "slow_within_bl": 1.0}, "arrive_bl <= slow_within_bl"),
    ({"interval_s": 0.0}, "interval_s must be > 0"),
    ({"turn_for_s": -1.0}, "turn_for_s must be > 0"),
])
def test_rules_that_cannot_work_are_refused_in_one_line(rules, message):
    with pytest.raises(ValueError, match=message) as error:
        SteeringParams(**rules)
    assert "\n" not in str(error.value)


def test_a_repertoire_without_turns_to_both_sides_is_refused_naming_what_it_lacks():
    swims_only = Repertoire([REPERTOIRE[n] for n in REPERTOIRE.names if "right" not in n])
    with pytest.raises(ValueError, match="needs a right turn in the repertoire"):
        repertoire_moves(swims_only)


def test_a_table_of_moves_chooses_by_the_goals_cell_and_turns_toward_it():
    s = steering()
    moves = [name(left) for left, _ in s.moves]
    assert moves == ["rest", "swim_slow", "swim_medium", "swim_fast", "turn_left_45",
                     "turn_left_90", "turn_left_180"]
    table = np.zeros(TABLE_SHAPE, dtype=int)
    table[0, 3] = 3  # ahead (|bearing| < 30 deg), beyond 4 BL: swim fast
    table[2, 1] = 5  # |bearing| 60-90 deg, 1-2 BL: the 90 deg turn toward the goal
    s = SkillSteering(REPERTOIRE, SteeringParams(), DT, table)
    s.reset(4)
    goals = np.array([bearing(10, 5.0), bearing(70, 1.5), bearing(-70, 1.5), bearing(70, 3.0)])
    assert [name(k) for k in s.choose(goals)] == [
        "swim_fast", "turn_left_90", "turn_right_90", "rest"]


@pytest.mark.parametrize("table", [np.zeros((6, 3), int), np.full(TABLE_SHAPE, 7),
                                   np.full(TABLE_SHAPE, 0.5)])
def test_a_table_that_is_not_one_is_refused_in_one_line(table):
    with pytest.raises(ValueError, match="a table of moves must be integers in") as error:
        SkillSteering(REPERTOIRE, SteeringParams(), DT, table)
    assert "\n" not in str(error.value)


@pytest.mark.parametrize("table", [None, np.full(TABLE_SHAPE, 3)])
def test_a_fish_whose_goal_is_not_finite_rests_and_the_others_steer_on(table):
    s = SkillSteering(REPERTOIRE, SteeringParams(), DT, table)
    s.reset(3)
    goals = np.array([bearing(0, 5.0), [np.nan, np.nan, np.nan], [np.inf, 0.0, 0.0]])
    assert [name(k) for k in s.choose(goals)] == ["swim_fast", "rest", "rest"]
    assert np.isfinite(s.act(goals)).all()
