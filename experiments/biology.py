"""How the animals swim, in the figures biologists measure them by: for each water model.

The demo (:mod:`animat.experiments.demo`) prints these and the physics tests hold them to the
ranges of real fish. Every figure comes from the hand motor controllers
(:mod:`animat.envs.motor.fish`, :mod:`animat.envs.motor.dolphin`) from the point start
(the body at rest where its task places it, the seeded node noise only: a calibration, not a
score over the tasks' start spreads, :mod:`animat.envs.tasks.start`):

* :func:`cruise_figures` of a swim: speed U (BL/s, net travel over the last half), the tail's
  peak-to-peak amplitude A across the travel (BL), the beat frequency f (Hz), the Strouhal
  number ``St = f A / U`` and the stride ``U / f`` (BL per beat). Real fish cruise at St
  0.2-0.4 with A about 0.2 BL and 0.5-1 BL per beat (Taylor, Nudds & Thomas 2003, Nature 425;
  Videler 1993, Fish Swimming); dolphins at St 0.2-0.3 (Rohr & Fish 2004, J. Exp. Biol. 207).
* :func:`gait_grid`: the speeds of head-to-tail waves of muscle contraction over the three
  segments (frequency, phase lag per segment) and of the same waves run tail to head, with the
  speed of the wave that the body itself then makes (:func:`rear_wave_speed`).
* :func:`rear_wave_speed`: the speed V of the body's own wave over its rear half (the
  swimming's, not the muscles'), positive head to tail, and the slip ``U / V`` (real fish
  about 0.6-0.8 at cruise: Videler 1993, table 4.3; a wave that runs tail to head, V < 0,
  cannot propel a fish forward in resistive-force theory, Gray & Hancock 1955).
* :func:`c_start`: the heading a C-start reaches (a one-sided bend, then a counter-stroke).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers the envs)

from ..envs.bodies.spec import BodySpec
from ..envs.core.batch import BodyBatch
from ..envs.core.env import BodyEnv
from ..envs.motor.dolphin import DOLPHIN_SWIM, dolphin_calibrated, dolphin_swim_mc, dolphin_turn_mc
from ..envs.motor.fish import (
    CStartParams,
    SwimParams,
    cstart_mc,
    swim_mc,
    to_action,
    turn_duration,
    wave_mc,
)
from ..envs.registration import water_of
from ..envs.tasks.base import EpisodeSummary
from ..envs.tasks.locomotion import SwimTask

TAIL_TIPS = [21, 22]  # the trailing edge's nodes, the fish's and the dolphin's


def play(env: gym.Env, actuation: Callable, seconds: float, fins=None
         ) -> tuple[list[dict], np.ndarray]:
    """Run ``actuation(t) -> u (6,)`` for ``seconds`` (with fin commands ``fins`` (2,) in
    [-1, 1] appended when given) from the seeded start; returns the per-step infos and every
    node's track (T, N, 3), m (the trailing edge's: ``nodes[:, TAIL_TIPS].mean(axis=1)``)."""
    env.reset(seed=0)
    infos, nodes = [], []
    for k in range(int(round(seconds / env.unwrapped.dt))):
        action = to_action(actuation((k + 1) * env.unwrapped.dt))
        if fins is not None:
            action = np.append(action, fins).astype(np.float32)
        infos.append(env.step(action)[4])
        nodes.append(env.unwrapped.node_positions)
    return infos, np.array(nodes)


def hand_mc_over_starts(env_id: str, env_kwargs: dict, seeds: list[int]
                        ) -> dict[str, np.ndarray]:
    """The task's hand-designed MC (calibrated for the env's water) played open loop from each
    seeded start of the task's start spread (:mod:`animat.envs.tasks.start`), in one native
    batch: the task's episode summary, each figure (len(seeds),)."""
    env = gym.make_vec(env_id, num_envs=len(seeds), **env_kwargs)
    env.reset(seed=list(seeds))
    core: Any = env.unwrapped
    controller = core.task.hand_controller(model=water_of(env_id, env_kwargs).model)
    summary = EpisodeSummary(core.task, len(seeds))
    for k in range(core.episode_steps):
        action = to_action(controller((k + 1) * core.dt))
        summary.update(env.step(np.tile(action, (len(seeds), 1)))[4])
    env.close()
    return summary.summary()


def rear_wave_speed(nodes: np.ndarray, com: np.ndarray, hz: float, dt: float, body: BodySpec,
                    vertical: bool = False) -> float:
    """The speed (BL/s) of the body's wave over the rear half of the body: nodes (T, N, 3) and com
    (T, 3) m over whole beats of ``hz``, every ``dt`` s. The body's own axis (its front nodes'
    centroid less its back nodes, ``body.frame_front`` and ``frame_back``, averaged over the time:
    not the way it travels, which may be tail first) sets along and across (in the horizontal
    plane, or with ``vertical`` in the vertical one); each node's sway across it is reduced to the
    phase of its component at ``hz``; the phase's slope along the body over the rear half of the
    nodes gives the wave speed ``2 pi hz / slope``: positive when the wave runs head to tail,
    negative tail to head."""
    axes = body_axes(nodes, body)
    if not vertical:
        axes[:, 2] = 0.0
    heading = (axes / np.linalg.norm(axes, axis=1, keepdims=True)).mean(axis=0)
    heading /= np.linalg.norm(heading)
    across = (np.array([0.0, 0.0, 1.0]) - heading[2] * heading if vertical
              else np.array([-heading[1], heading[0], 0.0]))
    across /= np.linalg.norm(across)
    relative = nodes - com[:, None, :]
    along, sway = (relative @ heading).mean(axis=0), relative @ across  # (N,), (T, N)
    t = np.arange(len(com)) * dt
    phase = np.angle((sway - sway.mean(axis=0)).T @ np.exp(-2j * np.pi * hz * t))
    rear = np.argsort(along)[: len(along) // 2][::-1]  # the rear half, front to back
    slope = np.polyfit(along[rear], np.unwrap(phase[rear]), 1)[0]  # rad/m, head leading > 0
    return float(2.0 * np.pi * hz / slope / body.length) if slope != 0.0 else float("inf")


def body_axes(nodes: np.ndarray, body: BodySpec) -> np.ndarray:
    """(T, 3) the body's own axis at every step of ``nodes`` (T, N, 3): its front nodes'
    centroid less its back nodes' (``body.frame_front``, ``frame_back``), m."""
    return nodes[:, body.frame_front].mean(axis=1) - nodes[:, body.frame_back].mean(axis=1)


def cruise_figures(infos: list[dict], nodes: np.ndarray, dt: float, body: BodySpec,
                   hz: float, start: float, vertical: bool = False) -> dict[str, float]:
    """Biology figures over the part of a swim after ``start`` s (``nodes`` (T, N, 3) the nodes'
    tracks, m, of :func:`play`, of ``body``): U (BL/s, net travel per second), A (BL, the tail
    tip's peak-to-peak excursion across the travel direction: in the horizontal plane, or with
    ``vertical`` in the vertical plane, the dolphin's), f (Hz), St = fA/U, the stride U/f (BL per
    beat), the body's rear wave speed V (BL/s, :func:`rear_wave_speed`) and the slip U/V."""
    first, length = int(round(start / dt)), body.length
    com = np.array([i["com"] for i in infos])[first:]
    tail = nodes[:, TAIL_TIPS].mean(axis=1)
    travel = com[-1] - com[0]
    speed = np.linalg.norm(travel) / ((len(com) - 1) * dt)
    heading = travel / np.linalg.norm(travel)
    if vertical:
        across = np.array([0.0, 0.0, 1.0]) - heading[2] * heading
    else:
        across = np.array([-heading[1], heading[0], 0.0])
    across /= np.linalg.norm(across)
    sway = (tail[first:] - com) @ across
    amplitude = sway.max() - sway.min()
    wave = rear_wave_speed(nodes[first:], com, hz, dt, body, vertical)
    return {"U": speed / length, "A": amplitude / length, "f": hz,
            "St": hz * amplitude / speed, "stride": speed / length / hz,
            "V": wave, "slip": speed / length / wave}


def fish_cruise(water: dict, params: SwimParams, seconds: float = 10.0,
                physics: dict | None = None) -> dict[str, float]:
    """:func:`cruise_figures` of the fish's swim-MC at full speed over the last half of
    ``seconds``; ``physics``: the env's ``physics_dt``, ``frame_skip`` and ``integrator``
    (default: the env's)."""
    env = BodyEnv("swim", duration=seconds, water=water, start_spread="point", **(physics or {}))
    infos, nodes = play(env, lambda t: swim_mc(1.0, t, params), seconds)
    return cruise_figures(infos, nodes, env.dt, env.body, params.max_hz, seconds / 2)


def dolphin_cruise(water: dict, params: SwimParams = DOLPHIN_SWIM, seconds: float = 6.0,
                   physics: dict | None = None) -> dict[str, float]:
    """:func:`cruise_figures` of the dolphin's fluke stroke at full speed (its own pool, 3 m
    down), the flukes' sway measured in the vertical plane, and its pitch at the end
    (``pitch``, deg); ``physics`` as :func:`fish_cruise`'s."""
    env = gym.make("Animat/DolphinForward-v0", water=water, duration=seconds,
                   start_spread="point", **(physics or {}))
    infos, nodes = play(env, lambda t: dolphin_swim_mc(1.0, t, params), seconds)
    body = env.unwrapped.body
    figures = cruise_figures(infos, nodes, env.unwrapped.dt, body, params.max_hz, seconds / 2,
                             vertical=True)
    heading = body_axes(nodes[-1:], body)[0]
    figures["pitch"] = float(np.degrees(np.arctan2(heading[2], np.hypot(*heading[:2]))))
    env.close()
    return figures


def dolphin_turn(model: str, direction: str, angle_deg: float, after: float = 2.0,
                 physics: dict | None = None) -> tuple[float, float]:
    """The dolphin's hand turn-MC (:func:`animat.envs.motor.dolphin.dolphin_turn_mc`,
    calibrated for the water ``model``) from the seeded start: the pitch (up, down) or heading
    (left, right) turned toward ``direction``, deg, when the MC ends and ``after`` s later;
    ``physics`` as :func:`fish_cruise`'s."""
    calibration = dolphin_calibrated(model)
    angle = np.radians(angle_deg)
    if direction in ("up", "down"):
        end, key = turn_duration(angle, calibration.turn), "pitch_deg"
    else:
        end, key = calibration.steer_delay + angle / calibration.steer_rate, "heading_deg"
    env = gym.make("Animat/DolphinTurn-v0", direction=direction, angle_deg=angle_deg,
                   water={"model": model}, duration=end + after, start_spread="point",
                   **(physics or {}))
    infos, _ = play(env, lambda t: dolphin_turn_mc(direction, angle, t, calibration),
                    end + after)
    env.close()
    sign = 1.0 if direction in ("up", "left") else -1.0
    turned = sign * np.degrees(np.unwrap(np.radians([i[key] for i in infos])))
    return float(turned[int(round(end / env.unwrapped.dt)) - 1]), float(turned[-1])


def gait_grid(water: dict, hz: list[float], lags: list[float], amplitude: float = 1.0,
              seconds: float = 8.0) -> tuple[np.ndarray, np.ndarray]:
    """For the head-to-tail wave of muscle contraction of each frequency and phase lag per
    segment (rad; :func:`animat.envs.motor.fish.wave_mc`) in ``[..., 0]`` and the same wave
    run tail to head (the lag negated) in ``[..., 1]``, over the last half of ``seconds``:
    the fish's speed (BL/s, net travel along the start heading) and the speed of the body's
    own rear wave (BL/s, :func:`rear_wave_speed`), each (len(hz), len(lags), 2). One batch of
    fish, seeded starts."""
    combos = [(f, sign * lag) for f in hz for lag in lags for sign in (1.0, -1.0)]
    core = BodyBatch(len(combos), SwimTask(), water=water, duration=100.0, start_spread="point")
    core.reset_rows(np.arange(len(combos)), [np.random.default_rng(0) for _ in combos])
    steps = int(round(seconds / core.dt))
    heading, coms, nodes = core.kinematics().frames[:, 0, :2].copy(), [], []
    for k in range(steps):
        t = (k + 1) * core.dt
        u = np.stack([wave_mc(f, lag, amplitude, t) for f, lag in combos])
        info = core.step(2.0 * u - 1.0)[1]
        coms.append(info["com"].copy())
        if k >= steps // 2:
            nodes.append(core.state.x.copy())
    coms, nodes = np.array(coms), np.array(nodes)  # (T, B, 3), (T/2, B, N, 3)
    travel = coms[-1, :, :2] - coms[steps // 2 - 1, :, :2]
    along = np.einsum("bk,bk->b", travel, heading / np.linalg.norm(heading, axis=1)[:, None])
    speed = along / (seconds - (steps // 2) * core.dt) / core.body.length
    waves = [rear_wave_speed(nodes[:, b], coms[steps // 2:, b], f, core.dt, core.body)
             for b, (f, _) in enumerate(combos)]
    shape = (len(hz), len(lags), 2)
    return speed.reshape(shape), np.array(waves).reshape(shape)


def c_start(water: dict, params: CStartParams, seconds: float = 1.0,
            physics: dict | None = None) -> np.ndarray:
    """(T,) the fish's heading (deg, unwrapped, positive to the turn's side) every env step
    of a left C-start from rest (:func:`animat.envs.motor.fish.cstart_mc`); ``physics`` as
    :func:`fish_cruise`'s."""
    env = BodyEnv("swim", duration=seconds, water=water, start_spread="point", **(physics or {}))
    infos, _ = play(env, lambda t: cstart_mc(t, True, params), seconds)
    env.close()
    return np.degrees(np.unwrap(np.radians([i["heading_deg"] for i in infos])))
