"""One logger, pluggable sinks (after stable-baselines3's ``common/logger.py``).

Every learner logs through a :class:`Logger`: scalars with a fixed tag and the global step,
which is always the number of env steps consumed (CleanRL's convention), and text (e.g. the
hyperparameters). Sinks: TensorBoard event files, a CSV of the same scalars, memory (tests).
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Protocol


class Sink(Protocol):
    def scalar(self, tag: str, value: float, step: int) -> None: ...
    def text(self, tag: str, text: str, step: int) -> None: ...
    def close(self) -> None: ...


class Logger:
    """Fans scalars and text out to its sinks."""

    def __init__(self, sinks: list[Sink] | None = None) -> None:
        self.sinks = list(sinks or [])

    def scalar(self, tag: str, value: float, step: int) -> None:
        value = float(value)
        if not math.isfinite(value):
            raise ValueError(f"scalar {tag!r} at step {step} is not finite: {value}")
        for sink in self.sinks:
            sink.scalar(tag, value, int(step))

    def scalars(self, values: dict[str, float], step: int) -> None:
        for tag, value in values.items():
            self.scalar(tag, value, step)

    def text(self, tag: str, text: str, step: int = 0) -> None:
        for sink in self.sinks:
            sink.text(tag, text, int(step))

    def hparams(self, params: dict[str, object], metrics: dict[str, float]) -> None:
        """A run's hyperparameters (flat: name -> number, string or bool) beside its final
        ``metrics``, for the sinks that keep them (TensorBoard's HParams view)."""
        for sink in self.sinks:
            if hasattr(sink, "hparams"):
                sink.hparams(params, metrics)

    def close(self) -> None:
        for sink in self.sinks:
            sink.close()


class MemorySink:
    """Keeps everything in lists: ``records`` of (tag, value, step) and ``texts``."""

    def __init__(self) -> None:
        self.records: list[tuple[str, float, int]] = []
        self.texts: list[tuple[str, str, int]] = []

    def scalar(self, tag: str, value: float, step: int) -> None:
        self.records.append((tag, value, step))

    def text(self, tag: str, text: str, step: int) -> None:
        self.texts.append((tag, text, step))

    def close(self) -> None:
        pass

    def series(self, tag: str) -> list[tuple[int, float]]:
        return [(step, value) for t, value, step in self.records if t == tag]


class CsvSink:
    """Appends ``step,tag,value`` rows to a CSV file (flushed every row)."""

    def __init__(self, path: str | Path) -> None:
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        new = not path.exists()
        self._file = path.open("a", newline="")
        self._writer = csv.writer(self._file)
        if new:
            self._writer.writerow(["step", "tag", "value"])

    def scalar(self, tag: str, value: float, step: int) -> None:
        self._writer.writerow([step, tag, repr(value)])
        self._file.flush()

    def text(self, tag: str, text: str, step: int) -> None:
        pass

    def close(self) -> None:
        self._file.close()


class TensorBoardSink:
    """TensorBoard event files in ``log_dir`` (torch's SummaryWriter)."""

    def __init__(self, log_dir: str | Path) -> None:
        from torch.utils.tensorboard import SummaryWriter

        self._writer = SummaryWriter(log_dir=str(log_dir))

    def scalar(self, tag: str, value: float, step: int) -> None:
        self._writer.add_scalar(tag, value, step)

    def text(self, tag: str, text: str, step: int) -> None:
        self._writer.add_text(tag, text, step)

    def hparams(self, params: dict[str, object], metrics: dict[str, float]) -> None:
        """Into the same log folder (TensorBoard's HParams tab); the metrics are written under
        ``hparams/`` so that they do not mix with the run's curves."""
        self._writer.add_hparams(params, {f"hparams/{k}": v for k, v in metrics.items()},
                                 run_name=".")

    def close(self) -> None:
        self._writer.flush()
        self._writer.close()
