"""Hand-designed motor controllers (MCs): natural parameters and time -> muscle actuations.

Each MC is a small pure function of its parameters and time ``t`` (s, scalar or array of
shape (T,)) returning actuations ``u`` in [0, 1], shape (..., 6) in the actuator order
left-front, left-middle, left-back, right-front, right-middle, right-back (or fin angles,
shape (..., 2), rad, for the fin MCs), for the fish body (:mod:`animat.envs.bodies.fish`). The
tasks' hand
controllers (:mod:`animat.envs.tasks.base`), the ``handmc`` learner and the demo use them.
``to_action``
maps actuations to an env action ``a = 2u - 1``.

Biomechanics (Tu's thesis): the middle and back segments drive swimming, the back one lagging
in phase, with amplitude and frequency growing with speed; the front segments drive turning.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEFT_FRONT, LEFT_MIDDLE, LEFT_BACK, RIGHT_FRONT, RIGHT_MIDDLE, RIGHT_BACK = range(6)
MIN_RELIEF = 0.25  # the least share of its amplitude a turn strokes at, however fast the fish
MAX_SPEED = 100.0  # BL/s, the largest forward speed a turn is told (fish: up to ~20)


@dataclass(frozen=True)
class SwimParams:
    """Swim-MC gains: frequency ``min_hz + (max_hz - min_hz) * speed``, amplitude
    ``max_amplitude * speed``, back segment lagging the middle by ``phase_lag`` rad. The
    defaults are calibrated for the default (reactive) water, :data:`PAPER_SWIM` for the
    paper's (resistive) one (:func:`calibrated`). The
    amplitude eases in over ``ramp_cycles`` tail beats from t = 0: a fish not yet under way
    yaws at every one-sided stroke, and an ease-in ending on a three-quarter beat leaves the
    smallest heading offset."""

    min_hz: float = 1.0
    max_hz: float = 3.0
    max_amplitude: float = 0.6
    phase_lag: float = 0.25 * np.pi
    ramp_cycles: float = 3.75
    start_phase: float = 0.0


@dataclass(frozen=True)
class TurnParams:
    """Turn-MC: a train of one-sided power strokes. Each stroke contracts the turn-side
    segments within ``rise`` s and relaxes them over the rest of ``period`` s (fast in, slow
    out: the water resists the fast half more, so each stroke yaws the body toward the turn
    side). The number of strokes is ``ceil(angle / angle_per_stroke)``. A turn begun at a
    forward speed ``U`` (BL/s) strokes at ``amplitude * max(MIN_RELIEF, 1 - speed_relief *
    U**2)``: in the reactive water a fish under way turns further for the same bend (the water's
    reaction grows with the speed), so a turn begun at cruise needs smaller strokes than one
    from rest; ``speed_relief`` is fitted to the strokes that turn 45 degrees from rest and from
    the swim-MC's speeds. The defaults are calibrated for the
    default (reactive) water, :data:`PAPER_TURN` for the paper's (resistive) one, which has no
    relief (:func:`calibrated`)."""

    period: float = 0.4
    rise: float = 0.08
    angle_per_stroke: float = np.radians(23.0)
    amplitude: float = 0.8
    speed_relief: float = 0.06


@dataclass(frozen=True)
class CStartParams:
    """C-start (the escape turn of fish: Domenici & Blake 1997, J. Exp. Biol. 200): every
    turn-side segment fully contracted for ``bend`` s (stage 1, the body bent into a C), then
    the other side's at ``counter_amplitude`` for ``counter`` s (stage 2, the counter-stroke
    that throws the tail back and propels the fish out of the turn), then relaxed."""

    bend: float = 0.1
    counter: float = 0.3
    counter_amplitude: float = 1.0


@dataclass(frozen=True)
class FinParams:
    """Fin-MC gain: the fin angle (rad) for a command of 1."""

    max_angle: float = np.radians(30.0)


# The controllers calibrated for the reactive water (Water(model="reactive"), the default), where
# the same muscles move the fish much further than in the paper's: the full-speed swim at 0.6 of
# the activation swims with a fish's tail amplitude (0.20 BL peak to peak, St 0.22, 0.91 BL per
# beat at 3 Hz, 2.7 BL/s), and a turn stroke of 0.8 turns about 23 degrees (the 90-degree
# turn-MC ends at 91 degrees, peaks at 96, holds 91); the C-start's defaults (CStartParams)
# turn 72 degrees within 1 s there (the resistive water turns 23 at most). These are the
# dataclasses' defaults. The paper's water takes the full activation and 13 degrees a stroke.
# Measured by the demo (animat demo) and held by tests/envs/physics/test_reactive.py and
# tests/envs/motor/test_motor.py.
REACTIVE_SWIM = SwimParams()
REACTIVE_TURN = TurnParams()
PAPER_SWIM = SwimParams(max_amplitude=1.0)
PAPER_TURN = TurnParams(angle_per_stroke=np.radians(13.0), amplitude=1.0, speed_relief=0.0)


def calibrated(model: str) -> tuple[SwimParams, TurnParams]:
    """The swim-MC's and turn-MC's parameters calibrated for a water model (``Water.model``):
    :data:`PAPER_SWIM` and :data:`PAPER_TURN` for ``"resistive"``, :data:`REACTIVE_SWIM` and
    :data:`REACTIVE_TURN` (the defaults) for ``"reactive"``."""
    if model == "reactive":
        return REACTIVE_SWIM, REACTIVE_TURN
    if model == "resistive":
        return PAPER_SWIM, PAPER_TURN
    raise ValueError(f"no motor controllers are calibrated for water model {model!r}")


def _check_unit(name: str, value, low: float, high: float):
    """``value`` as a float (an array of floats for an array) if it is within [low, high]
    (every entry); else ValueError naming the first that is not."""
    if np.ndim(value) == 0:
        value = float(value)
        if not (low <= value <= high):
            raise ValueError(f"{name} must be in [{low}, {high}], got {value!r}")
        return value
    values = np.asarray(value, dtype=float)
    bad = ~((low <= values) & (values <= high))
    if bad.any():
        raise ValueError(f"{name} must be in [{low}, {high}], got {float(values[bad][0])!r}")
    return values


def swim_mc(speed: float | np.ndarray, t: np.ndarray | float,
            params: SwimParams = SwimParams()) -> np.ndarray:
    """Swim forward at ``speed`` in [0, 1] (0: glide, 1: full speed; an array: one swim per
    entry, broadcast with ``t``). Returns u (..., 6)."""
    speed = _check_unit("swim speed", speed, 0.0, 1.0)
    t = np.asarray(t, dtype=float)
    hz = params.min_hz + (params.max_hz - params.min_hz) * speed
    ramp = params.ramp_cycles / hz
    eased = ramp > 0  # no ramp: at full amplitude from the start
    ease = np.where(eased, np.clip(t / np.where(eased, ramp, 1.0), 0.0, 1.0), 1.0)
    half = 0.5 * params.max_amplitude * speed * ease * ease * (3.0 - 2.0 * ease)
    phase = 2.0 * np.pi * hz * t + params.start_phase
    u = np.zeros(np.shape(phase) + (6,))
    u[..., LEFT_MIDDLE] = half * (1.0 + np.sin(phase))
    u[..., RIGHT_MIDDLE] = half * (1.0 - np.sin(phase))
    u[..., LEFT_BACK] = half * (1.0 + np.sin(phase - params.phase_lag))
    u[..., RIGHT_BACK] = half * (1.0 - np.sin(phase - params.phase_lag))
    return u


def turn_strokes(angle, params: TurnParams = TurnParams()):
    """Number of power strokes the turn-MC uses for ``angle`` rad (an int; an array of them,
    one per entry, for an array)."""
    strokes = np.maximum(1, np.ceil(np.asarray(angle) / params.angle_per_stroke - 1e-9).astype(int))
    return int(strokes) if np.ndim(angle) == 0 else strokes


def turn_duration(angle, params: TurnParams = TurnParams()):
    """Seconds from the start of a turn of ``angle`` rad until its muscles are relaxed (an
    array: per entry)."""
    return turn_strokes(angle, params) * params.period


def turn_mc(angle, t: np.ndarray | float, left=True,
            params: TurnParams = TurnParams(), speed=0.0) -> np.ndarray:
    """Turn left (``left=True``) or right by ``angle`` rad in [0, pi], begun at the forward
    speed ``speed`` (BL/s, in [-100, 100]; 0: from rest); ``angle``, ``left`` and ``speed``
    may be arrays (one turn per entry, broadcast with ``t``). Returns u (..., 6)."""
    angle = _check_unit("turn angle", angle, 0.0, np.pi)
    speed = _check_unit("turn's forward speed (BL/s)", speed, -MAX_SPEED, MAX_SPEED)
    t = np.asarray(t, dtype=float)
    phase = np.mod(t, params.period) / params.period
    rise = params.rise / params.period
    envelope = np.where(phase < rise, phase / rise, 1.0 - (phase - rise) / (1.0 - rise))
    active = (t >= 0.0) & (t < turn_duration(angle, params))
    amplitude = params.amplitude * np.maximum(MIN_RELIEF, 1.0 - params.speed_relief * speed**2)
    envelope = amplitude * np.where(active, envelope, 0.0)
    u = np.zeros(np.shape(envelope) + (6,))
    left = np.asarray(left, bool)
    for segment in (LEFT_FRONT, LEFT_MIDDLE, LEFT_BACK):
        u[..., segment] = np.where(left, envelope, 0.0)
    for segment in (RIGHT_FRONT, RIGHT_MIDDLE, RIGHT_BACK):
        u[..., segment] = np.where(left, 0.0, envelope)
    return u


def cstart_mc(t: np.ndarray | float, left: bool = True,
              params: CStartParams = CStartParams()) -> np.ndarray:
    """A C-start to the left (``left=True``) or right from ``t = 0``. Returns u (..., 6)."""
    t = np.asarray(t, dtype=float)
    bend = (t >= 0.0) & (t <= params.bend)
    counter = (t > params.bend) & (t <= params.bend + params.counter)
    turn_side, other = (slice(0, 3), slice(3, 6)) if left else (slice(3, 6), slice(0, 3))
    u = np.zeros(t.shape + (6,))
    u[..., turn_side] = np.where(bend, 1.0, 0.0)[..., None]
    u[..., other] = np.where(counter, params.counter_amplitude, 0.0)[..., None]
    return u


def wave_mc(hz: float, lag: float, amplitude: float, t: np.ndarray | float,
            ease: float = 1.0) -> np.ndarray:
    """A wave of contraction over the three segments, front to back: segment k of the left
    side at ``amplitude (1 + sin(2 pi hz t - k lag)) / 2`` and of the right side in
    antiphase, eased in over ``ease`` s; a negative ``lag`` runs the wave tail to head.
    Returns u (..., 6)."""
    t = np.asarray(t, dtype=float)
    scale = 0.5 * amplitude * (np.clip(t / ease, 0.0, 1.0) if ease > 0 else np.ones_like(t))
    u = np.zeros(t.shape + (6,))
    for k, (left, right) in enumerate(((LEFT_FRONT, RIGHT_FRONT), (LEFT_MIDDLE, RIGHT_MIDDLE),
                                       (LEFT_BACK, RIGHT_BACK))):
        wave = np.sin(2.0 * np.pi * hz * t - k * lag)
        u[..., left] = scale * (1.0 + wave)
        u[..., right] = scale * (1.0 - wave)
    return u


def fin_mc(pitch: float = 0.0, roll: float = 0.0, params: FinParams = FinParams()) -> np.ndarray:
    """Pectoral fin angles (2,) rad (arrays: (..., 2)) for an up/down command ``pitch`` and a
    ``roll`` command, each in [-1, 1]. Positive pitch raises both leading edges (the fish rises
    when it moves forward); positive roll lifts the left fin and lowers the right (rolls to the
    right)."""
    pitch = _check_unit("fin pitch", pitch, -1.0, 1.0)
    roll = _check_unit("fin roll", roll, -1.0, 1.0)
    left = np.minimum(np.maximum(pitch + roll, -1.0), 1.0)
    right = np.minimum(np.maximum(pitch - roll, -1.0), 1.0)
    return params.max_angle * np.stack(np.broadcast_arrays(left, right), axis=-1)


def to_action(u: np.ndarray) -> np.ndarray:
    """Actuations u in [0, 1] -> env actions in [-1, 1] (float32)."""
    return (2.0 * np.asarray(u) - 1.0).astype(np.float32)
