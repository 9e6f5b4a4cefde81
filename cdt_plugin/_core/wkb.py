"""Well-known binary (WKB) of triangles, compiled: one Polygon record per
triangle, written in one pass, for GEOS to read a whole GeometryCollection of
them in one call (the shapely adapter's output of a mesh)."""
from __future__ import annotations

import numpy as np

from .jit import entry


@entry
def triangle_polygon_records(coordinate_bytes, triangles, corners, header):
    """The WKB records of one Polygon per row of ``triangles`` (k, 3): each
    ``header`` (its bytes: byte order, type, one ring, four points) followed by
    the closed ring of the triangle's corners ``corners`` (4 positions into the
    row, the last repeating the first), each corner the row of
    ``coordinate_bytes`` (n, 8 * dimension) that holds its vertex's coordinates
    as they lie in memory (little-endian float64). ``k * (len(header) + 4 *
    coordinate_bytes.shape[1])`` bytes, coordinates bit for bit."""
    k = triangles.shape[0]
    h, w = header.shape[0], coordinate_bytes.shape[1]
    out = np.empty(k * (h + 4 * w), np.uint8)
    p = 0
    for t in range(k):
        for j in range(h):
            out[p + j] = header[j]
        p += h
        for c in range(4):
            v = triangles[t, corners[c]]
            for j in range(w):
                out[p + j] = coordinate_bytes[v, j]
            p += w
    return out
