"""How each integrator's figures move with its step: the accuracy table of ``docs/integrators.md``.

Each figure a researcher reads off the bodies (the demo's cruise speed, Strouhal number, stride
and slip, the C-start, the 90-degree turn-MC, the fin-MC's pitch, the dolphin's stroke and pitch
turn) and the invariants (momentum in a vacuum, rotation invariance, energy decay, tissue strain)
are measured for the explicit integrator at its default step and for the implicit one
(:mod:`animat.envs.physics.implicit`, backward Euler) at 6.25, 12.5, 25 and 50 ms, against the
converged reference: the explicit integrator at a quarter of its default step. A second table
(:func:`theta_sweep`) gives, for the implicit step's theta and step, the fish's cruise speed
in both waters and how many of 16 fish stay finite under 20 s of random actions.

    python -m animat.experiments.bench.integrators            # print the tables
    python -m animat.experiments.bench.integrators --write    # and write docs/integrators.md

A third table (:func:`stability`) sweeps legal drives (random, the alternating drive, bang-bang
at every period from 1 to 20 env steps) over the fish and the dolphin in both waters.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

import numpy as np

from ...envs.bodies.fish import fish_body
from ...envs.core.env import BodyEnv
from ...envs.motor.fish import (
    CStartParams,
    FinParams,
    calibrated,
    fin_mc,
    swim_mc,
    to_action,
    turn_duration,
    turn_mc,
)
from ...envs.physics.integrator import step_batch
from ...envs.physics.observe import momenta
from ...envs.physics.system import DEFAULT_DT, System, Water, vacuum
from ..biology import c_start, dolphin_cruise, dolphin_turn, fish_cruise, play
from .stability import DOLPHIN_DT, ENV_DT, driven, noisy_start, stability

IMPLICIT_STEPS = (0.05, 0.025, 0.0125, 0.00625)  # s
ANGLES = {"C-start heading at 0.5 s", "turn-MC heading", "dolphin pitch turn", "dolphin pitch"}


def columns() -> dict[str, tuple[dict, dict]]:
    """Each column's name and (the fish's env physics, the dolphin's)."""
    def physics(dt: float, integrator: str) -> dict:
        return {"physics_dt": dt, "frame_skip": int(round(ENV_DT / dt)), "integrator": integrator}
    out = {"reference": (physics(DEFAULT_DT / 4, "explicit"), physics(DOLPHIN_DT / 4, "explicit")),
           "explicit": (physics(DEFAULT_DT, "explicit"), physics(DOLPHIN_DT, "explicit"))}
    for dt in IMPLICIT_STEPS:
        out[f"implicit {dt * 1000:g} ms"] = (physics(dt, "implicit"), physics(dt, "implicit"))
    return out


def fish_figures(model: str, physics: dict) -> dict[str, float]:
    """The fish's figures in water ``model``: cruise (U BL/s, St, stride BL, slip), the
    C-start's heading 0.5 s in (deg), the 90-degree turn-MC's heading when it ends (deg) and
    the fin-MC's depth change in 6 s of swimming with the fins pitched up (BL)."""
    swim, turn = calibrated(model)
    water = {"model": model}
    cruise = fish_cruise(water, swim, physics=physics)
    heading = c_start(water, CStartParams(), physics=physics)
    out = {f"{model} {k}": cruise[k] for k in ("U", "St", "stride", "slip")}
    out[f"{model} C-start heading at 0.5 s"] = float(heading[int(round(0.5 / ENV_DT)) - 1])
    end = turn_duration(np.pi / 2, turn)
    env = BodyEnv("swim", duration=end + 1.0, water=water, start_spread="point", **physics)
    infos, _ = play(env, lambda t: turn_mc(np.pi / 2, t, True, turn), end)
    out[f"{model} turn-MC heading"] = float(infos[-1]["heading_deg"])
    fins = fin_mc(pitch=1.0) / FinParams().max_angle
    env = BodyEnv("swim", duration=7.0, water=water, start_spread="point", fins=True, **physics)
    infos, _ = play(env, lambda t: swim_mc(1.0, t, swim), 6.0, fins=fins)
    out[f"{model} fin depth change"] = float(infos[-1]["com"][2] - infos[0]["com"][2]
                                            ) / env.body.length
    return out


def dolphin_figures(physics: dict) -> dict[str, float]:
    """The dolphin's stroke (U BL/s, St) in its pool and its pitch at the end, and its 90-degree
    pitch-up turn-MC's pitch when the MC ends (deg), reactive water."""
    cruise = dolphin_cruise({"model": "reactive"}, physics=physics)
    turned, _ = dolphin_turn("reactive", "up", 90.0, physics=physics)
    return {"dolphin U": cruise["U"], "dolphin St": cruise["St"],
            "dolphin pitch": cruise["pitch"], "dolphin pitch turn": turned}


def invariants(physics: dict, seconds: float = 10.0, bodies: int = 8) -> dict[str, float]:
    """The fish's invariants under random actions (one new activation per env step, seeded):
    in a vacuum, the largest drift of the linear (kg m/s) and angular momentum (kg m^2/s)
    over ``seconds``, relative to their start (the start's random velocities, 0.05 m/s per
    node); a rigidly rotated start's largest distance from the rotated trajectory (mm); the
    share of the elastic and kinetic energy left 2 s after a stretched, unforced start (in
    the reactive water); the shortest and longest element over the run, as a share of its
    rest length, in the reactive water."""
    body, dt = fish_body(), physics["physics_dt"]
    steps, substeps = int(round(seconds / ENV_DT)), physics["frame_skip"]
    rng = np.random.default_rng(0)
    u = rng.uniform(0.0, 1.0, (steps + 1, bodies, body.num_actuators))
    x0 = np.repeat(body.rest_positions[None], bodies, 0) + 0.002 * rng.normal(size=(bodies, 23, 3))
    v0 = 0.05 * rng.normal(size=x0.shape)
    out = {}
    system = System(body, vacuum(), dt=dt, integrator=physics["integrator"])
    x, v = x0.copy(), v0.copy()
    start = _momenta(x, v, body.masses)
    worst = np.zeros(2)
    for k in range(steps):
        step_batch(x, v, u[k], u[k + 1], np.zeros((bodies, 2)), substeps, system.kernel_args)
        now = _momenta(x, v, body.masses)
        worst = np.maximum(worst, [np.abs(now[i] - start[i]).max() / np.abs(start[i]).max()
                                   for i in range(2)])
    out["vacuum linear momentum drift"], out["vacuum angular momentum drift"] = worst
    out["rotated start, mm off"] = _rotation_gap(body, physics, x0[:1], v0[:1], u[:, :1], steps)
    out["energy left after 2 s"] = _energy_left(body, physics, x0, substeps)
    out["shortest element"], out["longest element"] = _tissue(body, physics, x0, u, steps)
    return out


def _momenta(x: np.ndarray, v: np.ndarray, masses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    com = (x * masses[None, :, None]).sum(axis=1) / masses.sum()
    return momenta(x, v, masses, com)


def _rotation_gap(body, physics: dict, x0, v0, u, steps: int) -> float:
    """mm: the largest gap between the rotated start's trajectory and the rotated trajectory
    (a rotation of 1 rad about a tilted axis), in a vacuum (the water's gravity and buoyancy
    pick a direction)."""
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    rotation = np.eye(3) + np.sin(1.0) * k + (1 - np.cos(1.0)) * k @ k
    system = System(body, vacuum(), dt=physics["physics_dt"], integrator=physics["integrator"])
    pair = [(x0.copy(), v0.copy()), (x0 @ rotation.T, v0 @ rotation.T)]
    gap = 0.0
    for step in range(steps):
        for x, v in pair:
            step_batch(x, v, u[step], u[step + 1], np.zeros((1, 2)), physics["frame_skip"],
                       system.kernel_args)
        gap = max(gap, float(np.abs(pair[0][0] @ rotation.T - pair[1][0]).max()))
    return 1000.0 * gap


def _energy_left(body, physics: dict, x0, substeps: int) -> float:
    """The elastic and kinetic energy left 2 s after the bodies start stretched (their start
    noise) and at rest, unforced, in the reactive water, as a share of the start's."""
    system = System(body, Water(), dt=physics["physics_dt"], integrator=physics["integrator"])
    x, v = x0.copy(), np.zeros_like(x0)
    rest = np.zeros((x.shape[0], body.num_actuators))
    energy = [_energy(body, x, v)]
    for _ in range(int(round(2.0 / ENV_DT))):
        step_batch(x, v, rest, rest, np.zeros((x.shape[0], 2)), substeps, system.kernel_args)
    energy.append(_energy(body, x, v))
    return float(energy[1].sum() / energy[0].sum())


def _energy(body, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(B,) the elements' elastic energy at their rest lengths plus the nodes' kinetic energy
    in the centre of mass's frame, J."""
    i, j = body.elements[:, 0], body.elements[:, 1]
    stretch = np.linalg.norm(x[:, j] - x[:, i], axis=2) - body.rest_lengths
    com_v = (v * body.masses[None, :, None]).sum(axis=1) / body.masses.sum()
    kinetic = 0.5 * (body.masses[None, :, None] * (v - com_v[:, None]) ** 2).sum(axis=(1, 2))
    return 0.5 * (body.stiffness * stretch**2).sum(axis=1) + kinetic


def _tissue(body, physics: dict, x0, u, steps: int) -> tuple[float, float]:
    """The shortest and longest element (share of its rest length) under random actions
    ``u`` (steps + 1, B, A), reactive water."""
    system = System(body, Water(), dt=physics["physics_dt"], integrator=physics["integrator"])
    _, lows, highs = driven(system, lambda k: u[k + 1], x0, steps * ENV_DT)
    return float(lows.min()), float(highs.max())


def measure(column: tuple[dict, dict]) -> dict[str, float]:
    """Every figure of one column (the fish's physics, the dolphin's); a run that went
    non-finite gives NaN figures."""
    fish, dolphin = column
    out: dict[str, float] = {}
    for part in (lambda: fish_figures("reactive", fish), lambda: fish_figures("resistive", fish),
                 lambda: dolphin_figures(dolphin), lambda: invariants(fish)):
        out.update(_finite_or_nan(part))
    return out


def _finite_or_nan(part: Callable[[], dict]) -> dict[str, float]:
    """``part()``'s figures; none (shown as failed) if its run raised on a non-finite state."""
    with np.errstate(all="ignore"):
        try:
            return {k: float(value) for k, value in part().items()}
        except (ValueError, FloatingPointError, ZeroDivisionError):
            return {}


INVARIANTS = ("vacuum linear momentum drift", "vacuum angular momentum drift",
              "rotated start, mm off", "energy left after 2 s", "shortest element",
              "longest element")


def deviation(name: str, value: float, reference: float) -> str:
    """A cell: the value and its distance from the reference (deg for angles, % otherwise;
    the invariants as they are)."""
    if not np.isfinite(value):
        return "non-finite"
    if name in INVARIANTS:
        return f"{value:.3g}"
    if any(name.endswith(angle) for angle in ANGLES):
        return f"{value:.1f} ({value - reference:+.1f}°)"
    return f"{value:.3g} ({100 * (value - reference) / abs(reference):+.1f}%)"


def within_bound(name: str, value: float, reference: float) -> bool:
    """Whether a figure lies within 5% (angles 5 degrees) of the reference."""
    if not np.isfinite(value):
        return False
    if any(name.endswith(angle) for angle in ANGLES):
        return abs(value - reference) <= 5.0
    return abs(value - reference) <= 0.05 * abs(reference)


def table(results: dict[str, dict[str, float]]) -> str:
    """A markdown table: a row per figure, a column per integrator and step, and a last row
    saying which columns keep every figure within the bound."""
    names = list(results)
    reference = results["reference"]
    lines = ["| figure | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for figure in reference:
        cells = [deviation(figure, results[c].get(figure, np.nan), reference[figure])
                 if c != "reference" else f"{reference[figure]:.4g}" for c in names]
        lines.append(f"| {figure} | " + " | ".join(cells) + " |")
    verdict = ["—" if c == "reference" else
               ("yes" if all(within_bound(f, results[c].get(f, np.nan), reference[f])
                             for f in reference if f not in INVARIANTS) else "no")
               for c in names]
    lines.append("| every figure within 5% (5°) | " + " | ".join(verdict) + " |")
    return "\n".join(lines)


THETAS = (0.5, 0.6, 0.75, 1.0)


def theta_sweep(seconds: float = 20.0, bodies: int = 16) -> str:
    """A markdown table: for each theta (rows) and implicit step (columns), the fish's cruise
    speed at full swim-MC in each water against the reference's (%), and the number of
    ``bodies`` fish that stay finite with every element within 0.5-2 of its rest length under
    ``seconds`` of random actions (a new activation each env step, reactive water)."""
    body = fish_body()
    reference = {model: _cruise_speed(body, model, "explicit", DEFAULT_DT / 4, 1.0)
                 for model in ("reactive", "resistive")}
    head = " | ".join(f"{dt * 1000:g} ms" for dt in IMPLICIT_STEPS)
    lines = [f"| theta | {head} |", "|---" * (len(IMPLICIT_STEPS) + 1) + "|"]
    for theta in THETAS:
        cells = []
        for dt in IMPLICIT_STEPS:
            speeds = [100 * (_cruise_speed(body, m, "implicit", dt, theta) - reference[m])
                      / reference[m] for m in reference]
            kept = _kept(body, dt, theta, seconds, bodies)
            cells.append(" / ".join("non-finite" if not np.isfinite(x) else f"{x:+.1f}%"
                                    for x in speeds) + f", {kept}/{bodies}")
        lines.append(f"| {theta:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _cruise_speed(body, model: str, integrator: str, dt: float, theta: float,
                  seconds: float = 5.0) -> float:
    """The fish's speed (BL/s) over the last half of ``seconds`` of the full-speed swim-MC,
    from rest, along x (the start heading)."""
    system = System(body, Water(model=model), dt=dt, integrator=integrator, theta=theta)
    swim, _ = calibrated(model)
    x, v = body.rest_positions[None].copy(), np.zeros((1,) + body.rest_positions.shape)
    u0, steps, coms = np.zeros((1, body.num_actuators)), int(round(seconds / ENV_DT)), []
    with np.errstate(all="ignore"):
        for k in range(steps):
            u = 0.5 * (to_action(swim_mc(1.0, (k + 1) * ENV_DT, swim))[None] + 1.0)
            step_batch(x, v, u0, u, np.zeros((1, 2)), int(round(ENV_DT / dt)),
                       system.kernel_args)
            u0 = u
            coms.append(float((x[0, :, 0] * body.masses).sum() / body.masses.sum()))
    half = steps // 2
    return (coms[-1] - coms[half - 1]) / ((steps - half) * ENV_DT) / body.length


def _kept(body, dt: float, theta: float, seconds: float, bodies: int) -> int:
    """How many of ``bodies`` fish stay finite, every element within 0.5-2 of its rest length,
    under ``seconds`` of random actions at the implicit step (dt, theta), reactive water."""
    system = System(body, Water(), dt=dt, integrator="implicit", theta=theta)
    rng = np.random.default_rng(0)
    sound, _, _ = driven(system, lambda k: rng.uniform(0.0, 1.0, (bodies, body.num_actuators)),
                         noisy_start(body, bodies), seconds)
    return int(sound.sum())


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m animat.experiments.bench.integrators",
                                     description=__doc__.split("\n")[0])
    parser.add_argument("--write", action="store_true",
                        help="also write the tables into docs/integrators.md")
    parser.add_argument("--bodies", type=int, default=32,
                        help="bodies per drive in the stability sweep (default 32)")
    parser.add_argument("--seconds", type=float, default=20.0,
                        help="seconds of each drive in the stability sweep (default 20)")
    args = parser.parse_args(argv)
    results = {name: measure(column) for name, column in columns().items()}
    text = (table(results) + "\n\n" + theta_sweep() + "\n\n"
            + stability(args.bodies, args.seconds))
    print(text)
    if args.write:
        write_page(text)


def write_page(text: str) -> None:
    """Put the table between the markers of docs/integrators.md (the rest of the page is
    prose kept in the repository)."""
    page = Path(__file__).resolve().parents[2] / "docs" / "integrators.md"
    begin, end = "<!-- table: begin -->", "<!-- table: end -->"
    before, rest = page.read_text().split(begin)
    after = rest.split(end)[1]
    page.write_text(f"{before}{begin}\n{text}\n{end}{after}")


if __name__ == "__main__":
    main()
