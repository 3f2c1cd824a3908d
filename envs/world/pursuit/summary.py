"""The metrics of a ``Animat/FishPursuit-v0`` episode (:class:`PursuitSummary`), gathered from
each step's info of :class:`animat.envs.world.pursuit.env.FishPursuitEnv`."""

from __future__ import annotations

import numpy as np


class PursuitSummary:
    """Episode metrics of a pursuit from each step's info (the same interface as
    :class:`animat.envs.tasks.base.EpisodeSummary`, one episode): ``fovea_fraction`` (the share
    of all the episode's frames with the prey in both foveas, the benchmark's headline),
    ``fovea_fraction_after_first`` (the share of the frames after the first foveation),
    ``first_foveation_s`` (s to the first frame with the
    prey in both foveas; the episode's length when there is none), ``captured`` (1 when the
    observer's head came within ``CAPTURE_BL`` of the prey's centre of mass, else 0),
    ``fovea_fraction_150`` (the same as ``fovea_fraction_after_first`` over the ``WINDOW`` =
    150 frames after the first foveation, or as many as the episode has),
    ``distance_closed_bl``, ``distractor_fraction`` and ``passer_fraction`` (the share of the
    frames after the first foveation with a distractor, or a passer, in both foveas and the
    prey not: the gaze taken by them), ``first_foveation_frame`` (-1: never), and
    over the frames with the prey in both foveas: ``vergence_first_deg`` and
    ``vergence_last_deg`` (means of the first and last ``ENDS`` = 40 of them) and
    ``range_error`` (the median of
    ``|range_estimate / target_distance - 1|`` over those where the eyes converge, so that
    the range is finite; NaN when there are none)."""

    WINDOW, ENDS = 150, 40
    CAPTURE_BL = 0.5  # BL, head to the prey's centre of mass: the head at the prey's flank

    def __init__(self, body_length: float, start_distance: float, dt: float) -> None:
        self.length, self.start, self.dt = body_length, start_distance, dt
        self.closest = start_distance
        self.frames, self.first, self.held, self.held_window = 0, None, 0, 0
        self.passer, self.distractor = 0, 0
        self.vergence: list[float] = []
        self.range_errors: list[float] = []
        self.last: dict = {}

    def update(self, info: dict) -> None:
        if not info.get("moved", True):
            return  # a look within a frame (``glances``): the frame counts once, when it ends
        if self.first is None and info["target_in_fovea"]:
            self.first = self.frames
        if self.first is not None:
            self.held += bool(info["target_in_fovea"])
            if self.frames < self.first + self.WINDOW:
                self.held_window += bool(info["target_in_fovea"])
            self.passer += bool(info["passer_in_fovea"] and not info["target_in_fovea"])
            self.distractor += bool(info.get("distractor_in_fovea", False)
                                    and not info["target_in_fovea"])
        if info["target_in_fovea"]:
            self.vergence.append(float(np.degrees(info["vergence"])))
            if np.isfinite(info["range_estimate"]):  # the eyes converge
                self.range_errors.append(abs(info["range_estimate"] / info["target_distance"]
                                             - 1))
        self.closest = min(self.closest, float(info["target_distance"]))
        self.frames += 1
        self.last = info

    def summary(self) -> dict[str, float]:
        after = max(self.frames - (self.first if self.first is not None else self.frames), 1)
        seen = self.first is not None
        return {"fovea_fraction": self.held / max(self.frames, 1),
                "fovea_fraction_after_first": self.held / after if seen else 0.0,
                "first_foveation_s": (self.first if seen else self.frames) * self.dt,
                "captured": float(self.closest <= self.CAPTURE_BL * self.length),
                "fovea_fraction_150": self.held_window / min(after, self.WINDOW) if seen else 0.0,
                "distractor_fraction": self.distractor / after,
                "passer_fraction": self.passer / after,
                "distance_closed_bl": (self.start - self.last["target_distance"]) / self.length,
                "first_foveation_frame": float(self.first if self.first is not None else -1),
                "vergence_first_deg": _mean(self.vergence[:self.ENDS]),
                "vergence_last_deg": _mean(self.vergence[-self.ENDS:]),
                "range_error": float(np.median(self.range_errors)) if self.range_errors
                else float("nan")}


def _mean(values: list[float]) -> float:
    return float(np.mean(values)) if values else float("nan")
