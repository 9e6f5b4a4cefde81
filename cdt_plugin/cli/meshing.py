"""Meshing the features of a per-feature input (one call each, on threads) and
joining the meshes into one."""
from __future__ import annotations

import argparse
import inspect
from typing import Any, Sequence

import numpy as np

from .. import size_near, triangulate
from ..errors import CDTError
from ..fields import as_size_field
from ..nearness import SmallestSize
from ..options import MeshOptions
from ..parallel import map_ordered, resolve_workers
from ..triangulation import Triangulation
from .formats import import_for
from .readers import Feature, read_geometries
from .terminal import CLIError, progress_bar

MANY_FEATURES = 16        # features per thread worth starting one for


def triangulate_options(args: argparse.Namespace) -> dict[str, Any]:
    """Keyword options for triangulate, checked (:class:`~cdt_plugin.options.MeshOptions`);
    refinement options only when given."""
    options: dict[str, Any] = {"intersections": args.intersections}
    asked = {k: v for k, v in (("min_angle", args.min_angle), ("max_area", args.max_area))
             if v is not None}
    if asked:
        accepted = inspect.signature(triangulate).parameters
        missing = [k for k in asked if k not in accepted]
        if missing:
            raise CLIError("refinement options need a cdt_plugin whose triangulate() accepts "
                           f"{', '.join(missing)} (quality refinement is not in this version)")
        options.update(asked)
    if getattr(args, "merge_distance", None) is not None:     # (cdt-plugin mesh only)
        options["merge_distance"] = args.merge_distance
    MeshOptions.check(**options)      # every option checked before any input is read
    if getattr(args, "size", None) is not None:
        options["size"] = as_size_field(args.size)
    if getattr(args, "smooth", None) is not None:     # (cdt-plugin mesh only; a choice of the parser)
        options["smooth"] = args.smooth
    return options


def near_layers(args: argparse.Namespace) -> list[tuple[Any, float, float, float]]:
    """``(geometries, min, max, distance)`` of every ``--size-near``, its file read
    (:func:`~cdt_plugin.cli.readers.read_geometries`)."""
    return [(read_geometries(spec.path, spec.layer, "--size-near"), spec.size_min,
             spec.size_max, spec.distance) for spec in getattr(args, "size_near", None) or ()]


def with_sizes_near(options: dict[str, Any], args: argparse.Namespace) -> dict[str, Any]:
    """``options`` whose ``size`` also holds the ``--size-near`` fields (the smallest
    of all at every point), in the files' coordinates as they are."""
    fields: list[Any] = [size_near(*near[:3], distance=near[3]) for near in near_layers(args)]
    if not fields:
        return options
    if "size" in options:
        fields.insert(0, options["size"])
    return {**options, "size": fields[0] if len(fields) == 1 else SmallestSize(fields)}


def triangulate_features(features: Sequence[Feature], options: dict[str, Any], *,
                         repair: bool = False, progress: bool | None = None,
                         workers: int | None = None,
                         errors: str = "raise") -> list[Triangulation | CLIError]:
    """Triangulate each feature (a progress bar over many features when ``progress``
    is True, or None and stderr is a terminal), on ``workers`` threads (default:
    every core when there are many features). Errors name the feature; with
    ``errors="skip"`` a feature that fails has its ``CLIError`` in its place in the
    list instead of stopping the others."""
    show = progress if len(features) > 1 else False
    with progress_bar(show, "triangulating", "feature", len(features)) as step:
        return map_ordered(lambda feature: _triangulate_feature(feature, features, options, repair,
                                                                errors),
                           features, resolve_workers(workers, len(features) // MANY_FEATURES),
                           done=None if step is None else lambda *_: step(1))


def _triangulate_feature(feature: Feature, features: Sequence[Feature], options: dict[str, Any],
                         repair: bool, errors: str = "raise") -> Triangulation | CLIError:
    # Geometry goes through the shapely adapter (GEOS validity check, optional
    # repair) unless crossings are to be split: the engine then meshes the rings
    # as they are, by even-odd depth where they cross. With merge_distance the
    # engine checks the rings too, after merging (GEOS would refuse the
    # near-duplicate points that are to be merged).
    validate = repair or (options.get("intersections") != "split"
                          and not options.get("merge_distance"))
    try:      # (a feature that is no geometry fails alone too: skipped and named with "skip")
        geometry = _shapely_geometry(feature) if feature.geometry is not None and validate else None
    except CLIError as exc:
        if errors == "skip":
            return exc
        raise
    try:
        if feature.geometry is not None and validate:
            from ..adapters.shapely import triangulate as triangulate_geometry
            return triangulate_geometry(geometry, repair=repair, **options)
        if feature.geometry is not None:
            return triangulate(feature.geometry, **options)
        return triangulate(**feature.arrays, **options)
    except CDTError as exc:
        message = str(exc).replace(
            "pass repair=True to repair it with shapely.make_valid",
            "pass --repair to repair it with shapely.make_valid, or --intersections split "
            "to mesh its rings as they are")
        if errors == "skip":
            return CLIError(f"{feature.name}: {message}")
        raise CLIError(f"{feature.name}: {message}" if len(features) > 1 else message) from None


def _shapely_geometry(feature: Feature) -> Any:
    """The feature's geometry as a shapely geometry (GeoJSON mappings are converted)."""
    if not isinstance(feature.geometry, dict):
        return feature.geometry
    shapely = import_for("shapely", "validating GeoJSON polygons")
    try:
        return shapely.geometry.shape(feature.geometry)
    except (ValueError, TypeError, KeyError, AttributeError, IndexError,
            shapely.errors.ShapelyError) as exc:
        raise CLIError(f"{feature.name}: not a valid GeoJSON geometry ({exc}); "
                       "--intersections split meshes its rings as they are") from None


def concatenate(tris: Sequence[Triangulation]) -> Triangulation:
    """One Triangulation holding several (vertices, triangles, segments offset;
    ``regions`` = the index of the triangulation each triangle came from; numeric
    ``stats`` summed). One input is returned as it is.

    >>> import cdt_plugin
    >>> a = cdt_plugin.triangulate([[0, 0], [1, 0], [0, 1]], [[0, 1], [1, 2], [2, 0]])
    >>> both = concatenate([a, a])
    >>> both.triangles.tolist(), both.regions.tolist(), both.is_delaunay()
    ([[0, 1, 2], [3, 4, 5]], [0, 1], True)
    """
    if len(tris) == 1:
        return tris[0]
    voff = np.cumsum([0] + [len(t.vertices) for t in tris])
    toff = np.cumsum([0] + [len(t.triangles) for t in tris])
    soff = np.cumsum([0] + [t.stats.get("input_segments", 0) for t in tris])
    shift = lambda a, off: np.where(a >= 0, a + off, -1)  # noqa: E731
    out = Triangulation(
        np.vstack([t.vertices for t in tris]),
        np.vstack([t.triangles + o for t, o in zip(tris, voff)]).astype(np.int64),
        np.vstack([shift(t.neighbors, o) for t, o in zip(tris, toff)]).astype(np.int64),
        np.concatenate([shift(t.vertex_map, o) for t, o in zip(tris, voff)]),
        _sum_stats([t.stats for t in tris]))
    out.constrained = np.vstack([t.constrained for t in tris])
    out.segments = np.vstack([t.segments + o for t, o in zip(tris, voff)]).astype(np.int64)
    out.segment_ids = np.concatenate([shift(t.segment_ids, o) for t, o in zip(tris, soff)])
    out.steiner = np.concatenate([t.steiner + o for t, o in zip(tris, voff)]).astype(np.int64)
    out.regions = np.repeat(np.arange(len(tris)), [len(t.triangles) for t in tris])
    return out


def _sum_stats(stats: list[dict[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key in stats[0]:
        values = [s.get(key) for s in stats]
        if all(isinstance(v, bool) for v in values):
            out[key] = all(values)
        elif all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            out[key] = sum(values)
    return out
