"""A progress bar (rich) for long runs: env steps, the best value of the headline metric, ETA.
It is a logger sink, so every learner drives it the same way; quiet when output is not a
terminal."""

from __future__ import annotations

import math
import sys


class ProgressSink:
    """Shows env steps against the budget and the best ``metric`` so far."""

    def __init__(self, total: int, metric: str = "eval/return") -> None:
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.metric, self.best = metric, -math.inf
        self._progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                                  MofNCompleteColumn(), TextColumn("{task.fields[best]}"),
                                  TimeElapsedColumn(), TimeRemainingColumn())
        self._task = self._progress.add_task("env steps", total=total, best="")
        self._progress.start()

    @classmethod
    def if_terminal(cls, total: int, metric: str = "eval/return") -> ProgressSink | None:
        return cls(total, metric) if sys.stdout.isatty() else None

    def scalar(self, tag: str, value: float, step: int) -> None:
        if tag == self.metric:
            self.best = max(self.best, value)
        self._progress.update(self._task, completed=step,
                              best=f"best {self.metric} {self.best:.3f}")

    def text(self, tag: str, text: str, step: int) -> None:
        pass

    def close(self) -> None:
        self._progress.stop()
