"""Faults planted in a run: a pickle that acts when it is unpickled (what a hostile run folder
would carry), and a logger sink that dies once the run has logged past a step, as a killed
process would, so that a resume from the last checkpoint can be compared with the whole run."""

from animat.learners.logger import MemorySink


class Planted:
    """A pickle that, unpickled, writes a file: what a hostile run folder would carry."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (open, (self.marker, "w"))


class Crash(Exception):
    """What :class:`CrashingSink` raises: the run dies there."""


class CrashingSink(MemorySink):
    """Dies (like a killed process) once the run has logged past ``step``."""

    def __init__(self, step: int) -> None:
        super().__init__()
        self.step = step

    def scalar(self, tag: str, value: float, step: int) -> None:
        if step > self.step:
            raise Crash
        super().scalar(tag, value, step)
