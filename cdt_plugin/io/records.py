"""What the readers of :mod:`cdt_plugin.io` return (:class:`NodeData`, :class:`PolyData`,
:class:`EleData`, :class:`EdgeData`) and the lexical layer they share (:class:`Records`:
the records of one file, a cursor over them, and the parsing of their fields with errors
that name the file and the line)."""
from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import FileFormatError
from ..plc import PLC, as_plc

# ----------------------------------------------------------------------------------------
# result types
# ----------------------------------------------------------------------------------------

@dataclass
class NodeData:
    """Contents of a ``.node`` file (or the node section of a ``.poly``)."""
    vertices: NDArray[np.float64]      # (n, 2)
    attributes: NDArray[np.float64]    # (n, a) (a may be 0)
    markers: NDArray[np.int64] | None  # (n,), or None when the header says 0 markers
    first_index: int                   # 0 or 1: the numbering base of the file


@dataclass
class PolyData:
    """Contents of a ``.poly`` file. All indices are zero-based."""
    vertices: NDArray[np.float64]              # (n, 2)
    attributes: NDArray[np.float64]            # (n, a)
    markers: NDArray[np.int64] | None          # (n,) or None
    segments: NDArray[np.int64]                # (m, 2), zero-based
    segment_markers: NDArray[np.int64] | None  # (m,) or None
    holes: NDArray[np.float64]                 # (h, 2) hole seed points
    regions: NDArray[np.float64]               # (r, 4): x, y, attribute, max_area
    first_index: int                           # numbering base of the file (0 or 1)
    node_path: Path | None = None              # the .node file the vertices came from, if any

    def to_plc(self) -> PLC:
        """The file's PLC (vertices, segments, holes, region seeds), ready for
        :func:`cdt_plugin.triangulate`. Hole points are kept as Triangle uses them
        (triangles reachable from outside the segments are removed too), and a
        region's positive maximum area bounds its triangles.

        >>> import os, tempfile, cdt_plugin
        >>> from cdt_plugin.io import read_poly, write_poly
        >>> path = os.path.join(tempfile.mkdtemp(), "square.poly")
        >>> write_poly(path, [[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1], [1, 2], [2, 3], [3, 0]])
        >>> tri = cdt_plugin.triangulate(read_poly(path).to_plc())
        >>> len(tri.triangles), tri.is_delaunay()
        (2, True)
        """
        return as_plc(self.vertices, self.segments, self.holes,
                      self.regions if len(self.regions) else None)

    @property
    def vertex_attributes(self) -> NDArray[np.float64]:
        return self.attributes

    @property
    def vertex_markers(self) -> NDArray[np.int64] | None:
        return self.markers


@dataclass
class EleData:
    """Contents of a ``.ele`` file (zero-based vertex indices)."""
    triangles: NDArray[np.int64]     # (k, 3) or (k, 6)
    attributes: NDArray[np.float64]  # (k, a)
    first_index: int


@dataclass
class EdgeData:
    """Contents of a ``.edge`` file (zero-based vertex indices)."""
    edges: NDArray[np.int64]           # (m, 2)
    markers: NDArray[np.int64] | None  # (m,) or None
    first_index: int


# ----------------------------------------------------------------------------------------
# lexical layer
# ----------------------------------------------------------------------------------------

class Records:
    """The records (non-blank, comment-stripped lines) of one file, with line numbers."""

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.name = self.path.name
        try:
            with open(self.path, "r", encoding="utf-8", errors="replace") as f:
                text = f.read()
        except OSError as exc:
            raise FileFormatError(f"{self.path}: cannot read file ({exc.strerror})") from exc
        recs: list[tuple[int, list[str]]] = []
        for lineno, line in enumerate(text.splitlines(), start=1):
            toks = line.split("#", 1)[0].split()
            if toks:
                recs.append((lineno, toks))
        self.recs = recs
        self.nlines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        self.pos = 0

    # -- errors ---------------------------------------------------------------------------
    def error(self, lineno: int | None, msg: str) -> FileFormatError:
        where = f"{self.name} line {lineno}" if lineno is not None else self.name
        err = FileFormatError(f"{where}: {msg}")
        err.path = self.path
        err.line = lineno
        return err

    # -- cursor ---------------------------------------------------------------------------
    def at_end(self) -> bool:
        return self.pos >= len(self.recs)

    def next(self, what: str) -> tuple[int, list[str]]:
        if self.pos >= len(self.recs):
            raise self.error(None, f"unexpected end of file: expected {what}")
        rec = self.recs[self.pos]
        self.pos += 1
        return rec

    def next_of(self, n: int, i: int, items: str) -> tuple[int, list[str]]:
        """Record ``i`` of the ``n`` ``items`` a header declares; at the end of the
        file, an error that says how many were found."""
        if self.pos >= len(self.recs):
            raise self.error(None, f"unexpected end of file: {n} {items} declared, found {i}")
        return self.next(items)

    def expect_end(self, after: str) -> None:
        if self.pos < len(self.recs):
            lineno, toks = self.recs[self.pos]
            raise self.error(lineno, f"unexpected extra record {' '.join(toks)!r} after {after}")

    # -- fields ---------------------------------------------------------------------------
    def need(self, lineno: int, toks: list[str], n: int, what: str) -> None:
        if len(toks) < n:
            raise self.error(lineno, f"expected {n} numbers ({what}), got {len(toks)}")

    def int_(self, lineno: int, tok: str, what: str) -> int:
        try:
            return int(tok)
        except ValueError:
            pass
        try:
            v = float(tok) if "_" not in tok else math.nan
        except ValueError:
            v = math.nan
        if math.isfinite(v) and v == int(v):
            return int(v)
        raise self.error(lineno, f"expected an integer for {what}, got {tok!r}")

    def float_(self, lineno: int, tok: str, what: str) -> float:
        # float() keeps exponents ("2.86e-05" is 2.86e-05). Python also accepts "1_000",
        # which no C strtod does: reject it rather than guess.
        try:
            if "_" in tok:
                raise ValueError
            v = float(tok)
        except ValueError:
            raise self.error(lineno, f"expected a number for {what}, got {tok!r}") from None
        if not math.isfinite(v):
            raise self.error(lineno, f"{what} is not finite ({tok!r})")
        return v

    # -- counts, flags, numbering ---------------------------------------------------------
    def count(self, lineno: int, tok: str, what: str) -> int:
        n = self.int_(lineno, tok, what)
        if n < 0:
            raise self.error(lineno, f"{what} must be >= 0, got {n}")
        return n

    def flag(self, lineno: int, toks: list[str], k: int, what: str) -> int:
        if len(toks) <= k:
            return 0
        v = self.int_(lineno, toks[k], what)
        if v not in (0, 1):
            raise self.error(lineno, f"{what} must be 0 or 1, got {v}")
        return v

    def first_number(self, lineno: int, tok: str, what: str) -> int:
        first = self.int_(lineno, tok, what)
        if first not in (0, 1):
            raise self.error(lineno, f"the first {what} must be numbered 0 or 1, got {first}")
        return first
