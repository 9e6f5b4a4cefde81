"""Triangle's switches (version 1.6), read once into a :class:`Switches` record: the
engine options they ask for (:meth:`Switches.keywords`, the keywords of
:func:`cdt_plugin.triangulate`) and the output choices they make, for the
``triangle`` drop-in (:mod:`cdt_plugin.triangle`), the command line and
trimesh's ``triangle_args``.

Every switch of Triangle 1.6 is read (the letters, their numbers, their meaning):

| switch | Triangle | here |
|---|---|---|
| ``p`` | triangulate a PSLG (segments, holes, regions) | ``pslg`` |
| ``r`` | refine a previous mesh | ``refine`` |
| ``q`` | quality: minimum angle (20 without a number) | ``min_angle`` |
| ``a`` | maximum area: ``a<area>`` for every triangle, a bare ``a`` from the regions (``p``) or per triangle (``r``) | ``max_area``, ``area_from_input`` |
| ``u`` | the user's size test compiled into Triangle | ``user_test`` |
| ``A`` | regional attribute of each triangle | ``region_attributes`` |
| ``c`` | keep the convex hull (enclose it with segments) | ``convex_hull`` |
| ``D`` | conforming Delaunay | ``conforming_delaunay`` |
| ``j`` | drop vertices that no triangle uses | ``jettison`` |
| ``e`` | output the edges (and their markers) | ``edges`` |
| ``v`` | the Voronoi diagram | ``voronoi`` |
| ``n`` | output the neighbours of each triangle | ``neighbors`` |
| ``g`` | write an Object File Format (``.off``) file | ``geomview`` |
| ``B`` | no boundary markers in the output | ``no_markers`` |
| ``P`` | no output segments (``.poly`` file) | ``no_poly`` |
| ``N`` | no output vertices (``.node`` file) | ``no_nodes`` |
| ``E`` | no output triangles (``.ele`` file) | ``no_elements`` |
| ``I`` | no iteration numbers in the file names | ``no_iteration_numbers`` |
| ``O`` | ignore the holes | ``no_holes`` |
| ``X`` | no exact arithmetic | ``no_exact`` |
| ``z`` | number everything from zero | ``zero_index`` |
| ``o2`` | six-node (second-order) triangles | ``order`` = 2 |
| ``Y`` | no Steiner point on the boundary; ``YY``: on no segment | ``split`` = 1 (``Y``) or 2 (``YY``) |
| ``S`` | maximum number of Steiner points (``S`` alone: 0) | ``max_steiner`` |
| ``i`` | incremental Delaunay | ``incremental`` |
| ``F`` | Fortune's sweepline Delaunay | ``sweepline`` |
| ``l`` | vertical cuts only in divide and conquer | ``vertical_cuts`` |
| ``s`` | split segments instead of a constrained triangulation | ``split_segments_first`` |
| ``C`` | check the final mesh | ``check`` |
| ``Q`` | quiet | ``quiet`` |
| ``V`` | verbose (``VV``, ``VVV``... more) | ``verbose`` (the count) |

Numbers are read as ``triangle.c`` reads them: the digits and dots that follow the
letter (``q``, ``a``; only digits for ``S``). Where Triangle would silently read
something else than what was written, :class:`~cdt_plugin.errors.SwitchError` says
so instead: an exponent (``a1e-3``: Triangle reads 1, takes ``e`` for the edges
switch and skips ``-3``), a second dot (``q.5.3``), a dot after ``S`` (``S5.5``:
Triangle reads 5 and skips ``.5``), ``o`` without ``2``, ``YYY`` (Triangle then
splits as without ``Y``), ``a0`` (Triangle stops: the area must be positive),
``h`` (Triangle prints its help and exits the process), and any other character
Triangle would skip. White space between switches and a ``-`` at the start of each
word (the command line's habit: ``"-p -q30"``) are allowed; ``Y`` and ``V`` are
counted wherever they stand, as ``triangle.c`` counts them (``pYqY`` is ``pqYY``).
"""
from __future__ import annotations

import functools
import re
from typing import NamedTuple

from .errors import SwitchError

#: The letters that are on/off switches, by the :class:`Switches` field they set.
FLAGS = {"p": "pslg", "r": "refine", "u": "user_test", "A": "region_attributes",
         "c": "convex_hull", "D": "conforming_delaunay", "j": "jettison", "e": "edges",
         "v": "voronoi", "n": "neighbors", "g": "geomview", "B": "no_markers", "P": "no_poly",
         "N": "no_nodes", "E": "no_elements", "I": "no_iteration_numbers", "O": "no_holes",
         "X": "no_exact", "z": "zero_index", "i": "incremental", "F": "sweepline",
         "l": "vertical_cuts", "s": "split_segments_first", "C": "check", "Q": "quiet"}
_TOKEN = re.compile(r"o2|Y+|V+|[qa][0-9.]*|S[0-9]*|.", re.S)
_EXPONENT = re.compile(r"[eE][+-]?[0-9]")


class Switches(NamedTuple):
    """A Triangle switch string, read (:func:`read_switches`): one field per switch
    (the table of :mod:`cdt_plugin.switches`), False/None/0 where it is absent."""

    text: str = ""
    pslg: bool = False
    refine: bool = False
    min_angle: float | None = None
    max_area: float | None = None
    area_from_input: bool = False
    user_test: bool = False
    region_attributes: bool = False
    convex_hull: bool = False
    conforming_delaunay: bool = False
    jettison: bool = False
    edges: bool = False
    voronoi: bool = False
    neighbors: bool = False
    geomview: bool = False
    no_markers: bool = False
    no_poly: bool = False
    no_nodes: bool = False
    no_elements: bool = False
    no_iteration_numbers: bool = False
    no_holes: bool = False
    no_exact: bool = False
    zero_index: bool = False
    order: int = 1
    split: int = 0
    max_steiner: int | None = None
    incremental: bool = False
    sweepline: bool = False
    vertical_cuts: bool = False
    split_segments_first: bool = False
    check: bool = False
    quiet: bool = False
    verbose: int = 0

    @property
    def quality(self) -> bool:
        """Whether Triangle refines (``q``, ``a`` or ``u``: Triangle's ``quality``)."""
        return self.min_angle is not None or self.max_area is not None or self.area_from_input \
            or self.user_test

    @property
    def files(self) -> tuple[str, ...]:
        """The files the Triangle program writes with these switches, by extension
        (``.node`` unless ``N``, ``.ele`` unless ``E``, ``.poly`` with ``p`` or ``c``
        unless ``P``, ``.edge`` with ``e``, ``.neigh`` with ``n``, ``.v.node`` and
        ``.v.edge`` with ``v``, ``.off`` with ``g``): what a command line honours.

        >>> read_switches("pevN").files
        ('.ele', '.poly', '.edge', '.v.node', '.v.edge')
        """
        wanted = ((".node", not self.no_nodes), (".ele", not self.no_elements),
                  (".poly", (self.pslg or self.convex_hull) and not self.no_poly),
                  (".edge", self.edges), (".neigh", self.neighbors),
                  (".v.node", self.voronoi), (".v.edge", self.voronoi), (".off", self.geomview))
        return tuple(ext for ext, on in wanted if on)

    def keywords(self) -> dict[str, float | bool | int | str]:
        """The :func:`cdt_plugin.triangulate` keywords these switches ask for
        (``q`` ``min_angle``, ``a<area>`` ``max_area``, ``D`` ``conforming_delaunay``,
        ``Y`` ``split_boundary=False``, ``YY`` also ``split_segments=False``,
        ``c`` ``keep_hull``, ``S`` ``max_steiner``, ``i`` ``algorithm="incremental"``);
        only those that differ from the defaults.

        >>> read_switches("pq30a0.5cDS100i").keywords()
        {'min_angle': 30.0, 'max_area': 0.5, 'keep_hull': True, 'conforming_delaunay': True, \
'max_steiner': 100, 'algorithm': 'incremental'}
        """
        return dict(_keywords(self))


def _keywords(s: Switches):
    if s.min_angle is not None:
        yield "min_angle", s.min_angle
    if s.max_area is not None:
        yield "max_area", s.max_area
    if s.convex_hull:
        yield "keep_hull", True
    if s.conforming_delaunay:
        yield "conforming_delaunay", True
    if s.split:
        yield "split_boundary", False
    if s.split > 1:
        yield "split_segments", False
    if s.max_steiner is not None:
        yield "max_steiner", s.max_steiner
    if s.incremental:
        yield "algorithm", "incremental"


@functools.lru_cache(maxsize=256)
def read_switches(text: str) -> Switches:
    """Read a Triangle switch string (``"pq30a0.1"``, ``"-pzAevn"``...).

    Raises :class:`~cdt_plugin.errors.SwitchError` naming the switch and its
    position where the string is not what Triangle 1.6 reads (see the module).
    Cached: a program that passes the same string again pays a dictionary look-up.

    >>> s = read_switches("pq30Aao2")
    >>> s.pslg, s.min_angle, s.area_from_input, s.region_attributes, s.order
    (True, 30.0, True, True, 2)
    >>> read_switches("pYY").split, read_switches("pY").split
    (2, 1)
    >>> read_switches("pa1e-3")
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.SwitchError: Triangle switch 'a1' at position 1 of 'pa1e-3' is followed \
by an exponent: Triangle reads the number as 1 and takes 'e' for a switch; write the number \
without an exponent
    """
    if not isinstance(text, str):
        raise SwitchError(f"Triangle switches must be a string, got {text!r} ({type(text).__name__})")
    fields: dict[str, object] = {"text": text}
    counts = {"Y": 0, "V": 0}
    for word in re.finditer(r"\S+", text):        # (words apart, each may start with "-")
        body = word.group()[1:] if word.group().startswith("-") else word.group()
        at = word.end() - len(body)
        for m in _TOKEN.finditer(body):
            _token(fields, counts, m.group(), at + m.start(), text, body[m.end():])
    if counts["Y"] > 2:
        raise SwitchError(f"Triangle switches {text!r} have Y {counts['Y']} times: Triangle "
                          "reads three or more as neither Y nor YY (it then splits segments as "
                          "without Y); write Y or YY")
    return Switches(**fields, split=counts["Y"], verbose=counts["V"])  # type: ignore[arg-type]


def _token(fields: dict[str, object], counts: dict[str, int], token: str, where: int, text: str,
           rest: str) -> None:
    """Store what one token (a letter and its number) sets (``Y`` and ``V`` in
    ``counts``); ``rest``: what follows it."""
    letter = token[0]
    if letter in FLAGS:
        fields[FLAGS[letter]] = True
    elif token == "o2":
        fields["order"] = 2
    elif letter in counts:          # (counted, as triangle.c counts them: pYqY is YY)
        counts[letter] += len(token)
    elif letter in "qaS":
        _number(fields, token, where, text, rest)
    elif letter == "o":
        raise _error(token, where, text, "o is only read as o2 (six-node triangles); "
                     "Triangle skips any other o")
    elif letter == "h":
        raise _error(token, where, text, "Triangle prints its help and ends the process")
    else:
        raise _error(token, where, text, "Triangle 1.6 has no such switch (it would skip "
                     "the character)")


def _number(fields: dict[str, object], token: str, where: int, text: str, rest: str) -> None:
    """Store the number of a ``q``, ``a`` or ``S`` token, or raise where Triangle
    would read another number than the one written."""
    letter, digits = token[0], token[1:]
    if _EXPONENT.match(rest):
        raise _error(token, where, text, f"is followed by an exponent: Triangle reads the number "
                     f"as {digits} and takes {rest[0]!r} for a switch; write the number "
                     "without an exponent")
    if rest.startswith(".") or digits.count(".") > 1 or digits == ".":
        raise _error(token + rest[:1], where, text, "is not a number as Triangle reads it "
                     "(digits and one dot" + (" only" if letter != "S" else "; S takes a whole "
                                              "number") + ")")
    if letter == "q":
        fields["min_angle"] = float(digits) if digits else 20.0
    elif letter == "S":
        fields["max_steiner"] = int(digits) if digits else 0   # (a bare S is S0 in Triangle)
    elif digits:
        area = float(digits)
        if area <= 0:
            raise _error(token, where, text, "asks for a maximum area of 0: Triangle stops "
                         "(the area must be positive)")
        fields["max_area"] = area
    else:
        fields["area_from_input"] = True


def _error(token: str, where: int, text: str, why: str) -> SwitchError:
    return SwitchError(f"Triangle switch {token!r} at position {where} of {text!r} {why}"
                       if why.startswith(("is ", "asks")) else
                       f"Triangle switch {token!r} at position {where} of {text!r}: {why}")


def options_from_switches(switches: str) -> dict[str, float | bool | int | str]:
    """Translate a Triangle switch string into :func:`cdt_plugin.triangulate` keywords
    (:meth:`Switches.keywords`), for callers that have only a polygon to mesh
    (trimesh's ``triangle_args``). Switches that choose outputs are accepted;
    ``r`` and ``u`` need what such a call lacks (a previous mesh, a size test
    compiled into Triangle) and raise :class:`~cdt_plugin.errors.SwitchError`
    (:mod:`cdt_plugin.triangle` takes ``r``).

    >>> options_from_switches("pq30a0.5Q")
    {'min_angle': 30.0, 'max_area': 0.5}
    >>> options_from_switches("pqDY")
    {'min_angle': 20.0, 'conforming_delaunay': True, 'split_boundary': False}
    """
    read = read_switches(switches or "")
    if read.refine:
        raise SwitchError(f"Triangle switch 'r' in {switches!r} refines a previous mesh: "
                          "use cdt_plugin.triangle.triangulate with the mesh's triangles, or "
                          "Triangulation.refine")
    if read.user_test:
        raise user_test_error(switches)
    return read.keywords()


def user_test_error(switches: str) -> SwitchError:
    """The error for ``u``: Triangle calls a size test (``triunsuitable``) compiled
    into it; the ``triangle`` package compiles Triangle's sample test (a triangle is
    too large when its longest edge squared exceeds 0.05 (x^2 + y^2) + 0.02 at its
    first corner), which no user chose."""
    return SwitchError(f"Triangle switch 'u' in {switches!r} asks for the size test compiled "
                       "into Triangle (triunsuitable; the triangle package compiles Triangle's "
                       "sample test, which depends on the distance from the origin): "
                       "cdt_plugin takes no compiled test; use 'q' and 'a' bounds")
