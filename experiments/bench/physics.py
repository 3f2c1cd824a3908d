"""Simulator benchmark: simulated seconds per wall second, ours against MuJoCo's Swimmer-v5.

Run ``python -m animat.experiments.bench.physics`` or ``animat bench``. It measures, in the
same process and in interleaved rounds (median of each), ``Animat/FishSwim-v0`` as one env and
as the native batch of 256, both in the default (reactive) water and in the paper's resistive
one (``water={"model": "resistive"}``), and, when ``mujoco`` is installed (the ``bench`` extra),
Gymnasium's ``Swimmer-v5`` as one env and as a sync vector of 256, all with uniformly random
actions, and prints the ratios (the reactive water's throughput against the resistive one's
too); and the same fish on the implicit integrator at 12.5 ms (``integrator="implicit"``,
four steps per env step: ``docs/integrators.md``) against Swimmer-v5 and the explicit default.
Simulated seconds per wall second of a vector env count every sub-env's time.
``--breakdown`` prints where an integration step's time goes instead: each force term, the
kick-drift and the whole fused step, in ns per body and step, for one body and for SIMD
chunks of 32 and 128 bodies, each part timed in a compiled loop
(:mod:`animat.experiments.bench.parts`); and the implicit step's parts (its matrix, the
banded factor, the two solves) and the whole fused implicit step, per body and implicit step.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym
import numpy as np

import animat  # noqa: F401  (registers Animat/*)
from animat.envs.physics import forces, reactive
from animat.envs.physics.integrator import CHUNK, MAX_CHUNK, NO_BALL, step_chunk
from animat.envs.physics.system import half_bandwidth

from . import parts


def sim_seconds_per_second(env, dt: float, num_envs: int, seconds: float, seed: int = 0) -> float:
    """Step ``env`` with random actions for about ``seconds`` of wall time (after a warm-up)."""
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    actions = rng.uniform(-1, 1, (64,) + env.action_space.shape).astype(np.float32)
    for k in range(3):
        env.step(actions[k])
    steps, start = 0, time.perf_counter()
    while (elapsed := time.perf_counter() - start) < seconds:
        for _ in range(8):
            env.step(actions[steps % 64])
            steps += 1
    return steps * dt * num_envs / elapsed


REACTIVE = {"model": "reactive"}  # the default water, said where it is timed
RESISTIVE = {"model": "resistive"}
IMPLICIT = {"integrator": "implicit", "physics_dt": 0.0125, "frame_skip": 4}  # 4 steps / env step


def make_configurations(num_envs: int) -> dict[str, tuple]:
    """{name: (env, dt, sub-env count)}; Swimmer-v5 only when mujoco is installed."""
    single = gym.make("Animat/FishSwim-v0")
    batch = gym.make_vec("Animat/FishSwim-v0", num_envs=num_envs)
    configs = {"fish, 1 env": (single, single.unwrapped.dt, 1),
               f"fish, native batch of {num_envs}": (batch, batch.dt, num_envs)}
    single = gym.make("Animat/FishSwim-v0", water=RESISTIVE)
    batch = gym.make_vec("Animat/FishSwim-v0", num_envs=num_envs, water=RESISTIVE)
    configs["fish, resistive water, 1 env"] = (single, single.unwrapped.dt, 1)
    configs[f"fish, resistive water, native batch of {num_envs}"] = (batch, batch.dt, num_envs)
    single = gym.make("Animat/FishSwim-v0", **IMPLICIT)
    batch = gym.make_vec("Animat/FishSwim-v0", num_envs=num_envs, **IMPLICIT)
    configs["fish, implicit 12.5 ms, 1 env"] = (single, single.unwrapped.dt, 1)
    configs[f"fish, implicit 12.5 ms, native batch of {num_envs}"] = (batch, batch.dt, num_envs)
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return configs
    swimmer = gym.make("Swimmer-v5")
    swimmers = gym.make_vec("Swimmer-v5", num_envs=num_envs, vectorization_mode="sync")
    configs["Swimmer-v5, 1 env"] = (swimmer, swimmer.unwrapped.dt, 1)
    configs[f"Swimmer-v5, sync vector of {num_envs}"] = (swimmers, swimmers.envs[0].unwrapped.dt,
                                                         num_envs)
    return configs


def run(seconds: float = 6.0, num_envs: int = 256, rounds: int = 3) -> dict[str, float]:
    """Measure every configuration in ``rounds`` interleaved rounds of ``seconds / rounds``
    each (so machine noise hits all alike); returns the median simulated seconds per wall
    second of each."""
    configs = make_configurations(num_envs)
    samples: dict[str, list[float]] = {name: [] for name in configs}
    for _ in range(rounds):
        for name, (env, dt, count) in configs.items():
            samples[name].append(sim_seconds_per_second(env, dt, count, seconds / rounds))
    return {name: float(np.median(values)) for name, values in samples.items()}


def report(results: dict[str, float], num_envs: int = 256) -> str:
    lines = [f"{'configuration':<50} {'sim s / wall s':>15}"]
    lines += [f"{name:<50} {value:>15.1f}" for name, value in results.items()]
    batch = f"native batch of {num_envs}"
    pairs = [("fish, 1 env", "Swimmer-v5, 1 env"),
             (f"fish, {batch}", f"Swimmer-v5, sync vector of {num_envs}"),
             ("fish, resistive water, 1 env", "Swimmer-v5, 1 env"),
             (f"fish, resistive water, {batch}", f"Swimmer-v5, sync vector of {num_envs}"),
             ("fish, 1 env", "fish, resistive water, 1 env"),
             (f"fish, {batch}", f"fish, resistive water, {batch}"),
             ("fish, implicit 12.5 ms, 1 env", "Swimmer-v5, 1 env"),
             (f"fish, implicit 12.5 ms, {batch}", f"Swimmer-v5, sync vector of {num_envs}"),
             ("fish, implicit 12.5 ms, 1 env", "fish, 1 env"),
             (f"fish, implicit 12.5 ms, {batch}", f"fish, {batch}")]
    for ours, theirs in pairs:
        if ours in results and theirs in results:
            lines.append(f"ratio {ours} / {theirs}: {results[ours] / results[theirs]:.2f}x")
    if "Swimmer-v5, 1 env" not in results:
        lines.append("(install the 'bench' extra, i.e. mujoco, to compare with Swimmer-v5)")
    return "\n".join(lines)


def _timed(fn, reps: int) -> float:
    fn()
    start = time.perf_counter()
    for _ in range(reps):
        fn()
    return (time.perf_counter() - start) / reps


def breakdown(lanes: int, reps: int = 20000) -> dict[str, float]:
    """ns per body and integration step of each part of the step, for a chunk of ``lanes``
    bodies in a swimming state, each part over about ``reps`` body-steps in a compiled loop
    (:mod:`animat.experiments.bench.parts`: no call overhead) and the fused step over ``reps``
    substeps, in the reactive water (the fused step in both waters); one body through the
    kernels compiled for one (``ONE_BODY``), as a single env steps it."""
    env = gym.make("Animat/FishSwim-v0", water=REACTIVE)
    env.reset(seed=0)
    for k in range(20):
        env.step(np.full(6, np.sin(k), np.float32))
    c, x0 = env.unwrapped.system.kernel_args, env.unwrapped.node_positions
    v0 = env.unwrapped.node_velocities
    x = np.ascontiguousarray(np.repeat(x0[:, :, None], lanes, axis=2))
    v, f = np.ascontiguousarray(np.repeat(v0[:, :, None], lanes, axis=2)), np.zeros_like(x)
    rest = np.repeat(c.rest_lengths[:, None], lanes, axis=1).copy()
    u = np.full((lanes, 6), 0.5)
    sin_cos = np.zeros((2, 2, lanes))
    sin_cos[:, 1] = 1.0
    face_scratch, fin_scratch = np.empty((len(c.faces), 4, lanes)), np.empty((16, lanes))
    splash = np.zeros(lanes)
    frames = (c.frame_front, c.frame_back, c.frame_up, c.frame_down)
    xb, vb = np.repeat(x0[None], lanes, axis=0), np.repeat(v0[None], lanes, axis=0)
    sections = np.zeros((len(c.section_nodes), reactive.SECTION_ROWS, lanes))
    means = np.zeros((len(c.section_nodes), reactive.MEAN_ROWS, lanes))
    up = np.empty((3, lanes))
    one = forces.ONE_BODY if lanes == 1 else forces.BATCH  # as the env steps it
    loops = {
        "muscle rest lengths": lambda n: parts.rest_lengths_loop(n, c, u, rest, one),
        "elements": lambda n: parts.elements_loop(n, c, x, v, rest, f, one),
        "faces": lambda n: parts.faces_loop(n, c, x, v, f, face_scratch, splash, one),
        "fins": lambda n: parts.fins_loop(n, c, x, v, frames, sin_cos, f, fin_scratch, one),
        "gravity, buoyancy": lambda n: parts.gravity_loop(n, c, x, f, one),
        "reactive force (sections)": lambda n: parts.sections_loop(n, c, x, v, f, sections,
                                                                   means, up, one),
        "added mass (solve)": lambda n: parts.added_mass_loop(n, c, f, sections, one),
        "kick-drift": lambda n: parts.kick_drift_loop(n, c, x, v, f, one),
    }
    out = {}
    for name, loop in loops.items():
        f[:] = 0.0
        loop(1)  # compiled (or loaded) before it is timed
        start = time.perf_counter()
        loop(reps // lanes)
        out[name] = 1e9 * (time.perf_counter() - start) / (reps // lanes) / lanes
    band = np.zeros((3 * len(c.masses), half_bandwidth(c.elements, c.faces) + 1, lanes))
    factored, rhs = np.empty_like(band), np.ones((2, band.shape[0], lanes))
    blocks, terms = np.empty((len(c.elements), 5, lanes)), np.empty((len(c.faces), 4, lanes))
    parts.implicit_matrix_loop(1, c, x, v, rest, f, band, blocks, terms, one)
    loops = {
        "implicit: matrix": lambda n: parts.implicit_matrix_loop(n, c, x, v, rest, f, band,
                                                                 blocks, terms, one),
        "implicit: factor": lambda n: parts.implicit_factor_loop(n, band, factored, one),
        "implicit: two solves": lambda n: parts.implicit_solve_loop(n, factored, rhs, one),
    }
    for name, loop in loops.items():
        loop(1)
        start = time.perf_counter()
        loop(reps // lanes)
        out[name] = 1e9 * (time.perf_counter() - start) / (reps // lanes) / lanes
    steps = 40
    resistive = gym.make("Animat/FishSwim-v0", water=RESISTIVE).unwrapped.system.kernel_args
    for name, args in (("fused step, reactive water", c), ("fused step, resistive", resistive)):
        out[name] = 1e9 * _timed(
            lambda args=args: step_chunk(xb, vb, u, u, np.zeros((lanes, 2)), steps, args,
                                         np.zeros(lanes), *NO_BALL, one),
            max(1, reps // steps)) / lanes / steps
    implicit_args = gym.make("Animat/FishSwim-v0", **IMPLICIT).unwrapped.system.kernel_args
    out["fused implicit step, reactive"] = 1e9 * _timed(
        lambda: step_chunk(xb, vb, u, u, np.zeros((lanes, 2)), 4, implicit_args,
                           np.zeros(lanes), *NO_BALL, one), max(1, reps // 40)) / lanes / 4
    return out


def report_breakdown(reps: int = 20000) -> str:
    """The breakdown's table: one body, and chunks of CHUNK and MAX_CHUNK lanes (the narrowest
    and the widest a batch runs in, :func:`~animat.envs.physics.integrator.chunk_width`: the
    batch of 256 on 2 threads runs chunks of 128)."""
    columns = {"1 body": breakdown(1, reps), f"chunk of {CHUNK}": breakdown(CHUNK, reps),
               f"chunk of {MAX_CHUNK}": breakdown(MAX_CHUNK, reps)}
    lines = [f"{'part of a step':<26}" + "".join(f"{name:>14}" for name in columns)
             + "  (ns per body-step)"]
    lines += [f"{part:<26}" + "".join(f"{times[part]:>14.0f}" for times in columns.values())
              for part in columns["1 body"]]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=6.0,
                        help="wall seconds per configuration, over all rounds")
    parser.add_argument("--num-envs", type=int, default=256)
    parser.add_argument("--rounds", type=int, default=3, help="interleaved rounds (median)")
    parser.add_argument("--breakdown", action="store_true",
                        help="where a step's time goes, per force term")
    args = parser.parse_args(argv)
    if args.breakdown:
        print(report_breakdown())
        return
    print(report(run(args.seconds, args.num_envs, args.rounds), args.num_envs))


if __name__ == "__main__":
    main()
