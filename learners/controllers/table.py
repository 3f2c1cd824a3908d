"""A table of move codes as a black-box learner's encoding: one gene in [0, 1] per cell, read
as one of the table's moves (``floor(x * moves)``, 1 read as the last). The closed-loop tables
share it: the fish's switching table (:mod:`animat.learners.switching`) and the dolphin's stunt
table (:mod:`animat.learners.skills.stunt_learner`)."""

from __future__ import annotations

import numpy as np


class CellTableEncoding:
    """The encoding methods of a :class:`~animat.learners.blackbox.BlackBoxLearner` over a
    table: the learner sets ``shape`` (the table's) and ``moves`` (codes a cell may hold) in
    its ``_configure``; ``seed`` is the learner's."""

    shape: tuple[int, ...]
    moves: int
    seed: int

    def _fit_encoding(self, opt_params: dict) -> dict:
        return opt_params  # cells are not blocks of nodal values

    def _genes(self, actuators: int) -> tuple[int, str]:
        return int(np.prod(self.shape)), f"a table of {self.shape} moves"

    def _x0(self, num_actuators: int) -> np.ndarray:
        return np.random.default_rng(self.seed).uniform(0.0, 1.0, int(np.prod(self.shape)))

    def controller(self, vector: np.ndarray, duration: float) -> np.ndarray:
        """The table of move codes (``shape``) of a candidate's genes."""
        codes = np.minimum((np.asarray(vector) * self.moves).astype(int), self.moves - 1)
        return codes.reshape(self.shape)
