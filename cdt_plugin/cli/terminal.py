"""What the command line prints on stderr besides its results: an error or a
warning as one line, and progress bars."""
from __future__ import annotations

import sys
from contextlib import contextmanager
from typing import Callable, Iterator


class CLIError(Exception):
    """A problem with the command's input or options: printed as one line."""


def one_line(message: object) -> str:
    """``message`` with its runs of white space (line breaks too) made single spaces.

    >>> one_line("two\\n  lines ")
    'two lines'
    """
    return " ".join(str(message).split())


def warn(message: str) -> None:
    """Print ``cdt-plugin: warning: MESSAGE`` on stderr, on one line."""
    print(f"cdt-plugin: warning: {one_line(message)}", file=sys.stderr)


def fail(message: str) -> int:
    """Print ``cdt-plugin: error: MESSAGE`` on stderr, on one line; returns the exit status 1."""
    print(f"cdt-plugin: error: {one_line(message)}", file=sys.stderr)
    return 1


@contextmanager
def progress_bar(show: bool | None, desc: str, unit: str,
                 total: int) -> Iterator[Callable[[int], None] | None]:
    """A tqdm bar on stderr while the block runs (``show`` None: when stderr is a
    terminal; no bar without tqdm): gives its ``update``, or None when there is
    no bar. The bar is closed when the block ends, by an error too."""
    bar = None
    if show is True or show is None and sys.stderr.isatty():
        try:
            from tqdm import tqdm
        except ImportError:
            pass
        else:
            bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr)
    if bar is None:
        yield None
        return
    try:
        yield bar.update
    finally:
        bar.close()
