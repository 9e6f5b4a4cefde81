"""trimesh adapter: ``Path2D`` in, ``Trimesh`` and extruded solids out.

Data flow (DESIGN.md): ``Path2D`` / shapely polygon -> :class:`cdt_plugin.PLC`
-> :func:`cdt_plugin.triangulate` -> :class:`cdt_plugin.Triangulation` ->
``trimesh.Trimesh``. This module imports the engine; the engine never imports it.

Functions
---------
from_path2d(path)
    A ``trimesh.path.Path2D`` as a PLC: its closed polygons (shells and holes as
    ``Path2D.polygons_full`` sees them) as rings, its open entities as
    constraint segments, curves discretised as trimesh discretises them.
from_path3d(path)
    A planar ``trimesh.path.Path3D`` in any plane as a PLC with z, which
    :func:`cdt_plugin.triangulate` meshes in its plane.
to_trimesh(tri, z=None)
    A Triangulation as a ``Trimesh`` in its plane (3D input; z = 0 for 2D
    input), or flat at height ``z``.
triangulate_polygon(polygon, **kwargs)
    Drop-in for ``trimesh.creation.triangulate_polygon``: ``(vertices (n, 2),
    faces (m, 3))`` with only the vertices the faces use.
extrude_polygon(polygon, height, transform=None, mid_plane=False, **kwargs)
    Drop-in for ``trimesh.creation.extrude_polygon``: a watertight solid.
extrude_path(path, height, **kwargs)
    Every polygon of a ``Path2D`` extruded, one ``Trimesh`` each.
register(default=False), unregister(), registered(default=False)
    Hook this engine into trimesh itself: ``engine="cdt_plugin"`` in
    ``trimesh.creation.triangulate_polygon`` and in everything that calls it
    (``extrude_polygon``, ``sweep_polygon``, ``Path2D.triangulate`` /
    ``extrude``, ``Trimesh.slice_plane(cap=True)``); with ``default=True`` also
    when no engine is named.

Notes
-----
Extra keyword arguments of the triangulating functions go to
:func:`cdt_plugin.triangulate` (``intersections=``, ``holes=``, ...).

Near-duplicate points: trimesh treats vertices closer than ``trimesh.tol.merge``
(1e-8) as one (its ``Trimesh`` constructor merges vertices whose coordinates
round to the same multiple of it, and its Triangle wrapper drops ring points
that do), so the triangulating functions here merge input points closer than
``trimesh.tol.merge`` by default too (``merge_distance=`` of
:func:`cdt_plugin.triangulate`, read from ``trimesh.tol.merge`` at each call):
before meshing, so the solids stay watertight, where trimesh's own merge after
meshing can fold faces. The same points merge as in trimesh, except pairs
within rounding of the tolerance (trimesh rounds each coordinate to a grid, the
engine measures the distance). Pass ``merge_distance=0`` to keep every distinct
point.

Examples
--------
>>> import shapely, cdt_plugin.adapters.trimesh as ct
>>> square = shapely.box(0, 0, 4, 4).difference(shapely.box(1, 1, 3, 3))
>>> v, f = ct.triangulate_polygon(square)
>>> v.shape, f.shape
((8, 2), (8, 3))
>>> solid = ct.extrude_polygon(square, 2.0)
>>> bool(solid.is_watertight), float(solid.volume)
(True, 24.0)
"""
from __future__ import annotations

import contextlib
import inspect
import warnings
from typing import TYPE_CHECKING, Any, Callable, Iterator, Tuple, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cdt_plugin.optional import missing

try:
    import trimesh
    import trimesh.creation
    import trimesh.path
    from trimesh import transformations
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.trimesh", extra="trimesh") from exc

import cdt_plugin
from cdt_plugin import PLC
from cdt_plugin.switches import options_from_switches

if TYPE_CHECKING:
    import shapely

    from cdt_plugin import Triangulation

__all__ = ["from_path2d", "from_path3d", "to_trimesh", "triangulate_polygon", "extrude_polygon",
           "extrude_triangulation", "extrude_path", "register", "unregister", "registered",
           "is_registered", "ENGINE", "DroppedZWarning"]

ENGINE = "cdt_plugin"
"""The engine name that :func:`register` teaches ``trimesh.creation.triangulate_polygon``."""


class DroppedZWarning(UserWarning):
    """A polygon with z coordinates was triangulated into 2D vertices (trimesh's
    ``(n, 2)`` convention): its z values are not in the result."""


# ------------------------------------------------------------------ Path2D -> PLC
def from_path2d(path: trimesh.path.Path2D) -> PLC:
    """Read a ``trimesh.path.Path2D`` into a :class:`cdt_plugin.PLC`.

    * Closed loops become rings, grouped into polygons with holes exactly as
      ``path.polygons_full`` groups them (so what trimesh calls a hole is a hole
      here, and ``PLC.ring_is_hole`` / ``ring_polygon`` say so).
    * Entities in no closed loop (``path.dangling``: open lines, arcs, curves)
      become chains of constraint segments: they are edges of the mesh but do
      not bound the domain.
    * Curves (``Arc``, ``Bezier``, ``BSpline``) are discretised with
      ``entity.discrete(path.vertices, scale=path.scale)``, the same call trimesh
      uses for its own polygons, so the rings match ``polygons_full`` point for point.

    Coordinates shared between loops and open entities appear once per use in
    the PLC; the engine merges exact duplicates (``tri.vertex_map``).

    >>> import trimesh, shapely
    >>> path = trimesh.load_path(shapely.box(0, 0, 2, 2))
    >>> plc = from_path2d(path)
    >>> len(plc.vertices), len(plc.segments)
    (4, 4)
    """
    if not isinstance(path, trimesh.path.Path2D):
        raise TypeError(f"expected a trimesh.path.Path2D, got {type(path).__name__}")
    geometries = [polygon.__geo_interface__ for polygon in path.polygons_full
                  if polygon is not None and not polygon.is_empty]
    vertices = np.asarray(path.vertices, dtype=np.float64)
    for index in path.dangling:
        entity = path.entities[index]
        points = np.asarray(entity.discrete(vertices, scale=path.scale), dtype=np.float64)
        if points.ndim != 2 or len(points) == 0:
            continue          # e.g. Text entities: nothing to mesh
        points = points[:, :2]
        if len(points) == 1:
            geometries.append({"type": "Point", "coordinates": points[0].tolist()})
        else:
            geometries.append({"type": "LineString", "coordinates": points.tolist()})
    if not geometries:
        raise cdt_plugin.InvalidGeometryError("the Path2D has no polygons and no open entities")
    return PLC.from_geo_interface({"type": "GeometryCollection", "geometries": geometries})


def from_path3d(path: trimesh.path.Path3D) -> PLC:
    """Read a planar ``trimesh.path.Path3D`` (in any plane) into a
    :class:`cdt_plugin.PLC` with ``z``, which :func:`cdt_plugin.triangulate`
    meshes in its plane (:mod:`cdt_plugin.planar`; points off the plane raise
    :class:`cdt_plugin.NonPlanarError`).

    Every entity becomes a chain of constraint segments through its points
    (curves discretised as in :func:`from_path2d`), the path's vertices kept
    exactly; the domain is decided by depth parity (a closed loop inside a
    closed loop is a hole).

    >>> import trimesh, cdt_plugin
    >>> from trimesh.path.entities import Line
    >>> wall = trimesh.path.Path3D([Line([0, 1, 2, 3, 0])], [[0, 0, 0], [4, 0, 0], [4, 0, 3], [0, 0, 3]])
    >>> tri = cdt_plugin.triangulate(from_path3d(wall))
    >>> float(to_trimesh(tri).area), tri.plane.normal.tolist()
    (12.0, [0.0, 1.0, 0.0])
    """
    if not isinstance(path, trimesh.path.Path3D):
        raise TypeError(f"expected a trimesh.path.Path3D, got {type(path).__name__}")
    vertices = np.asarray(path.vertices, dtype=np.float64)
    geometries = []
    for entity in path.entities:
        points = np.asarray(entity.discrete(vertices, scale=path.scale), dtype=np.float64)
        if points.ndim != 2 or len(points) == 0:
            continue          # e.g. Text entities: nothing to mesh
        kind = "Point" if len(points) == 1 else "LineString"
        geometries.append({"type": kind, "coordinates": (points[0] if len(points) == 1 else points).tolist()})
    if not geometries:
        raise cdt_plugin.InvalidGeometryError("the Path3D has no entities with points")
    return PLC.from_geo_interface({"type": "GeometryCollection", "geometries": geometries})


# ----------------------------------------------------------- Triangulation -> Trimesh
def to_trimesh(tri: Triangulation, z: float | None = None, *, remove_unreferenced: bool = False,
               **kwargs: Any) -> trimesh.Trimesh:
    """A Triangulation as a flat ``trimesh.Trimesh``: in its own plane
    (``tri.vertices3d``: the plane of 3D input, z = 0 for 2D input), or at
    height ``z`` when given (``tri.vertices`` with that z).

    Faces are ``tri.triangles`` (counter-clockwise seen from the plane's
    normal, +z at height ``z``, so every face normal is that normal). The mesh
    is built with ``process=False``: no
    vertex is merged away, and vertex ``i`` of the mesh is ``tri.vertices[i]``
    — including the unreferenced ones (input vertices outside the domain). Pass
    ``remove_unreferenced=True`` to drop those (vertex indices then change).
    Other keywords go to the ``Trimesh`` constructor.
    """
    plane = getattr(tri, "plane", None)
    if z is None:
        vertices = np.asarray(tri.vertices3d, dtype=np.float64)
        normal = [0.0, 0.0, 1.0] if plane is None else plane.normal
    else:
        vertices = np.asarray(tri.vertices, dtype=np.float64)
        vertices = np.column_stack([vertices, np.full(len(vertices), float(z))])
        normal = [0.0, 0.0, 1.0]
    faces = np.asarray(tri.triangles, dtype=np.int64)
    if remove_unreferenced:
        vertices, faces = _compact(vertices, faces)
    vertices3 = vertices
    normals = np.tile(normal, (len(faces), 1))
    kwargs.setdefault("process", False)
    return trimesh.Trimesh(vertices=vertices3, faces=faces, face_normals=normals, **kwargs)


def _compact(vertices: NDArray[np.float64],
             faces: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Only the vertices the faces use, in their original order; faces renumbered."""
    used = np.zeros(len(vertices), bool)
    used[faces.ravel()] = True
    if used.all():          # the common case: nothing to drop
        return vertices, faces
    new_index = np.cumsum(used) - 1
    return vertices[used], new_index[faces].astype(np.int64)


# ------------------------------------------------------------- drop-ins for trimesh
def triangulate_polygon(polygon: shapely.Geometry | None, triangle_args: str | None = None,
                        engine: str | None = None, force_vertices: bool = False,
                        **kwargs: Any) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Drop-in for ``trimesh.creation.triangulate_polygon``: constrained
    Delaunay triangulation of a shapely polygon.

    Parameters
    ----------
    polygon : shapely Polygon (or anything with ``__geo_interface__``: MultiPolygon...)
    triangle_args : str, optional
        Triangle's switches, translated by
        :func:`cdt_plugin.switches.options_from_switches` (``"pq30a0.1"`` gives
        ``min_angle=30, max_area=0.1``); unsupported switches raise.
    engine : None
        Accepted for signature compatibility and ignored: this function *is*
        the engine.
    force_vertices : bool
        Raise ``ValueError`` if the triangulation has a vertex that is not an
        input vertex (intersections with ``"split"``, or quality refinement).
    **kwargs
        Passed to :func:`cdt_plugin.triangulate` (``intersections=``, ...);
        ``merge_distance`` defaults to ``trimesh.tol.merge`` (see the module's
        notes). The keywords of the ``Trimesh`` constructor, which trimesh's
        ``extrude_polygon`` passes on to both, are ignored here; any other
        keyword raises :class:`cdt_plugin.CDTError` naming it.

    Returns
    -------
    vertices : (n, 2) float64
        Only the vertices used by ``faces`` (trimesh's convention); exact
        duplicates (such as the closing point of a ring) appear once. A polygon
        with z coordinates gives 2D vertices too, with a :class:`DroppedZWarning`.
    faces : (m, 3) int64
        Counter-clockwise triangles.
    """
    if triangle_args is not None:
        kwargs = {**options_from_switches(triangle_args), **kwargs}
    kwargs = _engine_options(kwargs) if kwargs else {"merge_distance": trimesh.tol.merge}
    if polygon is None or polygon.is_empty:
        return np.empty((0, 2), np.float64), np.empty((0, 3), np.int64)
    if getattr(polygon, "has_z", False):
        warnings.warn("the polygon has z coordinates: trimesh's triangulate_polygon returns "
                      "(n, 2) vertices, so z is dropped", DroppedZWarning, stacklevel=2)
        import shapely                           # (only here: trimesh's polygons are shapely's)
        polygon = shapely.force_2d(polygon)      # (in x, y whatever its plane)
    tri = cdt_plugin.triangulate(polygon, **kwargs)
    if force_vertices and len(tri.steiner):
        raise ValueError(f"the triangulation inserted {len(tri.steiner)} vertices "
                         "(segment intersections or refinement) and force_vertices is set")
    return _compact(np.asarray(tri.vertices, np.float64), np.asarray(tri.triangles, np.int64))


#: The keywords of cdt_plugin.triangulate after the geometry (what the drop-ins pass on).
_TRIANGULATE_KEYWORDS = frozenset(list(inspect.signature(cdt_plugin.triangulate).parameters)[1:])
#: The keywords of the Trimesh constructor, which trimesh's extrude_polygon passes to the
#: triangulation and to the constructor alike.
_TRIMESH_KEYWORDS = frozenset(inspect.signature(trimesh.Trimesh.__init__).parameters) - {"self"}


def _engine_options(kwargs: dict[str, Any]) -> dict[str, Any]:
    """The keywords for :func:`cdt_plugin.triangulate`: ``merge_distance``
    defaulting to ``trimesh.tol.merge``, the ``Trimesh`` constructor's keywords
    left out; a :class:`cdt_plugin.CDTError` names any other unknown one."""
    unknown = sorted(kwargs.keys() - _TRIANGULATE_KEYWORDS - _TRIMESH_KEYWORDS)
    if unknown:
        raise cdt_plugin.CDTError(
            f"unknown option{'s' if len(unknown) > 1 else ''} {', '.join(map(repr, unknown))}: "
            "neither a keyword of cdt_plugin.triangulate nor of trimesh.Trimesh")
    options = {k: v for k, v in kwargs.items() if k in _TRIANGULATE_KEYWORDS}
    options.setdefault("merge_distance", trimesh.tol.merge)
    return options


def _boundary_edges(faces: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """Directed edges (i, j) of counter-clockwise faces whose reverse is no
    edge: the domain boundary, with the domain on the left."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    key = directed[:, 0] * n + directed[:, 1]
    reverse = directed[:, 1] * n + directed[:, 0]
    return directed[~np.isin(key, reverse)]


def _split_pinches(vertices: NDArray[np.float64], faces: NDArray[np.int64],
                   boundary: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Give each fan of faces around a pinch vertex (a vertex where the
    boundary passes more than once, such as a hole touching its shell) its
    own copy of the vertex, so that the extruded walls meet in manifold edges.
    Returns the (possibly longer) vertex array and the renumbered faces."""
    starts = np.bincount(boundary[:, 0], minlength=len(vertices))
    pinched = np.flatnonzero(starts > 1)
    if len(pinched) == 0:
        return vertices, faces
    faces = faces.copy()
    extra: list[NDArray[np.float64]] = []
    n = len(vertices)
    for v in pinched:
        around = np.flatnonzero((faces == v).any(axis=1))
        # union faces of the fan over the edges (v, w) they share
        parent = {int(f): int(f) for f in around}

        def find(f: int) -> int:
            while parent[f] != f:
                parent[f] = parent[parent[f]]
                f = parent[f]
            return f

        by_other: dict[int, list[int]] = {}
        for f in around:
            for w in faces[f]:
                if w != v:
                    by_other.setdefault(int(w), []).append(int(f))
        for shared in by_other.values():
            for other in shared[1:]:
                parent[find(other)] = find(shared[0])
        fans: dict[int, list[int]] = {}
        for f in around:
            fans.setdefault(find(int(f)), []).append(int(f))
        for fan in list(fans.values())[1:]:
            copy = n + len(extra)
            extra.append(vertices[v])
            rows = np.asarray(fan)
            faces[rows] = np.where(faces[rows] == v, copy, faces[rows])
    return np.concatenate([vertices, np.asarray(extra).reshape(-1, 2)]), faces


def extrude_triangulation(vertices: ArrayLike, faces: ArrayLike, height: float,
                          transform: ArrayLike | None = None, *, split_pinches: bool = True,
                          **kwargs: Any) -> trimesh.Trimesh:
    """Extrude a 2D triangulation into a closed solid, by vertex index.

    Unlike ``trimesh.creation.extrude_triangulation`` (which duplicates the wall
    vertices and lets ``Trimesh`` merge them by a rounding tolerance) the solid
    is built by index: vertex ``i`` of the 2D triangulation is vertex ``i`` at
    the bottom (z = 0) and ``i + n`` at the top (z = height); each boundary edge
    (an edge of exactly one face) gets two wall triangles on those same
    vertices. So nothing is merged by tolerance: vertices 1e-13 apart stay
    apart and the result is watertight whenever the triangulation is a
    manifold with boundary (every edge in one or two faces, consistently wound).
    ``faces`` may be in either winding; outward normals are enforced for the
    sign of ``height`` and for ``transform`` (a (4, 4) matrix applied last).
    With ``split_pinches`` (default) a vertex where the boundary passes twice
    (a hole touching its shell at a point) is duplicated, one copy per fan of
    faces, so the solid stays watertight (each edge in exactly two faces)
    instead of having a vertical edge in four faces; the copies share
    coordinates. Keywords go to the ``Trimesh`` constructor (default
    ``process=False``).
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if vertices.ndim != 2 or vertices.shape[1] != 2:
        raise ValueError(f"vertices must be (n, 2), got {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise ValueError(f"faces must be (m, 3), got {faces.shape}")
    height = float(height)
    if not np.isfinite(height) or height == 0.0:
        raise ValueError(f"height must be finite and nonzero, got {height}")
    n = len(vertices)
    if len(faces):
        a, b, c = (vertices[faces[:, k]] for k in range(3))
        area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        if np.sum(area2) < 0:            # clockwise input: make it counter-clockwise
            faces = faces[:, ::-1]
    boundary = _boundary_edges(faces, n)
    if split_pinches:
        vertices, faces = _split_pinches(vertices, faces, boundary)
        if len(vertices) != n:
            n = len(vertices)
            boundary = _boundary_edges(faces, n)
    i, j = boundary[:, 0], boundary[:, 1]
    # the domain lies left of i -> j, so (i, j, j') and (i, j', i') face outwards
    walls = np.concatenate([np.column_stack([i, j, j + n]), np.column_stack([i, j + n, i + n])])
    all_faces = np.concatenate([faces[:, ::-1], faces + n, walls])
    vertices3 = np.concatenate([np.column_stack([vertices, np.zeros(n)]),
                                np.column_stack([vertices, np.full(n, height)])])
    if height < 0:                       # the top is below the bottom: turn inside out
        all_faces = all_faces[:, ::-1]
    if transform is not None:
        transform = np.asarray(transform, dtype=np.float64)
        vertices3 = transformations.transform_points(vertices3, transform)
        if transformations.flips_winding(transform):
            all_faces = all_faces[:, ::-1]
    kwargs.setdefault("process", False)
    return trimesh.Trimesh(vertices=vertices3, faces=np.ascontiguousarray(all_faces), **kwargs)


def extrude_polygon(polygon: shapely.Geometry, height: float, transform: ArrayLike | None = None,
                    mid_plane: bool = False, **kwargs: Any) -> trimesh.Trimesh:
    """Drop-in for ``trimesh.creation.extrude_polygon``: the polygon extruded
    along +z by ``height`` into a watertight, consistently wound solid with
    outward normals and volume ``area * |height|``.

    ``transform`` (4, 4) is applied after construction; ``mid_plane=True``
    centres the solid on z = 0 (as trimesh does). Other keywords go to
    :func:`cdt_plugin.triangulate`; the solid is built by
    :func:`extrude_triangulation` (by index, no tolerance merging).
    """
    vertices, faces = triangulate_polygon(polygon, **kwargs)
    if len(faces) == 0:
        raise cdt_plugin.NoPolygonsError("the polygon is empty: nothing to extrude")
    if mid_plane:
        translation = np.eye(4)
        translation[2, 3] = abs(float(height)) / -2.0
        transform = translation if transform is None else np.dot(transform, translation)
    return extrude_triangulation(vertices, faces, height, transform=transform)


def extrude_path(path: trimesh.path.Path2D, height: float, transform: ArrayLike | None = None,
                 mid_plane: bool = False, **kwargs: Any) -> list[trimesh.Trimesh]:
    """Every polygon of ``path.polygons_full`` extruded by ``height``: one
    watertight ``Trimesh`` per polygon, in the order of ``polygons_full``
    (``Path2D.extrude`` returns trimesh ``Extrusion`` primitives the same way;
    this always returns a list). Use ``trimesh.util.concatenate`` for one mesh.
    Keywords go to :func:`cdt_plugin.triangulate`.
    """
    if not isinstance(path, trimesh.path.Path2D):
        raise TypeError(f"expected a trimesh.path.Path2D, got {type(path).__name__}")
    return [extrude_polygon(polygon, height, transform=transform, mid_plane=mid_plane, **kwargs)
            for polygon in path.polygons_full if polygon is not None and not polygon.is_empty]


# ------------------------------------------------- hooking into trimesh itself
# trimesh has no engine registry: register() replaces the module attribute
# trimesh.creation.triangulate_polygon by _hook. Every caller in trimesh looks the
# attribute up when it runs (extrude_polygon, sweep_polygon and revolve read the
# module global; Path2D.triangulate and slice_mesh_plane import it at call time),
# so that one replacement reaches them all.
_TriangulatePolygon = Callable[..., Tuple[NDArray[np.float64], NDArray[np.int64]]]


class _HookState(TypedDict):
    original: _TriangulatePolygon   # what register() replaced (trimesh's own function)
    default: bool                   # the hook's engine when none is named


# (register() stores the function it replaces; before that, trimesh's function at import)
_hooked: _HookState = {"original": trimesh.creation.triangulate_polygon, "default": False}


def _hook(polygon: shapely.Geometry | None, triangle_args: str | None = None,
          engine: str | None = None, force_vertices: bool = False,
          **kwargs: Any) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """trimesh's ``triangulate_polygon`` while :func:`register` is in force:
    ``engine="cdt_plugin"`` (any case; or no engine, after
    ``register(default=True)``) runs :func:`triangulate_polygon`, and an empty
    polygon raises :class:`cdt_plugin.NoPolygonsError` (trimesh's callers would
    fail on the empty arrays, or build an empty solid); any other engine runs
    trimesh's own function, its name lower-cased."""
    if isinstance(engine, str):
        engine = engine.lower()
    if engine == ENGINE or (engine is None and _hooked["default"]):
        if polygon is None or polygon.is_empty:
            raise cdt_plugin.NoPolygonsError(
                f"trimesh asked engine {ENGINE!r} to triangulate an empty polygon ({polygon!r})")
        return triangulate_polygon(polygon, triangle_args=triangle_args,
                                   force_vertices=force_vertices, **kwargs)
    return _hooked["original"](polygon, triangle_args=triangle_args, engine=engine,
                               force_vertices=force_vertices, **kwargs)


def is_registered() -> bool:
    """Whether ``trimesh.creation.triangulate_polygon`` is this module's hook."""
    return trimesh.creation.triangulate_polygon is _hook


def register(default: bool = False) -> None:
    """Make ``engine="cdt_plugin"`` an engine of ``trimesh.creation.triangulate_polygon``.

    After this, trimesh meshes with :func:`triangulate_polygon` whenever the
    engine is ``"cdt_plugin"``, in every trimesh function that goes through
    ``triangulate_polygon`` and passes the engine on: ``extrude_polygon``,
    ``sweep_polygon``, ``Path2D.triangulate`` and ``Trimesh.slice_plane(...,
    cap=True)`` (``engine=`` and, except for ``slice_plane``, the keywords of
    :func:`cdt_plugin.triangulate` or ``triangle_args``). With ``default=True`` it
    is also the engine when none is named, which reaches the callers that pass
    no engine: ``Path2D.extrude``, the ``Extrusion`` primitive, ``revolve(cap=True)``.
    Other engine names (``"earcut"``, ``"manifold"``, ``"triangle"``) still go to
    trimesh's own function. Engine names are case-insensitive (``"CDT_Plugin"``,
    ``"Earcut"``). With this engine, an empty polygon raises
    :class:`cdt_plugin.NoPolygonsError`, and a keyword that is neither
    :func:`cdt_plugin.triangulate`'s nor the ``Trimesh`` constructor's (which
    trimesh's ``extrude_polygon`` passes on too) a :class:`cdt_plugin.CDTError`
    naming it.

    Calling it again only updates ``default`` (nothing is wrapped twice);
    :func:`unregister` puts trimesh's function back, and :func:`registered` does
    both around a ``with`` block.

    >>> import shapely, trimesh, cdt_plugin.adapters.trimesh as ct
    >>> ct.register()
    >>> v, f = trimesh.creation.triangulate_polygon(shapely.box(0, 0, 2, 1), engine="cdt_plugin")
    >>> v.shape, f.shape
    ((4, 2), (2, 3))
    >>> solid = trimesh.creation.extrude_polygon(shapely.box(0, 0, 2, 1), 3.0, engine="cdt_plugin")
    >>> bool(solid.is_watertight), float(solid.volume)
    (True, 6.0)
    >>> ct.unregister()
    """
    if not isinstance(default, bool):
        raise cdt_plugin.CDTError(f"default must be True or False, got {default!r}")
    if not is_registered():
        _hooked["original"] = trimesh.creation.triangulate_polygon
        trimesh.creation.triangulate_polygon = _hook
    _hooked["default"] = default


def unregister() -> None:
    """Put trimesh's own ``triangulate_polygon`` back (the very function object
    :func:`register` replaced); does nothing if the hook is not registered.

    >>> import trimesh, cdt_plugin.adapters.trimesh as ct
    >>> original = trimesh.creation.triangulate_polygon
    >>> ct.register(); ct.unregister()
    >>> trimesh.creation.triangulate_polygon is original
    True
    """
    if is_registered():
        trimesh.creation.triangulate_polygon = _hooked["original"]
    _hooked["default"] = False


@contextlib.contextmanager
def registered(default: bool = False) -> Iterator[None]:
    """:func:`register` for the duration of a ``with`` block, then the state
    before it (unregistered, or registered with the earlier ``default``), even
    if the block raises.

    >>> import shapely, trimesh, cdt_plugin.adapters.trimesh as ct
    >>> with ct.registered(default=True):
    ...     v, f = trimesh.creation.triangulate_polygon(shapely.box(0, 0, 1, 1))
    >>> len(f), ct.is_registered()
    (2, False)
    """
    before = is_registered(), _hooked["default"]
    register(default)
    try:
        yield
    finally:
        if before[0]:
            register(before[1])
        else:
            unregister()
