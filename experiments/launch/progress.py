"""Progress of a long run, as a logger sink, so every learner drives it the same way: a bar
(rich) on a terminal, log lines elsewhere (under ``nohup`` or a batch scheduler), and a notice
while the physics kernels compile on a machine's first run."""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

LOG_EVERY = 0.1  # off a terminal, a line each time another tenth of the budget is run


class ProgressSink:
    """Shows env steps against the budget and the best ``metric`` so far, as a bar."""

    def __init__(self, total: int, metric: str = "eval/return") -> None:
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self.metric, self.best, self.steps = metric, -math.inf, 0
        self._progress = Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                                  MofNCompleteColumn(), TextColumn("{task.fields[best]}"),
                                  TimeElapsedColumn(), TimeRemainingColumn())
        self._task = self._progress.add_task("env steps", total=total, best="")
        self._progress.start()

    @classmethod
    def for_output(cls, total: int, metric: str = "eval/return", label: str = ""
                   ) -> ProgressSink | ProgressLog:
        """A bar on a terminal, log lines (:class:`ProgressLog`, each with ``label``: the run
        folder's name in a sweep) anywhere else."""
        return cls(total, metric) if sys.stdout.isatty() else ProgressLog(total, metric, label)

    def scalar(self, tag: str, value: float, step: int) -> None:
        if tag == self.metric:
            self.best = max(self.best, value)
        self.steps = max(self.steps, step)
        self._progress.update(self._task, completed=step,
                              best=f"best {self.metric} {self.best:.3f}")

    def text(self, tag: str, text: str, step: int) -> None:
        pass

    def finish(self, env_steps: int) -> None:
        """The run is done, having run ``env_steps`` (a learner may run fewer than its budget,
        whole generations or rollouts of it): the bar ends full there."""
        self.steps = env_steps
        self._progress.update(self._task, total=env_steps, completed=env_steps)

    def close(self) -> None:
        self._progress.stop()


class ProgressLog:
    """Off a terminal: a line on stdout each time another ``LOG_EVERY`` of the budget is run,
    with the env steps, their rate since the start and the best ``metric`` so far; and one
    when the run is done."""

    def __init__(self, total: int, metric: str = "eval/return", label: str = "") -> None:
        self.total, self.metric, self.best, self.steps = max(int(total), 1), metric, -math.inf, 0
        self.label = f"{label}: " if label else ""
        self._start, self._logged = time.monotonic(), 0

    def scalar(self, tag: str, value: float, step: int) -> None:
        if tag == self.metric:
            self.best = max(self.best, value)
        self.steps = max(self.steps, step)
        tenth = int(self.steps / self.total / LOG_EVERY)
        if tenth > self._logged:
            self._logged = tenth
            self._line(f"{min(100 * self.steps // self.total, 100)}%")

    def text(self, tag: str, text: str, step: int) -> None:
        pass

    def finish(self, env_steps: int) -> None:
        self.steps = env_steps
        self._line("done")

    def close(self) -> None:
        pass

    def _line(self, what: str) -> None:
        rate = self.steps / max(time.monotonic() - self._start, 1e-9)
        best = f", best {self.metric} {self.best:.4g}" if self.best > -math.inf else ""
        print(f"animat: {self.label}{what}: {self.steps:,} of {self.total:,} env steps, "
              f"{rate:,.0f} env steps/s{best}", flush=True)


def kernels_compiled() -> bool:
    """Whether Numba's on-disk cache holds the fused physics step (then a run starts at once);
    False on a machine's first run, or after the kernels' code changed."""
    import numba
    from numba.misc.appdirs import AppDirs

    from animat.envs.physics import integrator

    folders = [Path(integrator.__file__).parent / "__pycache__",  # beside the code, or
               Path(AppDirs(appname="numba", appauthor=False).user_cache_dir)]  # the user's
    if numba.config.CACHE_DIR:
        folders.append(Path(numba.config.CACHE_DIR))
    return any(any(folder.rglob("integrator.step_chunk*.nbi")) for folder in folders
               if folder.is_dir())


def compile_notice() -> None:
    """One line on stderr when the physics kernels are about to compile (a minute or two)."""
    if not kernels_compiled():
        print("animat: compiling the physics kernels (the first run on this machine; a minute "
              "or two, then cached)", file=sys.stderr, flush=True)
