"""Ctrl-C during a long compiled call: a clean ``KeyboardInterrupt``.

Compiled code does not look at signals. A SIGINT that arrives during a long
call is handled by Python when the call returns, or, if anything inside
checks for signals first, it leaves ``KeyboardInterrupt`` set while the call
returns a result, which Python reports as ``SystemError: CPUDispatcher(...)
returned a result with an exception set``. :func:`deferred_interrupt` records
the signal during the call instead and, once the call is over, hands it to
the handler that was installed (by default: ``KeyboardInterrupt``). The call
is not cut short: the interrupt takes effect when it returns.
"""
from __future__ import annotations

import signal
import threading
from contextlib import contextmanager

LONG = 20_000   # inputs from this size (points, vertices) take long enough to be interrupted


@contextmanager
def deferred_interrupt(size: int = LONG):
    """Defer SIGINT to the end of the block when ``size`` is at least
    :data:`LONG` and this is the main thread with a Python handler installed
    (signal handlers can only be set there; small calls cost nothing)."""
    if size < LONG or threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if not callable(previous):
        yield
        return
    frames = []
    signal.signal(signal.SIGINT, lambda signum, frame: frames.append(frame))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if frames:
        previous(signal.SIGINT, frames[-1])
