"""The one exception family of cdt_plugin.

Every malformed input raises a subclass of :class:`CDTError` whose message names
what is wrong: which vertex or segment (by input index) and where (coordinates).
The compiled core never raises; it returns status codes that the Python layer
turns into these exceptions.
"""
from __future__ import annotations


class CDTError(ValueError):
    """Base class of every error cdt_plugin raises for bad input or options."""


class InputShapeError(CDTError):
    """An array has the wrong shape, dtype or length (e.g. points not (n, 2))."""


class NonFiniteCoordinateError(CDTError):
    """A coordinate (or weight) is NaN or infinite; the message names the rows."""


class TooFewPointsError(CDTError):
    """The input has no points at all (after validation)."""


class FileFormatError(CDTError):
    """A Triangle-format (or other) input file cannot be parsed; names file and line."""


class InvertedTriangleError(CDTError):
    """Moving vertices inverted a triangle and no rebuild was allowed."""
