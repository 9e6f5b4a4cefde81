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
path_polygons(path)
    The polygons a ``Path2D``'s closed loops bound, exact where loops touch.
sweep_polygon(polygon, path, angles=None, cap=True, connect=True)
    Drop-in for ``trimesh.creation.sweep_polygon``: a watertight sweep.
Extrusion(polygon, transform=None, height=1.0, mutable=True, mid_plane=False)
    trimesh's lazy ``Extrusion`` primitive, its mesh built by :func:`extrude_polygon`.
register(default=False), unregister(), registered(default=False)
    Hook this engine into trimesh itself: ``engine="cdt_plugin"`` in
    ``trimesh.creation.triangulate_polygon``, ``extrude_polygon`` and
    ``sweep_polygon`` (whose solids trimesh would otherwise build by merging
    vertices) and in everything that calls them (``Path2D.triangulate`` /
    ``extrude``, ``Trimesh.slice_plane(cap=True)``); with ``default=True`` also
    when no engine is named, and ``Path2D.extrude`` returns :class:`Extrusion`.

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
from typing import TYPE_CHECKING, Any, Iterator, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray

from cdt_plugin.optional import missing

try:
    import trimesh
    import trimesh.creation
    import trimesh.path
    import trimesh.intersections
    import trimesh.primitives
    from trimesh import transformations
except ImportError as exc:
    raise missing(exc.name, "cdt_plugin.adapters.trimesh", extra="trimesh") from exc

import cdt_plugin
from cdt_plugin import PLC
from cdt_plugin import solids
from cdt_plugin.plain import plain_mesh
from cdt_plugin.switches import options_from_switches

if TYPE_CHECKING:
    import shapely

    from cdt_plugin import Triangulation

__all__ = ["from_path2d", "from_path3d", "to_trimesh", "triangulate_polygon", "extrude_polygon",
           "extrude_triangulation", "extrude_path", "path_polygons", "sweep_polygon", "slice_plane", "Extrusion",
           "register", "unregister", "registered", "is_registered", "ENGINE", "DroppedZWarning"]

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
        Raise :class:`cdt_plugin.CDTError` (a ``ValueError``, as trimesh
        raises) if the triangulation has a vertex that is not an input vertex
        (intersections with ``"split"``, or quality refinement).
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
    if triangle_args is None and not kwargs:     # (most calls: one compiled call, or None)
        plain = plain_mesh(polygon, trimesh.tol.merge)
        if plain is not None:
            return plain
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
        raise cdt_plugin.CDTError(f"the triangulation inserted {len(tri.steiner)} vertices "
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
        raise cdt_plugin.InputShapeError(f"vertices must be (n, 2), got {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise cdt_plugin.InputShapeError(f"faces must be (m, 3), got {faces.shape}")
    height = float(height)
    if not np.isfinite(height) or height == 0.0:
        raise cdt_plugin.CDTError(f"height must be finite and nonzero, got {height}")
    n = len(vertices)
    if len(faces):
        a, b, c = (vertices[faces[:, k]] for k in range(3))
        area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        if np.sum(area2) < 0:            # clockwise input: make it counter-clockwise
            faces = faces[:, ::-1]
    if split_pinches:
        vertices, faces = solids.split_pinches(vertices, faces)
        n = len(vertices)
    boundary = solids.boundary_edges(faces, n)
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
    :func:`cdt_plugin.triangulate`, except the ``Trimesh`` constructor's
    (``process=``, ``validate=``...: trimesh's own ``extrude_polygon`` passes
    its keywords to both), which go to the constructor; the solid is built by
    :func:`extrude_triangulation` (by index, no tolerance merging).
    """
    vertices, faces = triangulate_polygon(polygon, **kwargs)
    if len(faces) == 0:
        raise cdt_plugin.NoPolygonsError("the polygon is empty: nothing to extrude")
    if mid_plane:
        translation = np.eye(4)
        translation[2, 3] = abs(float(height)) / -2.0
        transform = translation if transform is None else np.dot(transform, translation)
    constructor = {k: v for k, v in kwargs.items() if k in _TRIMESH_KEYWORDS}
    return extrude_triangulation(vertices, faces, height, transform=transform, **constructor)


def path_polygons(path: trimesh.path.Path2D) -> list[shapely.Polygon]:
    """The polygons a ``Path2D``'s closed loops bound, decided by the engine.

    trimesh's ``path.polygons_full`` finds closed loops by a graph search that,
    at a vertex where loops touch (a hole touching its shell or another hole, as
    a ``Trimesh.section`` through such a solid gives), can join or split rings
    into wrong polygons. Here every segment of the entities in closed loops
    (curves discretised as trimesh does) is meshed at once, inside by parity
    (odd numbers of segments crossed from outside), and the triangles are
    joined into polygons by dropping the edges they share (GEOS's coverage
    union: no arithmetic), rings that touch at a point kept apart as OGC wants;
    in the order of ``polygons_full`` where it has the same polygon.

    >>> import shapely, trimesh
    >>> square = [(0, 0), (10, 0), (10, 10), (0, 10)]
    >>> p = shapely.Polygon(square, [[(0, 5), (3, 4), (3, 6)], [(3, 4), (5, 2), (5, 4)]])
    >>> path = trimesh.load_path(p)
    >>> [q.area for q in path_polygons(path)]
    [95.0]
    """
    vertices = np.asarray(path.vertices, dtype=np.float64)
    dangling = set(map(int, path.dangling))
    points, segments, start = [], [], 0
    for index, entity in enumerate(path.entities):
        if index in dangling:
            continue
        line = np.asarray(entity.discrete(vertices, scale=path.scale), dtype=np.float64)
        if line.ndim != 2 or len(line) < 2:
            continue                              # (Text entities: no segments)
        points.append(line[:, :2])
        k = np.arange(start, start + len(line) - 1)
        segments.append(np.column_stack([k, k + 1]))
        start += len(line)
    if not points:
        return []
    V, inverse = np.unique(np.concatenate(points), axis=0, return_inverse=True)
    S = inverse.reshape(-1)[np.concatenate(segments)]
    S = S[S[:, 0] != S[:, 1]]
    if not len(S):
        return []
    tri = cdt_plugin.triangulate(V, S)
    import shapely                                # (only here: trimesh's polygons are shapely's)
    V, T = np.asarray(tri.vertices, np.float64), np.asarray(tri.triangles, np.int64)
    # the triangles share their edges exactly: a coverage union only drops the shared
    # edges (no arithmetic) and gives each polygon in OGC's form (touching rings apart)
    union = shapely.coverage_union_all(shapely.polygons(V[T]))
    parts = [part for part in shapely.get_parts(union).tolist() if not part.is_empty]
    # in the order of polygons_full where trimesh found the same polygon
    theirs = [p for p in path.polygons_full if p is not None and not p.is_empty]
    where = [next((i for i, p in enumerate(theirs) if p.equals(part)), len(theirs) + k)
             for k, part in enumerate(parts)]
    return [parts[k] for k in np.argsort(where, kind="stable")]


def extrude_path(path: trimesh.path.Path2D, height: float, transform: ArrayLike | None = None,
                 mid_plane: bool = False, **kwargs: Any) -> list[trimesh.Trimesh]:
    """Every polygon of the path (:func:`path_polygons`: its closed loops'
    polygons, decided exactly, also where loops touch) extruded by ``height``:
    one watertight ``Trimesh`` per polygon (``Path2D.extrude`` returns trimesh
    ``Extrusion`` primitives the same way; this always returns a list). Use
    ``trimesh.util.concatenate`` for one mesh. Keywords go to
    :func:`cdt_plugin.triangulate`.
    """
    if not isinstance(path, trimesh.path.Path2D):
        raise TypeError(f"expected a trimesh.path.Path2D, got {type(path).__name__}")
    return [extrude_polygon(polygon, height, transform=transform, mid_plane=mid_plane, **kwargs)
            for polygon in path_polygons(path)]


def _sweep_frames(path: NDArray[np.float64], angles: NDArray[np.float64],
                  closed: bool) -> NDArray[np.float64]:
    """The (len(path), 4, 4) frames of ``trimesh.creation.sweep_polygon``: frame
    ``k`` takes the profile's plane to the plane through ``path[k]`` whose
    normal is the path's direction there (the mean of the two adjacent
    directions; of the first and last on a closed path), turned by ``angles[k]``.
    Composed as trimesh documents its unrolled matrices, so a sweep puts the
    profile where trimesh's own does."""
    direction = trimesh.util.unitize(path[1:] - path[:-1])
    mean = trimesh.util.unitize(direction[1:] + direction[:-1])
    normal = np.concatenate([direction[:1], mean, direction[-1:]])
    if closed:
        normal[0] = trimesh.util.unitize(normal[[0, -1]].mean(axis=0))
    theta, phi = trimesh.util.vector_to_spherical(normal).T
    frames = np.empty((len(path), 4, 4))
    for k in range(len(path)):
        rotation = (transformations.rotation_matrix(angles[k], [0, 0, 1])
                    @ transformations.rotation_matrix(phi[k], [1, 0, 0])
                    @ transformations.rotation_matrix(np.pi / 2 - theta[k], [0, 0, 1]))
        frames[k] = rotation.T            # the inverse of a rotation
        frames[k, :3, 3] = path[k]
    return frames


def sweep_polygon(polygon: shapely.Geometry, path: ArrayLike, angles: ArrayLike | None = None,
                  cap: bool = True, connect: bool = True, kwargs: dict[str, Any] | None = None,
                  **triangulation: Any) -> trimesh.Trimesh:
    """Drop-in for ``trimesh.creation.sweep_polygon``: the polygon swept along a
    3D ``path`` (n, 3), its plane at each path point as trimesh places it
    (normal along the path, turned by ``angles``).

    Built by index like :func:`extrude_triangulation`: each profile vertex is
    one vertex per path point, each boundary edge of the triangulation two
    wall triangles per step, pinch vertices (a hole touching the shell) split
    per fan. So the solid is watertight where trimesh's own sweep, given a
    triangulation with the pinch point once (ours, earcut's), leaves the wall
    edges there in four faces; and the end caps keep the interior
    Steiner points of a refined triangulation (``min_angle=``, ``max_area=``),
    which trimesh's sweep cannot place. ``cap`` closes an open path with the
    profile at both ends; a closed path (last point within ``trimesh.tol.merge``
    of the first) is joined into a ring when ``connect``. ``kwargs`` go to the
    ``Trimesh`` constructor (default ``process=False``), other keywords to
    :func:`triangulate_polygon`.

    >>> import shapely
    >>> ring = shapely.box(0, 0, 2, 2).difference(shapely.box(0.5, 0.5, 1.5, 1.5))
    >>> solid = sweep_polygon(ring, [[0, 0, 0], [0, 0, 1], [0, 0, 3]])
    >>> bool(solid.is_watertight), round(float(solid.volume), 12)
    (True, 9.0)
    """
    path = np.asarray(path, dtype=np.float64)
    if path.ndim != 2 or path.shape[1] != 3 or len(path) < 2:
        raise cdt_plugin.InputShapeError(f"the sweep path must be (n, 3) with n >= 2, got {path.shape}")
    angles = np.zeros(len(path)) if angles is None else np.asarray(angles, dtype=np.float64)
    if angles.shape != (len(path),):
        raise cdt_plugin.InputShapeError(f"angles must be ({len(path)},), one per path point, "
                                         f"got {angles.shape}")
    vertices, faces = _profile(polygon, triangulation)
    boundary = solids.boundary_edges(faces, len(vertices))
    ring = bool(np.linalg.norm(path[0] - path[-1]) < trimesh.tol.merge) and connect
    frames = _sweep_frames(path, angles, ring)
    slices = len(path) - 1 if ring else len(path)      # a ring's last point is its first
    n = len(vertices)
    flat = np.column_stack([vertices, np.zeros(n), np.ones(n)])
    vertices3 = np.concatenate([flat @ frame.T for frame in frames[:slices]])[:, :3]
    i, j = boundary[:, 0], boundary[:, 1]
    walls = []
    for k in range(len(path) - 1):
        here, there = k * n, (k + 1) % slices * n
        # the quad's diagonal as trimesh's own sweep draws it (the volume of a
        # curved sweep depends on it)
        walls += [np.column_stack([i + here, j + here, i + there]),
                  np.column_stack([j + there, i + there, j + here])]
    if cap and not ring:
        walls += [faces[:, ::-1], faces + (slices - 1) * n]
    vertices3, all_faces = _compact(vertices3, np.concatenate(walls))
    kwargs = dict(kwargs or {})
    kwargs.setdefault("process", False)
    return trimesh.Trimesh(vertices=vertices3, faces=np.ascontiguousarray(all_faces), **kwargs)


def _profile(polygon: shapely.Geometry,
             options: dict[str, Any]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The counter-clockwise triangulation of a profile, its pinch vertices split."""
    vertices, faces = triangulate_polygon(polygon, **options)
    if len(faces) == 0:
        raise cdt_plugin.NoPolygonsError(f"the polygon is empty: nothing to sweep ({polygon!r})")
    return solids.split_pinches(vertices, faces)


def slice_plane(mesh: trimesh.Trimesh, plane_origin: ArrayLike, plane_normal: ArrayLike,
                **kwargs: Any) -> trimesh.Trimesh:
    """The part of ``mesh`` on the positive side of a plane, capped: what
    ``mesh.slice_plane(origin, normal, cap=True)`` gives, built by index.

    Each edge crossing the plane gets one cut vertex, shared by both faces
    (trimesh's slicer gives each face its own and then merges vertices by a
    rounding tolerance, which folds the copies of a pinch point back into one
    and leaves edges in four faces). The cap is the constrained Delaunay
    triangulation of the cut's boundary loops in the plane, its pinch points
    split like :func:`extrude_triangulation`'s, each cap vertex the very vertex
    of the loop it closes. Vertices within ``trimesh.tol.merge`` of the plane
    count as on it (trimesh's rule). So a watertight mesh gives a watertight part whose
    volume is the exact part's volume up to rounding. Several planes
    ((n, 3) origins and normals) are applied in turn; keywords go to the
    ``Trimesh`` constructor (default ``process=False``).

    >>> import shapely
    >>> block = extrude_polygon(shapely.box(0, 0, 4, 4).difference(shapely.box(1, 1, 2, 2)), 2.0)
    >>> part = slice_plane(block, [0, 0, 0.5], [0, 0, 1])
    >>> bool(part.is_watertight), float(part.volume)
    (True, 22.5)
    """
    origins = np.asarray(plane_origin, dtype=np.float64).reshape(-1, 3)
    normals = np.asarray(plane_normal, dtype=np.float64).reshape(-1, 3)
    if origins.shape != normals.shape:
        raise cdt_plugin.InputShapeError(f"plane origins {origins.shape} and normals "
                                         f"{normals.shape} must be (3,) or (n, 3) alike")
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    for origin, normal in zip(origins, normals):
        vertices, faces = _cut(vertices, faces, origin, normal)
    vertices, faces = _compact(vertices, faces)
    kwargs.setdefault("process", False)
    return trimesh.Trimesh(vertices=vertices, faces=faces, **kwargs)


def _cut(vertices: NDArray[np.float64], faces: NDArray[np.int64], origin: NDArray[np.float64],
         normal: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The faces on the positive side of the plane, clipped at it by index, and
    the cap over the cut."""
    distance = (vertices - origin) @ normal
    # trimesh's rule: a vertex within trimesh.tol.merge of the plane is on it (a
    # vertex a rounding error off it would give cut points a rounding error apart)
    sign = np.where(np.abs(distance) <= trimesh.tol.merge, 0, np.sign(distance)).astype(np.int64)
    corner = sign[faces]
    keep = faces[(corner >= 0).all(axis=1) & (corner > 0).any(axis=1)]
    crossing = faces[(corner < 0).any(axis=1) & (corner > 0).any(axis=1)]
    # one cut vertex per crossing edge, computed from its lower-numbered end
    a, b = crossing, np.roll(crossing, -1, axis=1)
    cut = sign[a] * sign[b] < 0
    low, high = np.minimum(a, b)[cut], np.maximum(a, b)[cut]
    keys, index = np.unique(low * len(vertices) + high, return_inverse=True)
    u, w = keys // len(vertices), keys % len(vertices)
    t = distance[u] / (distance[u] - distance[w])
    points = vertices[u] + t[:, None] * (vertices[w] - vertices[u])
    cut_vertex = np.full(a.shape, -1, np.int64)
    cut_vertex[cut] = len(vertices) + index
    vertices = np.concatenate([vertices, points])
    faces = np.concatenate([keep, _clipped(crossing, cut_vertex, sign[crossing] >= 0)])
    on_plane = np.concatenate([sign == 0, np.ones(len(points), bool)])
    return vertices, np.concatenate([faces, _cap(vertices, faces, on_plane, origin, normal)])


def _clipped(crossing: NDArray[np.int64], cut_vertex: NDArray[np.int64],
             kept: NDArray[np.bool_]) -> NDArray[np.int64]:
    """The parts of the ``crossing`` faces on the positive side, as fans: each
    face's ring is its kept corners and the cut vertices of its edges (-1: not
    cut), in the face's order (corner k, then the cut of edge k -> k+1); a plane
    leaves 3 or 4 of them, which give 1 or 2 faces, face by face."""
    if not len(crossing):
        return np.empty((0, 3), np.int64)
    values = np.stack([crossing, cut_vertex], axis=2).reshape(-1, 6)
    present = np.stack([kept, cut_vertex >= 0], axis=2).reshape(-1, 6)
    ring = np.take_along_axis(values, np.argsort(~present, axis=1, kind="stable"), axis=1)
    fans = np.stack([ring[:, [0, 1, 2]], ring[:, [0, 2, 3]]], axis=1)     # (m, 2, 3)
    second = present.sum(axis=1) == 4
    return fans[np.column_stack([np.ones(len(ring), bool), second])]


def _cap(vertices: NDArray[np.float64], faces: NDArray[np.int64], on_plane: NDArray[np.bool_],
         origin: NDArray[np.float64], normal: NDArray[np.float64]) -> NDArray[np.int64]:
    """Faces (indices into ``vertices``) closing the boundary loops of ``faces``
    that lie on the plane, facing away from ``normal``."""
    open_edges = solids.boundary_edges(faces[:, ::-1], len(vertices))    # the loops, cap-wise
    open_edges = open_edges[on_plane[open_edges].all(axis=1)]
    if len(open_edges) < 3:
        return np.empty((0, 3), np.int64)
    used, segments = np.unique(open_edges, return_inverse=True)
    segments = segments.reshape(-1, 2)
    to_2d = trimesh.geometry.plane_transform(origin=origin, normal=-normal)
    points = transformations.transform_points(vertices[used], to_2d)[:, :2]
    tri = cdt_plugin.triangulate(points, segments)
    if len(tri.steiner):
        raise cdt_plugin.InvalidMeshError(
            f"the cut of the mesh by the plane through {origin.tolist()} with normal "
            f"{normal.tolist()} crosses itself: it cannot be capped")
    cap = np.asarray(tri.triangles, np.int64)
    merged = np.asarray(tri.vertex_map, np.int64)         # loop vertex -> vertex of tri
    loop_vertex = np.full(len(tri.vertices), -1, np.int64)
    loop_vertex[merged] = np.arange(len(merged))
    corners = loop_vertex[cap]
    # where loop vertices coincide (a pinch point; or the cut runs along an edge of
    # the mesh twice) each fan of cap faces around the point takes the loop vertex
    # of the loop edges that bound it
    for v in np.flatnonzero(np.bincount(merged, minlength=len(tri.vertices)) > 1):
        for rows, cols, loop in _fans(cap, int(v), merged, segments):
            corners[rows, cols] = loop
    return used[corners]


def _fans(cap: NDArray[np.int64], v: int, merged: NDArray[np.int64],
          segments: NDArray[np.int64]) -> Iterator[tuple[NDArray[np.int64], NDArray[np.int64], int]]:
    """The fans of cap faces around vertex ``v`` (faces joined by an edge at
    ``v`` that is no loop edge), each as (face rows, corner columns, the loop
    vertex that bounds it: the start of a loop edge leaving ``v`` along the
    fan's faces, or the end of one arriving)."""
    rows, cols = np.nonzero(cap == v)
    loop_edges = {(int(merged[a]), int(merged[b])): (int(a), int(b)) for a, b in segments}
    parent = list(range(len(rows)))

    def find(k: int) -> int:
        while parent[k] != k:
            parent[k] = parent[parent[k]]
            k = parent[k]
        return k

    by_edge: dict[int, int] = {}
    bounds: dict[int, int] = {}                  # face k -> its loop vertex at v
    for k, (row, col) in enumerate(zip(rows, cols)):
        after, before = int(cap[row, (col + 1) % 3]), int(cap[row, (col + 2) % 3])
        if (v, after) in loop_edges:
            bounds[k] = loop_edges[(v, after)][0]
        elif (before, v) in loop_edges:
            bounds[k] = loop_edges[(before, v)][1]
        for w in (after, before):
            if (v, w) in loop_edges or (w, v) in loop_edges:
                continue                          # a loop edge parts the fans
            if w in by_edge:
                parent[find(k)] = find(by_edge[w])
            else:
                by_edge[w] = k
    fans: dict[int, list[int]] = {}
    for k in range(len(rows)):
        fans.setdefault(find(k), []).append(k)
    for members in fans.values():
        loop = next((bounds[k] for k in members if k in bounds), None)
        if loop is not None:
            yield rows[members], cols[members], loop


class Extrusion(trimesh.primitives.Extrusion):
    """trimesh's ``Extrusion`` primitive whose mesh this engine builds
    (:func:`extrude_polygon`: watertight, by index), whenever it is first
    touched or rebuilt after a change of its ``primitive`` attributes.

    Under ``register(default=True)``, ``Path2D.extrude`` returns these; the
    mesh stays ours after the registration ends. Everything else is trimesh's
    primitive, and ``trimesh.primitives.Extrusion`` stays trimesh's class (of
    which this is a subclass): volume and area from the polygon, ``slide``,
    ``buffer``, ``to_dict``...

    >>> import shapely
    >>> part = Extrusion(shapely.box(0, 0, 2, 1), height=3.0)
    >>> isinstance(part, trimesh.primitives.Extrusion), bool(part.is_watertight), len(part.faces)
    (True, True, 12)
    """

    def _create_mesh(self) -> None:
        attributes = self.primitive
        mesh = extrude_polygon(attributes.polygon, attributes.height,
                               transform=attributes.transform, mid_plane=attributes.mid_plane)
        self._cache["vertices"] = mesh.vertices
        self._cache["faces"] = mesh.faces


# ------------------------------------------------- hooking into trimesh itself
# trimesh has no engine registry: register() replaces module attributes of trimesh
# by hooks that dispatch on the engine name. Every caller in trimesh looks the
# attributes up when it runs (extrude_polygon, sweep_polygon and revolve read the
# creation module's globals; Path2D.triangulate and slice_mesh_plane import them at
# call time; the Extrusion primitive calls creation.extrude_polygon; Trimesh.slice_plane
# calls intersections.slice_mesh_plane; Path2D.extrude is looked up on the class).
def _ours(engine: str | None) -> bool:
    """Whether a trimesh call naming ``engine`` is for this engine."""
    if engine is None:
        return _hooked["default"]
    return isinstance(engine, str) and engine.lower() == ENGINE


def _engine_name(engine: str | None) -> str | None:
    """trimesh's engine names in any case."""
    return engine.lower() if isinstance(engine, str) else engine


def _hook(polygon: shapely.Geometry | None, triangle_args: str | None = None,
          engine: str | None = None, force_vertices: bool = False,
          **kwargs: Any) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """trimesh's ``triangulate_polygon`` while :func:`register` is in force:
    ``engine="cdt_plugin"`` (any case; or no engine, after
    ``register(default=True)``) runs :func:`triangulate_polygon`, and an empty
    polygon raises :class:`cdt_plugin.NoPolygonsError` (trimesh's callers would
    fail on the empty arrays, or build an empty solid); any other engine runs
    trimesh's own function, its name lower-cased."""
    if _ours(engine):
        if polygon is None or polygon.is_empty:
            raise cdt_plugin.NoPolygonsError(
                f"trimesh asked engine {ENGINE!r} to triangulate an empty polygon ({polygon!r})")
        return triangulate_polygon(polygon, triangle_args=triangle_args,
                                   force_vertices=force_vertices, **kwargs)
    return _original("triangulate_polygon")(polygon, triangle_args=triangle_args,
                                            engine=_engine_name(engine),
                                            force_vertices=force_vertices, **kwargs)


def _extrude_hook(polygon: shapely.Geometry, height: float, transform: ArrayLike | None = None,
                  mid_plane: bool = False, **kwargs: Any) -> trimesh.Trimesh:
    """trimesh's ``extrude_polygon`` while :func:`register` is in force: with
    this engine, :func:`extrude_polygon` (trimesh's own stacks the caps and
    walls as separate vertices and lets the ``Trimesh`` constructor merge them
    by a rounding tolerance, which folds pinch points and near-duplicates)."""
    if _ours(kwargs.get("engine")):
        if polygon is None or polygon.is_empty:
            raise cdt_plugin.NoPolygonsError(
                f"trimesh asked engine {ENGINE!r} to extrude an empty polygon ({polygon!r})")
        return extrude_polygon(polygon, height, transform=transform, mid_plane=mid_plane, **kwargs)
    if "engine" in kwargs:
        kwargs["engine"] = _engine_name(kwargs["engine"])
    return _original("extrude_polygon")(polygon, height, transform=transform, mid_plane=mid_plane,
                                        **kwargs)


def _sweep_hook(polygon: shapely.Geometry, path: ArrayLike, angles: ArrayLike | None = None,
                cap: bool = True, connect: bool = True, kwargs: dict[str, Any] | None = None,
                **triangulation: Any) -> trimesh.Trimesh:
    """trimesh's ``sweep_polygon`` while :func:`register` is in force: with
    this engine, :func:`sweep_polygon` (by index, pinch points split)."""
    if _ours(triangulation.get("engine")):
        if polygon is None or polygon.is_empty:
            raise cdt_plugin.NoPolygonsError(
                f"trimesh asked engine {ENGINE!r} to sweep an empty polygon ({polygon!r})")
        return sweep_polygon(polygon, path, angles=angles, cap=cap, connect=connect,
                             kwargs=kwargs, **triangulation)
    if "engine" in triangulation:
        triangulation["engine"] = _engine_name(triangulation["engine"])
    return _original("sweep_polygon")(polygon, path, angles=angles, cap=cap, connect=connect,
                                      kwargs=kwargs, **triangulation)


def _slice_hook(mesh: trimesh.Trimesh, plane_normal: ArrayLike, plane_origin: ArrayLike,
                face_index: ArrayLike | None = None, cap: bool = False, engine: str | None = None,
                **kwargs: Any) -> trimesh.Trimesh | None:
    """trimesh's ``slice_mesh_plane`` (behind ``Trimesh.slice_plane``) while
    :func:`register` is in force: capped with this engine, :func:`slice_plane`
    for a watertight mesh (its guarantee needs one). A mesh that is not
    watertight by index (vertices split at texture seams, a triangle soup)
    goes to trimesh's own step, which merges vertices by a tolerance first."""
    if cap and face_index is None and mesh is not None and _ours(engine) and mesh.is_watertight:
        return slice_plane(mesh, plane_origin, plane_normal, **kwargs)
    return _original("slice_mesh_plane")(mesh, plane_normal, plane_origin, face_index=face_index,
                                         cap=cap, engine=_engine_name(engine), **kwargs)


def _path_extrude_hook(self: trimesh.path.Path2D, height: float,
                       **kwargs: Any) -> Extrusion | list[Extrusion]:
    """``Path2D.extrude`` under ``register(default=True)``: trimesh's lazy
    primitives, one per polygon of :func:`path_polygons` (one alone, not in a
    list, as trimesh returns it), of class :class:`Extrusion`."""
    result = [Extrusion(polygon=polygon, height=height, **kwargs) for polygon in path_polygons(self)]
    return result[0] if len(result) == 1 else result


def _path_triangulate_hook(self: trimesh.path.Path2D,
                           **kwargs: Any) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """``Path2D.triangulate`` while :func:`register` is in force: with this
    engine, the polygons of :func:`path_polygons` meshed by
    :func:`triangulate_polygon` and appended as trimesh appends them."""
    if not _ours(kwargs.get("engine")):
        if "engine" in kwargs:
            kwargs["engine"] = _engine_name(kwargs["engine"])
        return _original("triangulate")(self, **kwargs)
    kwargs.pop("engine", None)
    pieces = [triangulate_polygon(polygon, **kwargs) for polygon in path_polygons(self)]
    v, f = trimesh.util.append_faces([v for v, _ in pieces], [f for _, f in pieces])
    return np.asarray(v, np.float64), np.asarray(f, np.int64)


# What register() replaces: (module or class, attribute) -> the replacement.
# Path2D.extrude only with default=True (it names no engine).
_HOOKS: dict[tuple[Any, str], Any] = {
    (trimesh.creation, "triangulate_polygon"): _hook,
    (trimesh.creation, "extrude_polygon"): _extrude_hook,
    (trimesh.creation, "sweep_polygon"): _sweep_hook,
    (trimesh.path.Path2D, "triangulate"): _path_triangulate_hook,
    (trimesh.intersections, "slice_mesh_plane"): _slice_hook,
}
_DEFAULT_HOOKS: dict[tuple[Any, str], Any] = {(trimesh.path.Path2D, "extrude"): _path_extrude_hook}


class _HookState(TypedDict):
    originals: dict[str, Any]    # attribute name -> what register() replaced (trimesh's own)
    default: bool                # the hooks' engine when none is named


# (register() stores what it replaces; before that, trimesh's own at import)
_hooked: _HookState = {"originals": {name: getattr(module, name)
                                     for module, name in [*_HOOKS, *_DEFAULT_HOOKS]},
                       "default": False}


def _original(name: str) -> Any:
    """trimesh's own attribute ``name`` (the one register() replaced)."""
    return _hooked["originals"][name]


def is_registered() -> bool:
    """Whether the hooks of :func:`register` are in trimesh (``trimesh.creation.triangulate_polygon``
    is this module's hook)."""
    return trimesh.creation.triangulate_polygon is _hook


def register(default: bool = False) -> None:
    """Make ``engine="cdt_plugin"`` an engine of trimesh, and keep this engine's
    guarantees (watertight solids of the exact volume) in trimesh's own functions.

    trimesh has no engine registry, so this replaces attributes of trimesh's
    modules by hooks that run this module's functions when the engine is
    ``"cdt_plugin"`` and trimesh's own otherwise:

    * ``trimesh.creation.triangulate_polygon``: :func:`triangulate_polygon`;
      reaches ``Path2D.triangulate``, ``revolve(cap=True)`` and the caps of
      trimesh's own slicing (meshes that are not watertight by index).
    * ``trimesh.creation.extrude_polygon``: :func:`extrude_polygon`. trimesh's
      own extrusion gives the walls their own vertices and lets the ``Trimesh``
      constructor merge them with the caps' by a rounding tolerance, which
      leaves pinch points (holes touching each other or the shell at a vertex)
      and points a rounding error apart not watertight; ours builds the solid by
      index and splits pinch points.
    * ``trimesh.creation.sweep_polygon``: :func:`sweep_polygon` (trimesh's own,
      given a triangulation with a pinch point once, as ours, leaves the wall
      edges there in four faces, and cannot cap a triangulation with interior
      Steiner points).
    * ``trimesh.intersections.slice_mesh_plane`` with ``cap=True`` (behind
      ``Trimesh.slice_plane``) of a watertight mesh: :func:`slice_plane`.
      trimesh's own cuts each face apart and merges the cut points by a
      tolerance, which folds a pinch point's copies into one (a mesh that is
      not watertight by index, split at texture seams, keeps trimesh's step).
    * with ``default=True``, ``trimesh.path.Path2D.extrude``: the same
      lazy primitives, of class :class:`Extrusion`, whose mesh is ours whenever
      it is built, also after the registration ends (trimesh's own, built
      after the block, would be trimesh's default engine's).

    ``engine=`` and the keywords of :func:`cdt_plugin.triangulate` or
    ``triangle_args`` go along (``slice_plane`` passes only the engine). With
    ``default=True`` this engine is also the one when none is named, which
    reaches the callers that pass no engine: ``Path2D.extrude``, the ``Extrusion``
    primitive, ``revolve(cap=True)``. Other engine names (``"earcut"``,
    ``"manifold"``, ``"triangle"``) run trimesh's own functions, untouched.
    Engine names are case-insensitive (``"CDT_Plugin"``, ``"Earcut"``). With this
    engine, an empty polygon raises :class:`cdt_plugin.NoPolygonsError`, and a
    keyword that is neither :func:`cdt_plugin.triangulate`'s nor the ``Trimesh``
    constructor's (which trimesh's ``extrude_polygon`` passes on too) a
    :class:`cdt_plugin.CDTError` naming it.

    Calling it again only updates ``default`` (nothing is wrapped twice);
    :func:`unregister` puts every replaced attribute back, and :func:`registered`
    does both around a ``with`` block.

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
        for module, name in [*_HOOKS, *_DEFAULT_HOOKS]:
            _hooked["originals"][name] = getattr(module, name)
        for (module, name), hook in _HOOKS.items():
            setattr(module, name, hook)
    for (module, name), hook in _DEFAULT_HOOKS.items():
        setattr(module, name, hook if default else _original(name))
    _hooked["default"] = default


def unregister() -> None:
    """Put back every attribute of trimesh that :func:`register` replaced (the
    very objects it found); does nothing if the hooks are not registered.

    >>> import trimesh, cdt_plugin.adapters.trimesh as ct
    >>> original = trimesh.creation.extrude_polygon, trimesh.path.Path2D.extrude
    >>> ct.register(default=True); ct.unregister()
    >>> (trimesh.creation.extrude_polygon, trimesh.path.Path2D.extrude) == original
    True
    """
    if is_registered():
        for module, name in [*_HOOKS, *_DEFAULT_HOOKS]:
            setattr(module, name, _original(name))
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
