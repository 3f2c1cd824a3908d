"""The dolphin's hand-designed motor controllers: fluke strokes and turns, as pure functions of
time returning actuations u (..., 6) in [0, 1] in the order of
:data:`animat.envs.bodies.dolphin.ACTUATOR_NAMES` (dorsal middle, dorsal back, ventral middle,
ventral back, left front, right front).

The swim-MC is the fish's (:func:`animat.envs.motor.fish.swim_mc`) turned into the vertical plane:
the fish's left segments become the dorsal ones, its right segments the ventral ones. Pitch
turns are one-sided strokes as for the fish: dorsal strokes pitch the dolphin up, ventral
strokes down. It turns left or right by steering: the head bent to the side by the front
muscles while it swims.

Each water has its calibration (:class:`DolphinCalibration`, :func:`dolphin_calibrated`):

* the reactive water's (:data:`REACTIVE_DOLPHIN`, the default): the fluke beats at 3 Hz at half
  activation (2.9 BL/s, St 0.28, 0.96 BL per beat, as a dolphin cruises; at full activation
  and 3-5 Hz the stroke pitches the body over into loops); pitch strokes of 0.9 activation
  for 30 degrees each (90 degrees up: 76 when they end, down 77; 45: 46 and 48; a pitch up
  falls back once the strokes end, to -18 degrees 2 s later); the steer turns the body only
  once it is under way, after about 2 s (90 degrees: 92 and 90 when it ends, 104-110 2 s
  later, gliding on);
* the paper's water's (:data:`PAPER_DOLPHIN`, ``water={"model": "resistive"}``): the fluke at
  up to 5 Hz at full activation (2.2 BL/s, St 1.02), the fish's paper turn (90 degrees: 69
  when it ends), steering at 40 degrees/s from the start (90 degrees: 64 when it ends, 94 2 s
  later).

Measured from the seeded starts, 3 m down (``animat demo`` prints them). In both waters the
swimming dolphin pitches nose down as it goes (-29 degrees at 6 s, the paper's water -27; as
much without its lungs: the stroke's own moment), which the hand MCs do not correct.
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


@dataclass(frozen=True)
class DolphinCalibration:
    """The dolphin's hand MCs for one water: the fluke stroke ``swim``, the pitch turns'
    strokes ``turn``, and the steer: ``steer_delay`` s of steering before it turns, then
    ``steer_rate`` rad/s (a turn of ``angle`` steers ``steer_delay + angle / steer_rate`` s)."""

    swim: SwimParams
    turn: TurnParams
    steer_rate: float
    steer_delay: float = 0.0


PAPER_DOLPHIN = DolphinCalibration(
    swim=SwimParams(min_hz=2.0, max_hz=5.0, max_amplitude=1.0, ramp_cycles=1.0),
    turn=PAPER_TURN, steer_rate=np.radians(40.0))
REACTIVE_DOLPHIN = DolphinCalibration(
    swim=SwimParams(min_hz=2.0, max_hz=3.0, max_amplitude=0.5, ramp_cycles=1.0),
    turn=TurnParams(angle_per_stroke=np.radians(30.0), amplitude=0.9, speed_relief=0.0),
    steer_rate=np.radians(40.0), steer_delay=2.0)
DOLPHIN_SWIM = REACTIVE_DOLPHIN.swim  # the default water's stroke
PAPER_DOLPHIN_SWIM = PAPER_DOLPHIN.swim


def dolphin_calibrated(model: str) -> DolphinCalibration:
    """The dolphin's calibration for the water ``model`` (``"reactive"`` or ``"resistive"``)."""
    if model not in ("reactive", "resistive"):
        raise ValueError(f"no motor controllers are calibrated for water model {model!r}")
    return REACTIVE_DOLPHIN if model == "reactive" else PAPER_DOLPHIN

_FROM_FISH = {LEFT_MIDDLE: DORSAL_MIDDLE, LEFT_BACK: DORSAL_BACK, RIGHT_MIDDLE: VENTRAL_MIDDLE,
              RIGHT_BACK: VENTRAL_BACK}


@dataclass(frozen=True)
class Stroke:
    """A dolphin turn: which of its actuators contract in the one-sided strokes."""

    actuators: tuple[int, ...]


STROKES = {"up": Stroke((DORSAL_MIDDLE, DORSAL_BACK)),
           "down": Stroke((VENTRAL_MIDDLE, VENTRAL_BACK))}
STEER = {"left": LEFT_FRONT, "right": RIGHT_FRONT}


def dolphin_swim_mc(speed: float, t: np.ndarray | float,
                    params: SwimParams = DOLPHIN_SWIM) -> np.ndarray:
    """Swim forward at ``speed`` in [0, 1] by beating the flukes. Returns u (..., 6)."""
    fish = swim_mc(speed, t, params)
    u = np.zeros(fish.shape)
    for fish_actuator, actuator in _FROM_FISH.items():
        u[..., actuator] = fish[..., fish_actuator]
    return u


def dolphin_turn_mc(direction: str, angle: float, t: np.ndarray | float,
                    calibration: DolphinCalibration = REACTIVE_DOLPHIN) -> np.ndarray:
    """Turn ``direction`` (up, down, left, right) by ``angle`` rad. Up and down: the fish's
    stroke train (:func:`animat.envs.motor.fish.turn_mc`, ``calibration.turn``) on the dorsal
    or ventral actuators. Left and right: steer, the head bent to that side by its front
    muscles while the flukes beat at full speed (``calibration.swim``), for ``steer_delay +
    angle / steer_rate`` s, then glide (alone, a one-sided stroke of the front segment barely
    yaws the body, and in the paper's water the wrong way).
    Returns u (..., 6)."""
    params = calibration.turn
    if direction in STEER:
        t = np.asarray(t, dtype=float)
        steering = ((t >= 0) & (t < calibration.steer_delay + angle / calibration.steer_rate)
                    )[..., None]
        u = np.where(steering, dolphin_swim_mc(1.0, t, calibration.swim), 0.0)
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
