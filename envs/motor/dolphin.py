"""The dolphin's hand-designed motor controllers: fluke strokes and turns, as pure functions of
time returning actuations u (..., 6) in [0, 1] in the order of
:data:`animat.envs.bodies.dolphin.ACTUATOR_NAMES` (dorsal middle, dorsal back, ventral middle,
ventral back, left front, right front).

The swim-MC is the fish's (:func:`animat.envs.motor.fish.swim_mc`) turned into the vertical plane:
the fish's left segments become the dorsal ones, its right segments the ventral ones, and the
fluke beats at up to 5 Hz (the body measured 1.9 BL/s at 5 Hz, 1.2 BL/s at 3 Hz: a dolphin's
stroke is fast and short). Pitch turns are one-sided strokes as for the fish: dorsal strokes
pitch the dolphin up, ventral strokes down. It turns left or right by steering: the head
bent to the side by the front muscles while it swims.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..bodies.dolphin import (
    DORSAL_BACK,
    DORSAL_MIDDLE,
    LEFT_FRONT,
    RIGHT_FRONT,
    VENTRAL_BACK,
    VENTRAL_MIDDLE,
)
from .fish import (
    LEFT_BACK,
    LEFT_MIDDLE,
    PAPER_TURN,
    RIGHT_BACK,
    RIGHT_MIDDLE,
    SwimParams,
    TurnParams,
    swim_mc,
    turn_mc,
)

DOLPHIN_SWIM = SwimParams(min_hz=2.0, max_hz=5.0, max_amplitude=1.0, ramp_cycles=1.0)
_FROM_FISH = {LEFT_MIDDLE: DORSAL_MIDDLE, LEFT_BACK: DORSAL_BACK, RIGHT_MIDDLE: VENTRAL_MIDDLE,
              RIGHT_BACK: VENTRAL_BACK}


@dataclass(frozen=True)
class Stroke:
    """A dolphin turn: which of its actuators contract in the one-sided strokes."""

    actuators: tuple[int, ...]


STROKES = {"up": Stroke((DORSAL_MIDDLE, DORSAL_BACK)),
           "down": Stroke((VENTRAL_MIDDLE, VENTRAL_BACK))}
STEER = {"left": LEFT_FRONT, "right": RIGHT_FRONT}
STEER_RATE = np.radians(40.0)  # rad/s: the yaw rate of a steered full-speed swim (measured)


def dolphin_swim_mc(speed: float, t: np.ndarray | float,
                    params: SwimParams = DOLPHIN_SWIM) -> np.ndarray:
    """Swim forward at ``speed`` in [0, 1] by beating the flukes. Returns u (..., 6)."""
    fish = swim_mc(speed, t, params)
    u = np.zeros(fish.shape)
    for fish_actuator, actuator in _FROM_FISH.items():
        u[..., actuator] = fish[..., fish_actuator]
    return u


def dolphin_turn_mc(direction: str, angle: float, t: np.ndarray | float,
                    params: TurnParams = PAPER_TURN) -> np.ndarray:
    """Turn ``direction`` (up, down, left, right) by ``angle`` rad. Up and down: the fish's
    stroke train (:func:`animat.envs.motor.fish.turn_mc`) on the dorsal or ventral actuators.
    Left and right: steer, the head bent to that side by its front muscles while the flukes
    beat at full speed, for ``angle / STEER_RATE`` s, then glide (alone, a one-sided stroke
    of the front segment barely yaws the body: measured 1.5 deg the wrong way over 4 s).
    Returns u (..., 6)."""
    if direction in STEER:
        t = np.asarray(t, dtype=float)
        steering = ((t >= 0) & (t < angle / STEER_RATE))[..., None]
        u = np.where(steering, dolphin_swim_mc(1.0, t), 0.0)
        u[..., STEER[direction]] = steering[..., 0]
        return u
    if direction not in STROKES:
        raise ValueError(f"direction must be one of {sorted(STROKES) + sorted(STEER)}, got "
                         f"{direction!r}")
    envelope = turn_mc(angle, t, True, params)[..., LEFT_MIDDLE]
    u = np.zeros(envelope.shape + (6,))
    for actuator in STROKES[direction].actuators:
        u[..., actuator] = envelope
    return u
