"""``gdf.cdt.triangulate(...)``: :func:`triangulate` as a method of a
GeoDataFrame or GeoSeries (a pandas accessor, registered on import)."""
from __future__ import annotations

import sys
from typing import TYPE_CHECKING, Any

from cdt_plugin.adapters.geo.errors import NotGeographicError
from cdt_plugin.adapters.geo.meshing import triangulate

if TYPE_CHECKING:
    pass


class CDTAccessor:
    """``gdf.cdt`` / ``gs.cdt``: this module's meshing as a method of a GeoDataFrame
    or GeoSeries. Registered through pandas' extension API
    (``pandas.api.extensions.register_dataframe_accessor`` and
    ``register_series_accessor``) when this module is imported; geopandas has no
    registry of its own, and its classes subclass pandas', so they inherit it.
    On a pandas object that is not geographic (a DataFrame or Series of plain
    values), ``.cdt`` raises :class:`NotGeographicError`.

    >>> import geopandas, pandas, shapely
    >>> from cdt_plugin.adapters import geo           # registers .cdt
    >>> layer = geopandas.GeoDataFrame({"name": ["a", "b"]}, crs="EPSG:32633",
    ...     geometry=[shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 2)])
    >>> layer.cdt.triangulate()["name"].tolist()
    ['a', 'a', 'b', 'b']
    >>> tris = layer.geometry.cdt.triangulate(max_area=0.5)
    >>> len(tris), tris.crs.to_epsg()
    (6, 32633)
    >>> hasattr(pandas.DataFrame({"x": [1]}), "cdt")
    False
    """

    def __init__(self, obj: Any) -> None:
        self._obj = _geographic(obj)

    def triangulate(self, **options: Any) -> Any:
        """``triangulate(self)``: :func:`triangulate` of this GeoDataFrame or
        GeoSeries, with the same options (``output``, ``project``, ``repair``,
        ``errors``, ``progress``, ``workers``, ``min_angle``, ``max_area``, ...)
        and the same result."""
        return triangulate(self._obj, **options)


def _geographic(obj: Any) -> Any:
    """``obj`` when it is a GeoSeries or a GeoDataFrame with an active geometry
    column; else :class:`NotGeographicError` saying how to make one."""
    geopandas = sys.modules.get("geopandas")      # not imported: obj cannot be geographic
    if geopandas is not None and isinstance(obj, geopandas.GeoSeries):
        return obj
    if geopandas is not None and isinstance(obj, geopandas.GeoDataFrame):
        try:
            _ = obj.geometry              # raises without an active geometry column
        except AttributeError:
            raise NotGeographicError(
                ".cdt: the GeoDataFrame has no active geometry column (columns: "
                f"{list(obj.columns)}); set one with gdf.set_geometry(column)") from None
        return obj
    hint = ("geopandas.GeoDataFrame(frame, geometry=column)" if hasattr(obj, "columns") else
            "geopandas.GeoSeries(series)")
    raise NotGeographicError(f".cdt needs a GeoDataFrame or a GeoSeries, got a pandas "
                             f"{type(obj).__name__} with no geometry; make one with {hint}")


def _register_accessor() -> None:
    """``.cdt`` on every pandas DataFrame and Series (so on geopandas' subclasses)."""
    try:
        import pandas
    except ImportError:                 # no pandas, so no geopandas: nothing to hook into
        return
    pandas.api.extensions.register_dataframe_accessor("cdt")(CDTAccessor)
    pandas.api.extensions.register_series_accessor("cdt")(CDTAccessor)


_register_accessor()
