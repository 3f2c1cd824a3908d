"""One logger, pluggable sinks (after stable-baselines3's ``common/logger.py``).

Every learner logs through a :class:`Logger`: scalars with a fixed tag and the global step,
which is always the number of env steps consumed (CleanRL's convention), and text (e.g. the
hyperparameters). Sinks: TensorBoard event files, a CSV of the same scalars, memory (tests).

A run folder's sinks write each (tag, step) once. A killed run resumes from its last
checkpoint, and every learner resumes exactly, so it logs again, with the same values, what it
had logged between that checkpoint and the kill: the file sinks read what they already hold
when they open and do not write it twice (no duplicate rows), and they write each record
through to the file at once (a kill loses none of what was logged before the checkpoint).
"""

from __future__ import annotations

import csv
import io
import math
import os
from pathlib import Path
from typing import Protocol

from .storage.files import check_size, make_dirs, open_file
from .storage.tree import listing


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


def _csv_held(handle: int, path: Path) -> set[tuple[str, int]]:
    """The (tag, step) of every row of a CSV sink's open file, after cutting off a last row a
    kill left unfinished (no newline); ValueError naming the file when it is not such a file."""
    data = os.pread(handle, check_size(handle, path, "scalars"), 0)
    if data and not data.endswith(b"\n"):
        data = data[:data.rfind(b"\n") + 1]
        os.ftruncate(handle, len(data))
    try:
        rows = list(csv.reader(io.StringIO(data.decode(), newline="")))
    except (UnicodeDecodeError, csv.Error) as error:
        raise ValueError(f"{path}: not a scalars file ({error})") from None
    if rows[:1] not in ([], [["step", "tag", "value"]]):
        raise ValueError(f"{path}: not a scalars file (its header is {rows[0]})")
    try:
        return {(tag, int(step)) for step, tag, _ in rows[1:]}
    except ValueError as error:
        raise ValueError(f"{path}: a row is not step,tag,value ({error})") from None


class CsvSink:
    """Appends ``step,tag,value`` rows to a CSV file (flushed every row), each (tag, step)
    once (see the module's docstring); the file opened as a run folder's files are
    (:func:`~animat.learners.storage.files.open_file`: no link followed)."""

    def __init__(self, path: str | Path) -> None:
        path = Path(path)
        make_dirs(path.parent)
        handle = open_file(path, os.O_RDWR | os.O_APPEND | os.O_CREAT)
        try:
            self._held = _csv_held(handle, path)
        except BaseException:
            os.close(handle)
            raise
        self._file = os.fdopen(handle, "a", newline="")
        self._writer = csv.writer(self._file)
        if os.fstat(handle).st_size == 0:
            self._writer.writerow(["step", "tag", "value"])

    def scalar(self, tag: str, value: float, step: int) -> None:
        if (tag, step) in self._held:
            return
        self._held.add((tag, step))
        self._writer.writerow([step, tag, repr(value)])
        self._file.flush()

    def text(self, tag: str, text: str, step: int) -> None:
        pass

    def close(self) -> None:
        self._file.close()


def _events_held(log_dir: Path) -> set[tuple[str, int]]:
    """The (tag, step) of every value in the event files of ``log_dir`` (a record a kill cut
    short is passed over)."""
    from tensorboard.backend.event_processing.event_file_loader import EventFileLoader

    held: set[tuple[str, int]] = set()
    for path in listing(log_dir, "events.out.tfevents.*", "events"):
        for event in EventFileLoader(str(path)).Load():
            held.update((value.tag, int(event.step)) for value in event.summary.value)
    return held


class TensorBoardSink:
    """TensorBoard event files in ``log_dir`` (torch's SummaryWriter), each (tag, step) once,
    flushed at every record (see the module's docstring)."""

    def __init__(self, log_dir: str | Path) -> None:
        from torch.utils.tensorboard import SummaryWriter

        self._held = _events_held(make_dirs(log_dir))
        self._writer = SummaryWriter(log_dir=str(log_dir))

    def _new(self, tag: str, step: int) -> bool:
        if (tag, step) in self._held:
            return False
        self._held.add((tag, step))
        return True

    def scalar(self, tag: str, value: float, step: int) -> None:
        if self._new(tag, step):
            self._writer.add_scalar(tag, value, step)
            self._writer.flush()

    def text(self, tag: str, text: str, step: int) -> None:
        if self._new(f"{tag}/text_summary", step):  # the tag add_text writes
            self._writer.add_text(tag, text, step)
            self._writer.flush()

    def hparams(self, params: dict[str, object], metrics: dict[str, float]) -> None:
        """Into the same log folder (TensorBoard's HParams tab); the metrics are written under
        ``hparams/`` so that they do not mix with the run's curves; once per log folder (a
        resumed run's second call writes nothing)."""
        if not self._new("_hparams_/experiment", 0):  # the tag add_hparams writes
            return
        self._writer.add_hparams(params, {f"hparams/{k}": v for k, v in metrics.items()},
                                 run_name=".")

    def close(self) -> None:
        self._writer.flush()
        self._writer.close()
