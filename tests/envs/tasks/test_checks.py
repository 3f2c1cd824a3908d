"""A task's argument checks are inherited, never replaced: ``Animat/DolphinTurn-v0`` refuses
the fish turn task's bad weights at construction (a NaN weight made every reward NaN), every
task refuses a non-finite, huge or non-numeric number for each of its numeric arguments, and
every task's ``__post_init__`` runs each of its ancestors' checks. Each refusal is a ValueError
of one line naming the argument."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import MISSING, fields

import gymnasium as gym
import pytest

import animat  # noqa: F401
from animat.envs.checks import is_real
from animat.envs.tasks import TASKS, make_task

NAN, INF = float("nan"), float("inf")
# values no numeric task argument takes: not finite, beyond any range, not a number
NOT_NUMBERS = [NAN, INF, -INF, 1e30, -1e30, "1.0", True, [1.0]]
# the fish turn task's weights, which the dolphin's turn inherits, and values out of range
WEIGHT_CASES = [(field, value)
                for field in ("path_weight", "final_weight", "settle_s")
                for value in (NAN, INF, -INF, -1.0, 1e30, "0.5", None)]


def _numeric_fields(task: type) -> list[str]:
    """The task's arguments whose default is a real number, or None (an optional number)."""
    return [f.name for f in fields(task)
            if f.default is not MISSING and (f.default is None or is_real(f.default))]


def _refused(make: Callable[[], object], field: str) -> str:
    """The message of the ValueError that ``make()`` raises, checked to be one line that
    names ``field``."""
    with pytest.raises(ValueError) as refusal:
        make()
    message = str(refusal.value)
    assert "\n" not in message and message.startswith(f"{field} must be"), message
    return message


@pytest.mark.parametrize("field, value", WEIGHT_CASES, ids=repr)
def test_dolphin_turn_refuses_the_fish_turn_s_bad_weights_when_made(field, value):
    message = _refused(lambda: gym.make("Animat/DolphinTurn-v0", **{field: value}), field)
    assert "finite number in [0, " in message


@pytest.mark.parametrize("name, field, value", [
    (name, field, value) for name in sorted(TASKS) for field in _numeric_fields(TASKS[name])
    for value in NOT_NUMBERS], ids=repr)
def test_every_task_refuses_a_bad_number_for_each_numeric_argument(name, field, value):
    _refused(lambda: make_task(name, **{field: value}), field)


@pytest.mark.parametrize("name", sorted(TASKS))
def test_every_task_runs_each_of_its_ancestors_checks(name, monkeypatch):
    """Every ``__post_init__`` in the task's method resolution order is called when the task
    is made (a subclass's that does not call ``super().__post_init__()`` skips its parent's)."""
    task, called = TASKS[name], []
    defining = [k for k in task.__mro__ if "__post_init__" in vars(k)]

    def recorded(klass: type, original: Callable[[object], None]) -> Callable[[object], None]:
        def post_init(self: object) -> None:
            called.append(klass)
            original(self)
        return post_init

    for klass in defining:
        monkeypatch.setattr(klass, "__post_init__", recorded(klass, vars(klass)["__post_init__"]))
    task()
    assert sorted(map(repr, called)) == sorted(map(repr, defining))


@pytest.mark.parametrize("direction, angle_deg", [
    ("up", 45.0), ("down", 90.0), ("left", 180.0), ("right", 10.0)])
def test_dolphin_turn_keeps_its_own_directions_and_angles(direction, angle_deg):
    """The dolphin turns up and down as well as the fish's left and right, up or down at most
    to a vertical pitch; its weights default as the fish's."""
    env = gym.make("Animat/DolphinTurn-v0", direction=direction, angle_deg=angle_deg)
    task = env.unwrapped.core.task
    assert (task.direction, task.angle_deg) == (direction, angle_deg)
    assert (task.path_weight, task.final_weight, task.settle_s) == (1.0, 0.0, 0.5)
    env.close()


@pytest.mark.parametrize("name, kwargs, field", [
    ("dolphin_turn", {"direction": "sideways"}, "direction"),
    ("dolphin_turn", {"direction": ["up"]}, "direction"),
    ("dolphin_turn", {"direction": "up", "angle_deg": 95.0}, "angle_deg"),
    ("dolphin_turn", {"direction": "down", "start_pitch_deg": -30.0, "angle_deg": 70.0},
     "angle_deg"),
    ("dolphin_turn", {"start_pitch_deg": NAN}, "start_pitch_deg"),
    ("turn", {"direction": "up"}, "direction"),
    ("dolphin_arc", {"direction": "left"}, "direction"),
    ("dolphin_spin", {"direction": None}, "direction")])
def test_directions_and_angles_beyond_a_task_s_own_are_refused(name, kwargs, field):
    _refused(lambda: make_task(name, **kwargs), field)
