"""Once :func:`keep_freed_memory` has run, a block of megabytes comes from the heap, and once
freed stays there for the next to reuse, where glibc's defaults map it fresh from the kernel
(each case in a new interpreter: the thresholds are the process's)."""

import platform
import subprocess
import sys

import pytest

pytestmark = pytest.mark.skipif(platform.libc_ver()[0] != "glibc",
                                reason="mallopt's thresholds are glibc's")

ALLOCATE_AND_FREE = """
import ctypes
from animat.learners.ppo.allocator import keep_freed_memory
libc = ctypes.CDLL(None)
libc.malloc.restype, libc.malloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t]
libc.free.argtypes = [ctypes.c_void_p]
libc.sbrk.restype, libc.sbrk.argtypes = ctypes.c_void_p, [ctypes.c_ssize_t]
kept = keep_freed_memory() if {keep} else None
size = 16 << 20  # four minibatches of 128 compact retinal images, float32
block = libc.malloc(size)
top = libc.sbrk(0)
libc.free(block)
print(kept, 0 < top - block < 1 << 30, libc.sbrk(0) == top)  # mmap maps far from the heap
"""


def _allocate_and_free(keep: bool) -> list[str]:
    """[whether the thresholds were set, whether the block came from the heap, whether the
    heap kept its size once the block was freed]."""
    done = subprocess.run([sys.executable, "-c", ALLOCATE_AND_FREE.format(keep=keep)],
                          capture_output=True, text=True, timeout=300, check=True)
    return done.stdout.split()


def test_freed_megabytes_stay_in_the_heap():
    assert _allocate_and_free(keep=True) == ["True", "True", "True"]
    assert _allocate_and_free(keep=False) == ["None", "False", "True"]  # mapped, unmapped
