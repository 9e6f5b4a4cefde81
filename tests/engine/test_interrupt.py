"""Ctrl-C during a long compiled call is a clean KeyboardInterrupt and the
process stays usable (issue: reliability, inputs and interfaces). It was
``SystemError: CPUDispatcher(build_divide_sorted) returned a result with an
exception set``."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from cdt_plugin.interrupts import LONG, deferred_interrupt


def test_a_signal_during_a_long_call_is_raised_after_it():
    handler = signal.getsignal(signal.SIGINT)
    done = []
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt(LONG):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)          # the handler runs here: recorded, not raised
            done.append(True)
    assert done == [True]
    assert signal.getsignal(signal.SIGINT) is handler


def test_short_calls_are_not_wrapped():
    with pytest.raises(KeyboardInterrupt):
        with deferred_interrupt(LONG - 1):
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)
            pytest.fail("the interrupt should have been raised at once")


SCRIPT = textwrap.dedent("""
    import numpy as np, cdt_plugin
    P = np.random.default_rng(0).random((1_500_000, 2))
    cdt_plugin.delaunay(P[:100])
    print("ready", flush=True)
    try:
        for _ in range(4):            # long enough for the signal to arrive inside
            cdt_plugin.delaunay(P)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", flush=True)
    except BaseException as exc:
        print("other", type(exc).__name__, exc, flush=True)
    print("usable", len(cdt_plugin.delaunay(P[:10]).triangles), flush=True)
""")


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process is POSIX")
def test_ctrl_c_during_a_large_delaunay():
    child = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, text=True,
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    lines = []
    for line in child.stdout:
        lines.append(line.strip())
        if line.startswith("ready"):
            time.sleep(1.5)           # inside the divide-and-conquer call on this machine
            child.send_signal(signal.SIGINT)
    child.wait(timeout=300)
    out = [line for line in lines if not line.startswith("cdt_plugin:")]
    assert child.returncode == 0, out
    assert "KeyboardInterrupt" in out, out
    assert not any(line.startswith("other") for line in out), out
    assert "usable 12" in out, out
