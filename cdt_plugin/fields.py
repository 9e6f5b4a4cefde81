"""Size fields: what ``size=`` takes, checked once and evaluated vectorised.

A *size field* is a target edge length over the plane, given as

- a positive number: a constant length;
- a callable ``f(x, y) -> sizes``, with ``x``, ``y`` float64 arrays of one
  shape, returning positive lengths of that shape; it is called on many points
  at once (every triangle of a mesh in one call), never once per triangle;
- a :class:`~cdt_plugin.Triangulation` whose vertices carry sizes in
  ``vertex_attributes[:, 0]``: a background mesh, interpolated linearly inside
  its triangles (its triangles must cover the domain meshed).

:func:`as_size_field` turns any of them into a callable (or raises
:class:`~cdt_plugin.errors.SizeFieldError`), :func:`size_values` evaluates one
and checks the answer, :func:`graded_sizes` applies a gradation limit on a
mesh, and :func:`check_sizing` checks the sizing keywords of
:func:`cdt_plugin.triangulate` together, before any work starts.

>>> import numpy as np
>>> from cdt_plugin.fields import as_size_field, size_values
>>> ramp = as_size_field(lambda x, y: 0.1 + 0.2 * x)
>>> size_values(ramp, np.array([0.0, 1.0]), np.array([0.0, 0.0])).tolist()
[0.1, 0.30000000000000004]
>>> size_values(as_size_field(0.5), np.zeros(2), np.zeros(2)).tolist()
[0.5, 0.5]
"""
from __future__ import annotations

import numbers
from typing import Any, Callable, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ._core.gradation import limit_growth, triangle_measures, within_limit
from .errors import SizeFieldError

#: A size field as :func:`as_size_field` returns it: ``f(x, y) -> sizes``.
SizeField = Callable[[NDArray[np.float64], NDArray[np.float64]], Any]


class ConstantSize:
    """The size field of one length everywhere.

    >>> ConstantSize(0.25)(np.zeros(3), np.zeros(3)).tolist()
    [0.25, 0.25, 0.25]
    """

    def __init__(self, value: float) -> None:
        self.value = float(value)

    def __call__(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        return np.full(np.shape(x), self.value)

    def __repr__(self) -> str:
        return f"ConstantSize({self.value!r})"


class BackgroundSize:
    """The sizes at the vertices of a background mesh (its
    ``vertex_attributes[:, 0]``), interpolated linearly inside its triangles.
    A point outside the background's triangles raises
    :class:`~cdt_plugin.errors.SizeFieldError` naming it."""

    def __init__(self, mesh: Any) -> None:
        attributes = mesh.vertex_attributes
        if attributes is None or np.ndim(attributes) != 2 or np.shape(attributes)[1] < 1:
            raise SizeFieldError(f"a background mesh given as size must carry the sizes in "
                                 f"vertex_attributes[:, 0]; {mesh!r} has no vertex attributes")
        sizes = np.ascontiguousarray(attributes[:, 0], np.float64)
        bad = np.flatnonzero(~(sizes > 0) | ~np.isfinite(sizes))
        if len(bad):
            v = int(bad[0])
            px, py = (float(c) for c in mesh.vertices[v])
            raise SizeFieldError(f"the background mesh's size at vertex {v} ({px!r}, {py!r}) is "
                                 f"{float(sizes[v])!r}: sizes must be positive and finite",
                                 point=(px, py), value=float(sizes[v]))
        self.mesh, self.sizes = mesh, sizes

    def __call__(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
        shape = np.shape(x)
        points = np.column_stack([np.ravel(x), np.ravel(y)])
        out = self.mesh.interpolate(self.sizes, points)
        outside = np.flatnonzero(np.isnan(out))
        if len(outside):
            px, py = (float(c) for c in points[outside[0]])
            raise SizeFieldError(f"the point ({px!r}, {py!r}) lies outside the background mesh "
                                 f"{self.mesh!r} given as size ({len(outside)} points outside): "
                                 "its triangles must cover the domain", point=(px, py))
        return out.reshape(shape)

    def __repr__(self) -> str:
        return f"BackgroundSize({self.mesh!r})"


def as_size_field(size: object) -> SizeField:
    """``size`` (a positive number, a callable ``f(x, y)``, or a triangulation
    carrying sizes at its vertices) as a callable ``f(x, y) -> sizes``; a
    :class:`~cdt_plugin.errors.SizeFieldError` for anything else.

    >>> as_size_field(2)
    ConstantSize(2.0)
    >>> as_size_field("fine")
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.SizeFieldError: size must be a positive number, a callable f(x, y) -> sizes or a Triangulation with sizes in vertex_attributes[:, 0], got 'fine' (str)
    """
    if isinstance(size, (ConstantSize, BackgroundSize)):
        return size
    if isinstance(size, numbers.Real) and not isinstance(size, (bool, np.bool_)):
        value = float(size)
        if not (np.isfinite(value) and value > 0):
            raise SizeFieldError(f"size must be a positive finite length, got {size!r}",
                                 value=value)
        return ConstantSize(value)
    if hasattr(size, "vertex_attributes") and hasattr(size, "interpolate"):
        return BackgroundSize(size)
    if callable(size):
        return size
    raise SizeFieldError(f"size must be a positive number, a callable f(x, y) -> sizes or a "
                         f"Triangulation with sizes in vertex_attributes[:, 0], got {size!r} "
                         f"({type(size).__name__})")


def size_values(field: SizeField, x: NDArray[np.float64], y: NDArray[np.float64],
                min_size: float | None = None, *, name: str = "size") -> NDArray[np.float64]:
    """The values of ``field`` at the points ``(x, y)`` as float64 of their
    shape, raised to ``min_size`` where lower; a
    :class:`~cdt_plugin.errors.SizeFieldError` when the answer has another
    shape, is not real, or (below the floor, or without one) is not a
    positive finite number, naming the point and the value. ``name`` names
    the field in messages (``"max_area"`` for an area field).

    >>> size_values(lambda x, y: x - 1.0, np.array([2.0, 0.5]), np.array([0.0, 3.0]))
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.SizeFieldError: size gave -0.5 at (0.5, 3.0) (1 of 2 points): size values must be positive and finite (min_size= floors a field that vanishes)
    >>> size_values(lambda x, y: x - 1.0, np.array([2.0, 0.5]), np.array([0.0, 3.0]), 0.1).tolist()
    [1.0, 0.1]
    """
    try:
        answer = field(x, y)
    except SizeFieldError:
        raise
    except Exception as exc:
        raise SizeFieldError(f"{name} failed on {np.size(x)} points: {type(exc).__name__}: {exc}") from exc
    values = np.asarray(answer)
    if values.shape != np.shape(x):
        if values.shape == () and values.dtype.kind in "fiu":    # a constant from a callable
            values = np.full(np.shape(x), values)
        else:
            raise SizeFieldError(f"{name} must return one value per point, shape {np.shape(x)}, "
                                 f"got {values.dtype} {values.shape}")
    if values.dtype.kind not in "fiu":
        raise SizeFieldError(f"{name} must return real numbers, got {values.dtype}")
    values = values.astype(np.float64, copy=False)
    if min_size is not None:
        values = np.where(values < min_size, min_size, values)     # (NaN stays NaN)
    bad = ~(values > 0) | ~np.isfinite(values)
    if bad.any():
        i = int(np.flatnonzero(bad.ravel())[0])
        px, py, v = float(np.ravel(x)[i]), float(np.ravel(y)[i]), float(values.ravel()[i])
        hint = "" if min_size is not None else " (min_size= floors a field that vanishes)"
        raise SizeFieldError(f"{name} gave {v!r} at ({px!r}, {py!r}) ({int(bad.sum())} of "
                             f"{bad.size} points): {name} values must be positive and finite{hint}",
                             point=(px, py), value=v)
    return values


class Sizing(NamedTuple):
    """The sizing keywords of :func:`cdt_plugin.triangulate` and
    :meth:`~cdt_plugin.Triangulation.refine`, checked: the size field
    (``size``), the area field (a callable ``max_area``), the gradation limit
    and the floor (None: not given)."""

    size: SizeField | None = None
    area: SizeField | None = None
    growth: float | None = None
    min_size: float | None = None


def check_sizing(size: object = None, max_area: object = None, growth: object = None,
                 min_size: object = None) -> Sizing | None:
    """The checked :class:`Sizing` of the keywords (None when none of them
    asks for a field: ``max_area`` a number is the options' business), or the
    :class:`~cdt_plugin.errors.SizeFieldError` naming the first that is wrong.

    >>> check_sizing(size=0.1, growth=1.2)
    Sizing(size=ConstantSize(0.1), area=None, growth=1.2, min_size=None)
    >>> check_sizing(growth=0.5)
    Traceback (most recent call last):
    ...
    cdt_plugin.errors.SizeFieldError: growth must be a finite number > 1 (neighbouring edges differ at most by that factor), got 0.5
    """
    area = max_area if callable(max_area) else None
    if size is None and area is None and growth is None and min_size is None:
        return None
    field = None if size is None else as_size_field(size)
    g = None if growth is None else _real(growth, "growth")
    if g is not None and not (g > 1 and np.isfinite(g)):
        raise SizeFieldError(f"growth must be a finite number > 1 (neighbouring edges differ at "
                             f"most by that factor), got {growth!r}", value=growth)
    floor = None if min_size is None else _real(min_size, "min_size")
    if floor is not None and not (floor > 0 and np.isfinite(floor)):
        raise SizeFieldError(f"min_size must be a positive finite length, got {min_size!r}",
                             value=min_size)
    if field is None and area is None:
        what = "growth" if growth is not None else "min_size"
        raise SizeFieldError(f"{what} applies to a size field: give size= (or a callable "
                             "max_area=) with it")
    return Sizing(field, area, g, floor)


def _real(value: object, name: str) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise SizeFieldError(f"{name} must be a number, got {value!r} ({type(value).__name__})",
                             value=value)
    return float(value)


#: An equilateral triangle of edge ``h`` has area ``EQUILATERAL * h**2``.
EQUILATERAL = np.sqrt(3.0) / 4.0


def graded_sizes(vertices: NDArray[np.float64], triangles: NDArray[np.int64],
                 at_vertices: NDArray[np.float64] | None, at_centroids: NDArray[np.float64],
                 growth: float) -> NDArray[np.float64]:
    """The sizes ``at_centroids`` of the triangles (and ``at_vertices``, when
    given) limited so that they grow by at most ``growth - 1`` per unit of
    distance along the mesh (its edges, and from each centroid to its
    triangle's corners): each becomes the smallest, over the mesh's points, of
    that point's size plus ``(growth - 1)`` times the path length between them.
    Returns the limited sizes at the centroids.

    >>> V = np.array([[0.0, 0], [1, 0], [0, 1], [1, 1]])
    >>> T = np.array([[0, 1, 2], [1, 3, 2]])
    >>> graded_sizes(V, T, np.array([0.01, 1, 1, 1]), np.array([1.0, 1.0]), 1.5).round(3).tolist()
    [0.246, 0.883]
    """
    if at_vertices is None:
        at_vertices = np.full(len(vertices), np.inf)
    values = np.concatenate([at_vertices, at_centroids]).astype(np.float64, copy=False)
    V = np.ascontiguousarray(vertices, np.float64)
    T = np.ascontiguousarray(triangles, np.int64)
    if within_limit(V, T, values, float(growth) - 1.0):
        return values[len(V):]
    return limit_growth(V, T, values, np.argsort(values, kind="stable"), float(growth) - 1.0)


def triangle_sizes(vertices: NDArray[np.float64], triangles: NDArray[np.int64], field: SizeField,
                   growth: float | None = None, min_size: float | None = None,
                   centroids: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None
                   ) -> NDArray[np.float64]:
    """The size ``field`` at each triangle's centroid (``centroids``: their
    ``(x, y)`` when known), floored at ``min_size`` and limited by ``growth``
    (:func:`graded_sizes`, the field evaluated at the vertices too).

    >>> V = np.array([[0.0, 0], [3, 0], [0, 3]])
    >>> triangle_sizes(V, np.array([[0, 1, 2]]), lambda x, y: x + y).tolist()
    [2.0]
    """
    vertices = np.ascontiguousarray(vertices, np.float64)
    triangles = np.ascontiguousarray(triangles, np.int64)
    if centroids is None:
        centroids = triangle_measures(vertices, triangles)[:2]
    cx, cy = centroids
    h = size_values(field, cx, cy, min_size)
    if growth is None or isinstance(field, ConstantSize):
        return h
    at_vertices = size_values(field, vertices[:, 0], vertices[:, 1], min_size)
    return graded_sizes(vertices, triangles, at_vertices, h, growth)
