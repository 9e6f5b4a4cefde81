import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent / "support"))   # checker, corpus, helpers

TESTS = str(Path(__file__).parent.resolve())


def pytest_sessionfinish(session, exitstatus):
    """Fail the run when the package's own Python code called an internal
    kernel (one without numba's CPython wrapper: ``jit.kernel``): it must be a
    ``jit.entry``, or every such call compiles an uncached twin and goes
    through numba's slow path. Tests may call internal kernels."""
    jit = sys.modules.get("cdt_plugin._core.jit")
    if jit is None:
        return
    outside = sorted(c for c in jit.PYTHON_CALLERS
                     if not os.path.realpath(c[1]).startswith(TESTS + os.sep))
    if outside:
        lines = [f"  {name} called from {path} ({function})" for name, path, function in outside]
        session.config.get_terminal_writer().line(
            "\ninternal kernels called from Python outside the tests (mark them jit.entry):\n"
            + "\n".join(lines), red=True)
        session.exitstatus = pytest.ExitCode.TESTS_FAILED
