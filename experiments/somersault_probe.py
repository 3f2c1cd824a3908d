"""Can this dolphin somersault? A probe of the physics, not a learner of the paper's.

``python -m animat.experiments.somersault_probe --leap RUN`` plays a finished leap macro
run's sequence and, from a time ``t0`` near the exit, replaces its actuation by an *exit
stroke*: a fluke stroke of frequency ``f``, phase, amplitude and a dorsal/ventral bias per
segment (the back lagging the middle), held for ``h`` s, then a fixed pose for the flight.
A cross-entropy search over these 14 numbers (``POPULATION`` candidates a round, the best
``ELITE`` refit) maximises the largest pitch rotation of one flight
(``flight_rotation_deg`` of ``Animat/DolphinSomersault-v0``), from the first start; the best
is then scored over 4 starts at the default physics step, half and a quarter of it. It
answers whether the body and its water can turn a full somersault in one flight, which the
learners' figures alone cannot tell apart from a search that has not found it.
"""

from __future__ import annotations

import argparse

import numpy as np

from animat.experiments.stunt_figures import macro_of
from animat.learners.rollout import BatchEvaluator

POPULATION, ELITE = 256, 32
LOW = np.array([5.0, 0.05, 1.0, 0.0, 0.0, -1.0, -1.0, 0.0] + [-1.0] * 6)
HIGH = np.array([6.8, 1.5, 6.0, 1.0, 1.0, 1.0, 1.0, 1.0] + [1.0] * 6)
ENV, KWARGS = "Animat/DolphinSomersault-v0", {"duration": 9.0}


def _stroke(phase: np.ndarray, bias: float, amplitude: float) -> tuple[np.ndarray, np.ndarray]:
    """(dorsal, ventral) actions in [-1, 1] of one segment for stroke phases (T,) (cycles)."""
    s = np.clip(bias + 2.0 * amplitude * np.sin(2.0 * np.pi * phase), -1.0, 1.0)
    return np.where(s > 0, 2.0 * s - 1.0, -1.0), np.where(s < 0, -2.0 * s - 1.0, -1.0)


def exit_actions(base: np.ndarray, genes: np.ndarray, dt: float) -> np.ndarray:
    """(T, 6) the leap's actions ``base`` with the exit stroke of ``genes`` (14,) from t0."""
    t0, hold, hz, phase, amplitude, bias_middle, bias_back, lag = genes[:8]
    t = np.arange(len(base)) * dt
    out = base.copy()
    out[t >= t0] = genes[8:]  # the pose in flight
    stroke = (t >= t0) & (t < t0 + hold)
    cycles = hz * (t[stroke] - t0) + phase
    out[stroke] = -1.0
    out[stroke, 0], out[stroke, 2] = _stroke(cycles, bias_middle, amplitude)
    out[stroke, 1], out[stroke, 3] = _stroke(cycles - 0.5 * lag, bias_back, amplitude)
    return out


def search(leap_run: str, rounds: int, seed: int = 0) -> np.ndarray:
    """The best genes (14,) after ``rounds`` of the cross-entropy search."""
    sequence = macro_of(leap_run)[0]
    evaluator = BatchEvaluator(ENV, KWARGS, num_envs=POPULATION, seed=0, num_starts=1)
    base = sequence.actions(evaluator.dt, evaluator.steps)
    rng = np.random.default_rng(seed)
    mean, spread = (LOW + HIGH) / 2, (HIGH - LOW) / 2
    best, best_genes = -np.inf, mean
    for k in range(rounds):
        genes = np.clip(mean + spread * rng.standard_normal((POPULATION, len(LOW))), LOW, HIGH)
        _, metrics = evaluator.evaluate(np.stack([exit_actions(base, g, evaluator.dt)
                                                  for g in genes]))
        turned = metrics["flight_rotation_deg"]
        elite = np.argsort(-turned)[:ELITE]
        mean, spread = genes[elite].mean(axis=0), np.maximum(genes[elite].std(axis=0),
                                                            0.02 * (HIGH - LOW))
        if turned[elite[0]] > best:
            best, best_genes = turned[elite[0]], genes[elite[0]]
        print(f"round {k}: best {turned[elite[0]]:.0f} deg in one flight, elite mean "
              f"{turned[elite].mean():.0f}", flush=True)
    return best_genes


def score(leap_run: str, genes: np.ndarray, refine: int) -> dict[str, float]:
    """The exit stroke over 4 starts at the physics step divided by ``refine``."""
    sequence = macro_of(leap_run)[0]
    kwargs = {**KWARGS, "physics_dt": 0.05 / (80 * refine), "frame_skip": 80 * refine}
    evaluator = BatchEvaluator(ENV, kwargs, num_envs=1, seed=0)
    base = sequence.actions(evaluator.dt, evaluator.steps)
    _, metrics = evaluator.evaluate(exit_actions(base, genes, evaluator.dt)[None])
    return {k: float(v[0]) for k, v in metrics.items()}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--leap", required=True, help="a finished leap macro run folder")
    parser.add_argument("--rounds", type=int, default=20, help="rounds of the search")
    args = parser.parse_args(argv)
    genes = search(args.leap, args.rounds)
    print("exit stroke:", np.array2string(genes, precision=2, max_line_width=200))
    for refine in (1, 2, 4):
        m = score(args.leap, genes, refine)
        print(f"step / {refine}: one flight {m['flight_rotation_deg']:.0f} ± "
              f"{m['flight_rotation_deg_std']:.0f} deg over 4 starts, apex "
              f"{m['apex_height_bl']:.2f} BL")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
