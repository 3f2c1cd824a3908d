"""The stability sweep of ``docs/integrators.md``: legal drives (random, the alternating drive
that blows the explicit fish up, bang-bang at every period from 1 to 20 env steps) over the fish
and the dolphin in both waters, for each integrator and step; and the loop that drives a batch of
bodies and watches their tissue, which the accuracy table's invariants use too
(:mod:`animat.experiments.bench.integrators`)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ...envs.bodies.fish import fish_body
from ...envs.physics.integrator import step_batch
from ...envs.physics.system import DEFAULT_DT, System, Water

ENV_DT = 0.05  # s, the fish's and the dolphin's env step
DOLPHIN_DT = ENV_DT / 80  # s, the dolphin's default explicit step


def drives(bodies: int, rng: np.random.Generator) -> dict[str, Callable[[int], np.ndarray]]:
    """The legal drives of the stability sweep, each ``drive(k)`` -> activations (bodies, 6)
    at env step k: random (new each step), the alternating drive that blows up the explicit
    step (the front three muscles against the back three, swapped every step) and bang-bang
    with every period from 1 to 20 env steps (each muscle on or off, its own phase)."""
    alternate = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    out = {"random": lambda k: rng.uniform(0.0, 1.0, (bodies, 6)),
           "alternating": lambda k: np.tile(alternate if k % 2 else 1.0 - alternate,
                                            (bodies, 1))}
    phases = rng.integers(0, 40, (bodies, 6))
    for period in range(1, 21):
        out[f"bang-bang {period}"] = (
            lambda k, p=period: (((k + phases) // p) % 2).astype(float))
    return out


STABILITY_COLUMNS = {"explicit": ("explicit", None), "implicit 50 ms": ("implicit", 0.05),
                     "implicit 25 ms": ("implicit", 0.025),
                     "implicit 12.5 ms": ("implicit", 0.0125)}


def stability(bodies: int = 32, seconds: float = 20.0) -> str:
    """A markdown table: for the fish and the dolphin in each water (rows) and each integrator
    and step (columns), how many of the sweep's drives (:func:`drives`) keep all ``bodies``
    bodies finite with every element within 0.5-2 of its rest length for ``seconds``, and the
    shortest and longest element seen under the drives that did."""
    from ...envs.bodies.dolphin import dolphin_body
    lines = ["| body, water | " + " | ".join(STABILITY_COLUMNS) + " |",
             "|---" * (len(STABILITY_COLUMNS) + 1) + "|"]
    for name, body, explicit_dt in (("fish", fish_body(), DEFAULT_DT),
                                    ("dolphin", dolphin_body(), DOLPHIN_DT)):
        for model in ("reactive", "resistive"):
            cells = []
            for integrator, dt in STABILITY_COLUMNS.values():
                dt = explicit_dt if dt is None else dt
                system = System(body, Water(model=model), dt=dt, integrator=integrator)
                sweep = drives(bodies, np.random.default_rng(0))
                results = [_swept(system, drive, bodies, seconds) for drive in sweep.values()]
                kept = [r for r in results if r[0]]
                low = min((r[1] for r in kept), default=np.nan)
                high = max((r[2] for r in kept), default=np.nan)
                cells.append(f"{len(kept)}/{len(results)} ({low:.2f}-{high:.2f})")
            lines.append(f"| {name}, {model} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _swept(system: System, drive: Callable[[int], np.ndarray], bodies: int, seconds: float
           ) -> tuple[bool, float, float]:
    """Whether every body stays finite and sound under ``drive``, and the shortest and longest
    element seen (shares of rest length; NaN where a body went non-finite)."""
    sound, lows, highs = driven(system, drive, noisy_start(system.body, bodies), seconds)
    if not sound.all() and not np.isfinite(highs).all():
        return False, np.nan, np.nan
    return bool(sound.all()), float(lows.min()), float(highs.max())


def noisy_start(body, bodies: int, seed: int = 1) -> np.ndarray:
    """(bodies, N, 3) m: the rest shape with each coordinate moved by up to 0.002 BL (seeded),
    as the envs' reset noise moves it."""
    rng = np.random.default_rng(seed)
    x = np.repeat(body.rest_positions[None], bodies, 0)
    return x + 0.002 * body.length * rng.uniform(-1.0, 1.0, x.shape)


def driven(system: System, drive: Callable[[int], np.ndarray], x0: np.ndarray, seconds: float
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Step bodies from ``x0`` (B, N, 3) at rest under ``drive(k)`` -> activations (B, A) at
    env step k for ``seconds``: each body's soundness (finite throughout, every element within
    0.5-2 of its rest length), and its shortest and longest element (shares of rest length;
    inf once it went non-finite), each (B,)."""
    body, x = system.body, x0.copy()
    v, u0 = np.zeros_like(x), np.zeros((x.shape[0], body.num_actuators))
    i, j = body.elements[:, 0], body.elements[:, 1]
    lows, highs = np.full(x.shape[0], np.inf), np.zeros(x.shape[0])
    substeps = int(round(ENV_DT / system.dt))
    with np.errstate(all="ignore"):
        for k in range(int(round(seconds / ENV_DT))):
            u = drive(k)
            step_batch(x, v, u0, u, np.zeros((x.shape[0], 2)), substeps, system.kernel_args)
            u0 = u
            share = np.linalg.norm(x[:, j] - x[:, i], axis=2) / body.rest_lengths
            finite = np.isfinite(share).all(axis=1)
            lows = np.where(finite, np.minimum(lows, share.min(axis=1)), lows)
            highs = np.where(finite, np.maximum(highs, share.max(axis=1)), np.inf)
    return np.isfinite(highs) & (lows >= 0.5) & (highs <= 2.0), lows, highs
