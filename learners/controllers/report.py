"""What a black-box run reports of its controller (its artefacts): the learned tent controller
and its FFT abstraction, scored; after a refinement phase, the refined abstraction beside the
truncated one; and ``result_from``, which of them the run's result is
(:class:`ResultFrom`), read back as a player (:func:`reported_player`)."""

from __future__ import annotations

import json
from enum import StrEnum
from pathlib import Path

import numpy as np

from ..rollout import BatchEvaluator
from ..storage.files import CorruptFile
from .abstraction import AbstractController, abstract, most_compact
from .periodic import PeriodicPlayer, controller_from_vector
from .tent import TentController


class ResultFrom(StrEnum):
    """Which controller a run reports: ``result_from`` of its artefacts (written as the value,
    so result.json holds the same words as before the enum): the learning phase's best, or
    the refined FFT abstraction of it."""

    LEARNED = "learned"
    REFINED_ABSTRACTION = "refined abstraction"


def result_from(artefacts: dict, path: str | Path = "artefacts.json") -> ResultFrom:
    """The ``result_from`` of ``artefacts`` (read from ``path``); a run without one reports the
    learned controller. Any other value (null included) is a :class:`CorruptFile` naming the
    file and the field."""
    value = artefacts.get("result_from", ResultFrom.LEARNED.value)
    try:
        return ResultFrom(value)
    except ValueError:
        choices = ", ".join(json.dumps(r.value) for r in ResultFrom)
        raise CorruptFile(path, f"result_from is {json.dumps(value, default=str)}, not one of "
                                f"{choices}") from None


def reported_player(artefacts: dict, period: float | None) -> PeriodicPlayer:
    """The controller ``artefacts`` report (:func:`result_from`), played every ``period``."""
    if result_from(artefacts) is ResultFrom.REFINED_ABSTRACTION:
        return PeriodicPlayer(AbstractController.from_dict(artefacts["abstraction"]), period)
    nodes = artefacts["controller"]
    return PeriodicPlayer(TentController(np.array(nodes["nodes"]), nodes["t0"], nodes["t1"]),
                          period)


def eval_metrics(best: dict) -> dict[str, float]:
    """A phase's best ({``x``, ``return``, ``metrics``}) as ``eval/*`` metrics."""
    return {"eval/return": best["return"], **{f"eval/{k}": v for k, v in best["metrics"].items()}}


def samples(tent: TentController, period: float | None, steps: int | None = None
            ) -> int | None:
    """Samples of the FFT abstraction of ``tent``: the default over a period, else over the
    whole window, 4x finer than its nodes or, given the ``steps`` (env steps) it spans, one a
    step if that is finer: the env reads a controller only at the steps' ends, so the
    abstraction with every harmonic kept then plays exactly as the tent."""
    if period is not None:
        return None
    return max(4 * (tent.num_nodes - 1), int(steps or 0))


def abstraction_of(x: np.ndarray, nodes: int, period: float | None, duration: float,
                   threshold: float, max_parameters: int | None = None,
                   steps: int | None = None) -> AbstractController:
    """The FFT abstraction of the tent controller of ``x`` at ``threshold`` (over the period,
    or over the whole window of ``steps`` env steps for a non-periodic controller,
    :func:`samples`), its largest harmonics within ``max_parameters`` if given."""
    tent = controller_from_vector(x, nodes, period, duration)
    return abstract(tent, threshold, samples(tent, period, steps), max_parameters,
                    mirror=period is None)


def scores(controllers, period: float | None, evaluator: BatchEvaluator) -> list[dict]:
    """``eval/*`` metrics of each controller, played periodically (not charged)."""
    returns, metrics = evaluator.evaluate_players(
        [PeriodicPlayer(c, period) for c in controllers])
    return [{"eval/return": float(r), **{f"eval/{k}": float(v[j]) for k, v in
                                          metrics.items()}} for j, r in enumerate(returns)]


def learned_artefacts(x: np.ndarray, nodes: int, period: float | None, threshold: float | None,
                      evaluator: BatchEvaluator) -> dict:
    """The best learned controller ``x`` and its FFT abstraction: at the fixed ``threshold`` if
    one is given, else the most compact one within 10% of the learned objective; with what the
    abstraction scores (each simulation here is not charged to the budget)."""
    tent = controller_from_vector(x, nodes, period, evaluator.duration)
    artefacts = {"controller": {"nodes": tent.nodes.tolist(), "t0": tent.t0, "t1": tent.t1,
                                "periodic": period is not None},
                 "parameters": int(x.size),
                 "episode": {"task": evaluator.task.name,
                             "duration": evaluator.duration}}
    if threshold is not None:
        chosen = abstract(tent, threshold, samples(tent, period, evaluator.steps),
                          mirror=period is None)
    else:
        chosen, artefacts["abstraction_report"] = most_compact(
            tent, lambda cs: [-m["eval/return"] for m in scores(cs, period, evaluator)],
            samples=samples(tent, period, evaluator.steps), mirror=period is None)
    artefacts["abstraction"] = chosen.to_dict()
    artefacts["abstraction_metrics"] = {
        **scores([chosen], period, evaluator)[0], "parameters": chosen.num_parameters,
        "coefficients": chosen.num_coefficients, "refined": False}
    return artefacts


def refined_artefacts(support: AbstractController, best: dict, start: dict | None,
                      threshold: float, artefacts: dict) -> dict:
    """The refinement phase's ``best`` (frequency parameters of ``support``, the abstraction at
    ``threshold`` it started from, which scored ``start``) becomes the run's ``abstraction``;
    the truncation the "learn" phase chose moves to ``truncated_abstraction``;
    ``abstraction_metrics`` also report ``start`` (before refining)."""
    refined = support.with_frequency_parameters(best["x"])
    return {
        "truncated_abstraction": artefacts["abstraction"],
        "truncated_abstraction_metrics": artefacts["abstraction_metrics"],
        "abstraction": refined.to_dict(),
        "abstraction_metrics": {
            **eval_metrics(best), "parameters": refined.num_parameters,
            "coefficients": refined.num_coefficients, "refined": True,
            "threshold": threshold, "before_refining": start}}
