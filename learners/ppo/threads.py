"""Torch's threads beside Numba's: which runtime loads first, and how many threads each phase
of a PPO run gives torch.

Numba's parallel kernels (the envs) and torch (the network) each run on an OpenMP runtime of
their own: the system's libgomp and the one torch ships. Where Numba starts its threads
first, a PPO update on two threads runs slower than on one: the runtimes' idle threads, which
spin a while before they sleep, take the cores from each other's working ones (letting them
sleep at once, ``OMP_WAIT_POLICY=PASSIVE``, helps, but slows the envs' own kernels). Where
torch is loaded first, two threads update faster than one.
:func:`load_torch_first` is what the ``animat`` command does before a command that may learn,
and each process or Ray task a sweep or a tune starts;
a script that steps the envs and trains a network in one process should ``import torch``
before its first env step.
"""

from __future__ import annotations

import sys
from typing import Any


def load_torch_first() -> None:
    """Import torch (its OpenMP runtime with it) unless Numba's threads have started."""
    if not numba_started():
        import torch  # noqa: F401


def numba_started() -> bool:
    """Whether Numba's threading layer has started (its first parallel kernel has run)."""
    import numba

    try:
        numba.threading_layer()
    except ValueError:  # Numba's own signal: no threading layer has been started yet
        return False
    return True


def torch_loaded_late() -> bool:
    """Whether torch is still to be imported while Numba's threads run: the order in which
    torch's updates on more than one thread contend with them."""
    return "torch" not in sys.modules and numba_started()


def update_threads(hp: dict[str, Any]) -> int:
    """Torch's threads while the policy is updated: ``update_threads``, or ``torch_threads``
    where it is unset. While the envs step (on Numba's threads) torch keeps to
    ``torch_threads``: its idle threads, spinning for work, would take the cores from
    Numba's."""
    return int(hp.get("update_threads", hp["torch_threads"]))


def set_threads(count: int) -> None:
    """Torch's intra-op threads, set only where the count changes."""
    import torch

    if torch.get_num_threads() != count:
        torch.set_num_threads(count)
