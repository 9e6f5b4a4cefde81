"""Meshing a dask-geopandas GeoDataFrame partition by partition
(:func:`triangulate_dask`), on any Dask cluster."""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from cdt_plugin.batch import check_batch_options
from cdt_plugin.parallel import available_cores, check_count
from cdt_plugin.adapters.geo.errors import is_geographic, warn_geographic
from cdt_plugin.adapters.geo.meshing import mesh_layer
from cdt_plugin.adapters.geo.projection import ProjectLike, centred, layer_extent, target_crs
from cdt_plugin.adapters.shapely import Repair

if TYPE_CHECKING:
    import dask_geopandas


def triangulate_dask(dask_geodataframe: dask_geopandas.GeoDataFrame, *, project: ProjectLike = None,
                     repair: Repair = False, errors: str = "raise", npartitions: int | None = None,
                     **options: Any) -> dask_geopandas.GeoDataFrame:
    """:func:`triangulate` for a dask-geopandas GeoDataFrame: every partition is
    meshed where it lives (``map_partitions``), on whatever Dask scheduler is
    active (a ``dask.distributed.Client`` connected to a cluster, or the local one).

    Returns a lazy dask-geopandas GeoDataFrame of triangles with the columns of
    ``triangulate(...)`` (``position`` is the row number within the partition;
    the index restarts in every partition). ``project="utm"`` / ``"aeqd"`` is
    resolved once, for the whole frame (from the bounds of every partition: one
    pass over the data; pass a CRS to avoid it), so every partition is meshed in the same
    CRS and the result equals the single-machine one. ``errors="skip"`` leaves the
    failing features without triangles (no warning from the workers). Options are
    those of :func:`triangulate` (``progress``: use Dask's own diagnostics;
    ``workers`` defaults to 1 here: Dask runs the partitions in parallel).

    ``npartitions``: the partitions to mesh (the frame is repartitioned to that
    many first). By default the frame's own, split evenly when there are fewer
    than two per worker that will run them (the threads of the connected
    ``dask.distributed`` client, else this machine's cores), so that a frame
    made in one piece (``from_geopandas(layer, npartitions=1)``) still uses
    every worker; more partitions than that are kept as they are.

    >>> import dask_geopandas, geopandas, shapely
    >>> layer = geopandas.GeoDataFrame({"v": [1, 2]}, geometry=[shapely.box(0, 0, 1, 1),
    ...                                shapely.box(2, 0, 3, 1)])
    >>> tris = triangulate_dask(dask_geopandas.from_geopandas(layer, npartitions=2))
    >>> tris.compute(scheduler="sync")["v"].tolist()
    [1, 1, 2, 2]
    """
    options.pop("progress", None)
    options.setdefault("workers", 1)    # Dask runs the partitions in parallel
    check_batch_options(errors=errors, **options)
    count = check_count(npartitions, "npartitions")
    wanted = count if count is not None else max(dask_geodataframe.npartitions, 2 * _dask_workers())
    if wanted != dask_geodataframe.npartitions:
        dask_geodataframe = dask_geodataframe.repartition(npartitions=wanted)
    crs = dask_geodataframe.crs
    if centred(project):
        project = target_crs(project, crs, _dask_extent(dask_geodataframe))
    elif project is not None:
        project = target_crs(project, crs, None)
    elif is_geographic(crs):
        warn_geographic(crs)
    kwargs = dict(project=project, repair=repair, errors=errors, **options)
    meta = _triangulate_partition(dask_geodataframe._meta, **kwargs)
    return dask_geodataframe.map_partitions(_triangulate_partition, meta=meta, **kwargs)


def _dask_workers() -> int:
    """The threads that will run a Dask computation: the connected distributed
    client's (all its workers'), else this machine's cores (the threaded
    scheduler)."""
    try:
        from distributed import get_client
        return max(1, sum(get_client().nthreads().values()))
    except (ImportError, ValueError):       # no distributed, or no client connected
        return available_cores()


def _dask_extent(dask_geodataframe) -> np.ndarray:
    """:func:`layer_extent` of a dask GeoDataFrame, partition by partition (one pass)."""
    import dask

    geographic = is_geographic(dask_geodataframe.crs)
    parts = [dask.delayed(_frame_extent)(p, geographic) for p in dask_geodataframe.to_delayed()]
    rows = [r for r in dask.compute(*parts) if len(r)]
    return np.concatenate(rows) if rows else np.empty((0, 4))


def _frame_extent(frame, geographic: bool) -> np.ndarray:
    return layer_extent(np.asarray(frame.geometry.array, dtype=object), geographic)


def _triangulate_partition(frame, *, project=None, repair=False, errors="raise", **options):
    """One partition of :func:`triangulate_dask` (also its meta, from an empty frame)."""
    mesh = mesh_layer(frame, project=project, repair=repair, errors=errors, progress=False,
                 options=options, require_polygons=False, warn=False)
    return mesh.to_geodataframe()
