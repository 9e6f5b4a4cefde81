"""Ctrl-C during a long compiled call: a clean ``KeyboardInterrupt``.

Compiled code does not look at signals. A SIGINT that arrives during a long
call is handled by Python when the call returns, or, if anything inside
checks for signals first, it leaves ``KeyboardInterrupt`` set while the call
returns a result, which Python reports as ``SystemError: CPUDispatcher(...)
returned a result with an exception set``. :class:`deferred_interrupt`
records the signal during the call instead and, once the call is over, hands
it to the handler that was installed (by default: ``KeyboardInterrupt``). The
call is not cut short: the interrupt takes effect when it returns.
"""
from __future__ import annotations

import signal
import threading
from types import FrameType, TracebackType
from typing import Callable, Literal, Union

# what signal.getsignal returns: a Python handler, SIG_DFL/SIG_IGN, or None (not set from Python)
_Handler = Union[Callable[[int, Union[FrameType, None]], object], int, signal.Handlers, None]

LONG = 20_000   # inputs from this size (points, vertices) take long enough to be interrupted


class deferred_interrupt:  # noqa: N801 - used like a function: ``with deferred_interrupt(n):``
    """Defer SIGINT to the end of the ``with`` block when ``size`` is at least
    :data:`LONG` and this is the main thread with a Python handler installed
    (signal handlers can only be set there). Smaller calls cost two attribute
    checks (a class, not a generator: small calls are a few microseconds).

    >>> with deferred_interrupt(50_000) as guard:   # a SIGINT here would wait for the block's end
    ...     pass
    >>> guard.active
    True
    """

    __slots__ = ("active", "previous", "frames")

    previous: _Handler
    frames: list[FrameType | None]

    def __init__(self, size: int = LONG) -> None:
        self.active = size >= LONG and threading.current_thread() is threading.main_thread()

    def __enter__(self) -> deferred_interrupt:
        if self.active:
            self.previous = signal.getsignal(signal.SIGINT)
            self.active = callable(self.previous)
        if self.active:
            self.frames = []
            signal.signal(signal.SIGINT, lambda signum, frame: self.frames.append(frame))
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> Literal[False]:
        previous = self.previous if self.active else None
        if callable(previous):
            signal.signal(signal.SIGINT, previous)
            if self.frames and exc_type is None:
                previous(signal.SIGINT, self.frames[-1])
        return False
