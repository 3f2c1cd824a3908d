"""glibc's malloc set to keep the memory a PPO update frees, for its next minibatch to reuse.

Each minibatch of an update allocates tensors of megabytes and frees them: 128 compact
retinal images, 1 MB as SB3's rollout buffer keeps them (uint8), are 4 MB as the float32 the
network takes, and as much again once scaled to [0, 1]. glibc's malloc maps such blocks from
the kernel (``mmap``) and gives the free top of its heap back (``M_MMAP_THRESHOLD``,
``M_TRIM_THRESHOLD``: 128 KB to start with, raised as mapped blocks are freed, the second to
twice the first). With a minibatch's mix of sizes memory keeps going back to the kernel, and
each minibatch faults its pages in afresh, the kernel zeroing every one (costly above all in
a virtual machine). Fixing both thresholds high keeps the freed memory in the process. A
run's arithmetic is the same either way: only where its tensors live changes. The process
holds at most :data:`TRIM_THRESHOLD` of free heap beyond what it uses.

Elsewhere than glibc (macOS, musl) :func:`keep_freed_memory` does nothing: their allocators
have no such thresholds to set.
"""

from __future__ import annotations

import ctypes

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3  # glibc's <malloc.h>
MMAP_THRESHOLD = 32 << 20  # bytes: the largest glibc accepts; blocks above it still mmap
TRIM_THRESHOLD = 1 << 30  # bytes of free heap kept before any goes back to the kernel


def keep_freed_memory() -> bool:
    """Set glibc's ``M_MMAP_THRESHOLD`` to :data:`MMAP_THRESHOLD` and ``M_TRIM_THRESHOLD`` to
    :data:`TRIM_THRESHOLD` for the whole process (for good: the defaults' adaptive thresholds
    do not come back); whether both were set (False where the C library is not glibc)."""
    try:
        libc = ctypes.CDLL(None)
    except (OSError, TypeError):  # no C library to open by that name (Windows)
        return False
    if not hasattr(libc, "gnu_get_libc_version"):  # not glibc, whose numbers these are
        return False
    libc.mallopt.argtypes, libc.mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    mmap_set = libc.mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD) == 1
    trim_set = libc.mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD) == 1
    return mmap_set and trim_set
