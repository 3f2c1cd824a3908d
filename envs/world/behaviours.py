"""Behaviour routines of world fish (the paper's Section 2, after Tu and Terzopoulos): each turns
an intention and its focus into a navigation command (speed in [0, 1], turn and pitch in
[-1, 1]) that :class:`animat.envs.motor.navigation.Navigator` runs through the motor controllers
(the swim-, turn- and fin-MCs) on the physical body. Nothing here moves a fish: a behaviour
only chooses what its muscles and fins are told.

A turn command of ``turn`` starts a turn of ``turn * 90`` deg when ``|turn| > 0.15``
(positive: left); ``pitch`` sets the pectoral fins (positive: nose up).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .intention import AVOID, EAT, FLEE, HUNT, MATE, SCHOOL
from .percepts import Percepts, Tank


@dataclass(frozen=True)
class BehaviourParams:
    """avoid_turn, avoid_speed: the turn and speed commands of an avoidance (slow: a tighter
    turn); max_turn: the largest other turn command (a turn runs to its end: shorter ones
    let a fish re-plan sooner); slow_within: m from food or a mate inside which a fish slows
    down; court_distance: m inside which a courting pair circles each
    other; school_spacing: m a schooling fish keeps from its school's centre; wander_change:
    s between a wanderer's new headings; home: the share of the tank's half size beyond which
    a wanderer heads back to the middle; cruise_depth: the share of the layer's height (from
    the seabed) wanderers keep to."""

    avoid_turn: float = 0.5
    avoid_speed: float = 0.2
    max_turn: float = 0.5
    slow_within: float = 0.3
    court_distance: float = 0.3
    school_spacing: float = 0.25
    wander_change: float = 4.0
    home: float = 0.6
    cruise_depth: float = 0.5


def heading_error(headings: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """(F,) rad from each heading (F, 3) to a direction (F, 3) about +z (positive: left)."""
    yaw = np.arctan2(headings[:, 1], headings[:, 0])
    wanted = np.arctan2(directions[:, 1], directions[:, 0])
    return np.mod(wanted - yaw + np.pi, 2.0 * np.pi) - np.pi


def steer(headings: np.ndarray, directions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(F,) turn and pitch commands that point headings (F, 3) along directions (F, 3): the
    turn is the yaw error in units of 90 deg, the pitch the elevation error in units of 30 deg."""
    turn = np.clip(heading_error(headings, directions) / (0.5 * np.pi), -1.0, 1.0)
    norm = np.maximum(np.linalg.norm(directions, axis=1), 1e-9)
    elevation = np.arcsin(np.clip(directions[:, 2] / norm, -1.0, 1.0))
    pitch_now = np.arcsin(np.clip(headings[:, 2], -1.0, 1.0))
    return turn, np.clip((elevation - pitch_now) / np.radians(30.0), -1.0, 1.0)


def uniform_angles(rng: np.random.Generator | Sequence[np.random.Generator], count: int
                   ) -> np.ndarray:
    """(count,) angles uniform in [-pi, pi) rad: from ``rng``, or from each generator of a
    list in turn, ``count / len(rng)`` each (one block of fish per generator: the worlds of
    a batch, each drawing what it would draw alone)."""
    if isinstance(rng, np.random.Generator):
        return rng.uniform(-np.pi, np.pi, count)
    return np.concatenate([g.uniform(-np.pi, np.pi, count // len(rng)) for g in rng])


def wander_directions(rng: np.random.Generator | Sequence[np.random.Generator],
                      heads: np.ndarray, current: np.ndarray, due: np.ndarray, tank: Tank,
                      params: BehaviourParams) -> np.ndarray:
    """(F, 3) wander directions: a new random horizontal heading where ``due`` (F,) bool, the
    way to the tank's middle for a fish beyond ``home`` of its half size, and otherwise
    ``current`` (F, 3); each with the climb or dive back to the cruise depth. ``rng``: one
    generator, or one per equal block of fish (:func:`uniform_angles`)."""
    angle = uniform_angles(rng, len(heads))
    fresh = np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=1)
    out = np.where(due[:, None], fresh, current).copy()
    far = np.abs(heads[:, :2]).max(axis=1) > params.home * tank.half_size
    out[far, :2] = -heads[far, :2] / np.linalg.norm(heads[far, :2], axis=1, keepdims=True)
    cruise = tank.seabed_z + params.cruise_depth * (tank.top_z - tank.seabed_z)
    out[:, 2] = np.clip(2.0 * (cruise - heads[:, 2]), -0.5, 0.5)
    return out


def commands(intention: np.ndarray, focus_positions: np.ndarray, p: Percepts,
             heads: np.ndarray, headings: np.ndarray, com: np.ndarray,
             wander: np.ndarray, cruise: np.ndarray, sprint: np.ndarray,
             params: BehaviourParams) -> np.ndarray:
    """(F, 3) navigation commands for F fish: ``intention`` (F,), the focus's position (F, 3)
    (nan: none), percepts, heads/headings/com (F, 3), wander directions (F, 3) and each
    species' cruise and sprint speeds (F,)."""
    direction = wander.copy()
    speed = cruise.copy()
    to_focus = focus_positions - heads
    distance = np.linalg.norm(to_focus, axis=1)
    seeking = np.isin(intention, (EAT, HUNT, MATE)) & np.isfinite(distance)
    direction[seeking] = to_focus[seeking]
    near = np.clip(distance / params.slow_within, 0.3, 1.0)
    speed = np.where(intention == EAT, near * sprint, speed)
    speed = np.where(intention == HUNT, sprint, speed)
    away = heads - p.predator_position
    fleeing = (intention == FLEE) & np.isfinite(away[:, 0])
    direction[fleeing] = away[fleeing] * [1.0, 1.0, 0.3]
    speed = np.where(intention == FLEE, sprint, speed)
    schooling = (intention == SCHOOL) & np.isfinite(p.school_centre[:, 0])
    offset = p.school_centre - com
    gap = np.linalg.norm(offset, axis=1)
    pull = np.where(gap > params.school_spacing, 1.0, -0.5)[:, None] * offset / np.maximum(
        gap, 1e-9)[:, None]
    join = np.nan_to_num(p.school_heading) + pull
    direction[schooling] = join[schooling]
    speed = np.where(schooling, np.clip(cruise * (0.8 + gap / params.school_spacing * 0.2),
                                        0.0, 1.0), speed)
    turn, pitch = steer(headings, direction)
    turn = np.where(intention == FLEE, turn, np.clip(turn, -params.max_turn, params.max_turn))
    courting = (intention == MATE) & (distance < params.court_distance)
    turn = np.where(courting, 0.3, turn)  # circle the partner
    speed = np.where(courting, 0.3, np.where(intention == MATE, near * sprint, speed))
    avoiding = intention == AVOID
    turn = np.where(avoiding & (p.escape_turn != 0), params.avoid_turn * p.escape_turn, turn)
    pitch = np.where(avoiding & (p.escape_pitch != 0), p.escape_pitch, pitch)
    speed = np.where(avoiding, params.avoid_speed, speed)
    return np.stack([np.clip(speed, 0.0, 1.0), turn, pitch], axis=1)

