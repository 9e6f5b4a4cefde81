"""Threads for independent compiled calls (the ``workers=`` option).

Every kernel releases the GIL (:mod:`cdt_plugin._core.jit`), so compiled
calls on separate inputs run side by side in threads of one process: no
pickling, no second copy of the data, no second compilation. Results come
back in input order, so any number of workers gives the result of one.
"""
from __future__ import annotations

import ctypes
import functools
import operator
import os
import sys
from concurrent.futures import ThreadPoolExecutor
from typing import Callable, Iterable, SupportsIndex, TypeVar

import numpy as np

from .errors import CDTError

T = TypeVar("T")
R = TypeVar("R")


def available_cores() -> int:
    """CPUs this process may run on (its affinity mask where the OS has one)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:      # macOS, Windows
        return os.cpu_count() or 1


@functools.cache
def _malloc_trim() -> Callable[[int], int] | None:
    """glibc's ``malloc_trim`` (the process's own C library), or None where
    there is none."""
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError):         # musl and other C libraries
        return None


def release_freed_memory() -> None:
    """Give memory that was freed back to the operating system.

    glibc keeps what is freed below its adaptive mmap threshold (NumPy's
    temporaries of a large call: often tens of MB), in the arena of the thread
    that freed it, for the next allocation; it would stay resident through the
    rest of a large triangulation. ``malloc_trim`` returns it (as Dask's
    workers do); off glibc this does nothing.

    >>> release_freed_memory()
    """
    trim = _malloc_trim()
    if trim is not None:
        trim(0)


def mapped_empty(shape: int | tuple[int, ...], dtype: type | np.dtype = np.float64,
                 fill: int | float | None = None) -> np.ndarray:
    """``np.empty(shape, dtype)`` (``fill`` written to it if given) with its
    memory already mapped, for threads to write side by side.

    A new large array is mapped lazily, one page at a time when first
    written. When two threads write fresh pages side by side, each page fault
    waits for the kernel's lock on the process's memory map: on the 2-core
    machine of the benchmarks two threads wrote a fresh 48 MB array three to
    four times slower than one thread alone, and one write per page here, in
    one thread, costs about 5 ms for it.

    >>> mapped_empty(3, np.int64, fill=0)
    array([0, 0, 0])
    """
    a = np.empty(shape, dtype)
    if fill is not None:
        a.fill(fill)
    elif a.size:
        a.reshape(-1).view(np.uint8)[::4096] = 0
    return a


def check_workers(workers: SupportsIndex | None) -> int | None:
    """Validate a ``workers=`` option: None (the default: all cores where the
    work is large enough) or a whole number >= 1.

    >>> check_workers(2), check_workers(None)
    (2, None)
    >>> check_workers(0)
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.CDTError: workers must be None or a whole number >= 1, got 0
    """
    return check_count(workers, "workers")


def check_count(value: SupportsIndex | None, name: str) -> int | None:
    """Validate an option that is None or a whole number >= 1 (``workers``,
    ``npartitions``): the number, None, or a :class:`CDTError` naming ``name``.

    >>> check_count(3, "npartitions"), check_count(None, "npartitions")
    (3, None)
    """
    if value is None:
        return None
    try:
        count = operator.index(value)       # int and NumPy integers, not floats or bools
    except TypeError:
        count = 0
    if isinstance(value, bool) or count < 1:
        raise CDTError(f"{name} must be None or a whole number >= 1, got {value!r}")
    return count


def resolve_workers(workers: int | None, tasks: int) -> int:
    """How many threads to run ``tasks`` independent pieces of work on:
    ``workers`` (checked), by default every available core, never more than
    there are tasks."""
    wanted = available_cores() if workers is None else workers
    return max(1, min(wanted, tasks))


def map_ordered(fn: Callable[[T], R], items: Iterable[T], workers: int,
                done: Callable[[T, R], None] | None = None) -> list[R]:
    """``[fn(item) for item in items]`` on ``workers`` threads, results in
    input order; ``done(item, result)`` is called in the calling thread, in
    input order, as results arrive (progress bars). On an exception
    (``KeyboardInterrupt`` included) the pieces not started are cancelled, the
    running ones finish, and the exception propagates.

    >>> map_ordered(lambda k: k * k, range(5), workers=2)
    [0, 1, 4, 9, 16]
    """
    items = list(items)
    results: list[R] = []
    if workers <= 1 or len(items) <= 1:
        for item in items:
            results.append(fn(item))
            if done is not None:
                done(item, results[-1])
        return results
    # With no more pieces than threads, the calling thread runs the first one
    # rather than wait: a thread fewer to start (each call started two, about
    # 0.3 ms, and a Voronoi diagram makes four such calls)
    own = len(items) <= workers
    with ThreadPoolExecutor(max_workers=len(items) - 1 if own else workers,
                            thread_name_prefix="cdt_plugin") as pool:
        futures = [pool.submit(fn, item) for item in items[own:]]
        try:
            if own:
                results.append(fn(items[0]))
                if done is not None:
                    done(items[0], results[0])
            for item, future in zip(items[own:], futures):
                results.append(future.result())
                if done is not None:
                    done(item, results[-1])
        except BaseException:
            for future in futures:
                future.cancel()
            raise
    return results
