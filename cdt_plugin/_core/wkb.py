"""Well-known binary (WKB) of triangles, compiled: one Polygon record per
triangle, written in one pass, for GEOS to read a whole GeometryCollection of
them in one call (the shapely adapter's output of a mesh)."""
from __future__ import annotations

import struct
import sys

import numpy as np

from .jit import entry, kernel

#: The bytes of a Polygon record's header: byte order, type, rings, points
POLYGON_HEADER_BYTES = 13
#: WKB's name of this machine's byte order (1: little-endian): the coordinates go as they lie in memory
BYTE_ORDER = 1 if sys.byteorder == "little" else 0


def header(*values: int) -> bytes:
    """A WKB header: the byte order, then 32-bit integers in that order."""
    return struct.pack("=B" + "I" * len(values), BYTE_ORDER, *values)


#: The header of a triangle's Polygon record: type, one ring, four points (ISO WKB: Z is +1000)
POLYGON_HEADER_2D = np.frombuffer(header(3, 1, 4), np.uint8)
POLYGON_HEADER_3D = np.frombuffer(header(1003, 1, 4), np.uint8)
#: The header of a GeometryCollection (then the number of members, then the members)
COLLECTION_HEADER_2D = np.frombuffer(header(7), np.uint8)
COLLECTION_HEADER_3D = np.frombuffer(header(1007), np.uint8)
#: The corners of a triangle's closed ring, clockwise (as GEOS gives them) and counter-clockwise
CW_CORNERS = np.array([0, 2, 1, 0], np.int64)
CCW_CORNERS = np.array([0, 1, 2, 0], np.int64)


@entry
def triangle_polygon_records(coordinate_bytes, triangles, corners, header):
    """The WKB records of one Polygon per row of ``triangles`` (k, 3): each
    ``header`` (its 13 bytes: byte order, type, one ring, four points)
    followed by the closed ring of the triangle's corners ``corners`` (4
    positions into the row, the last repeating the first), each corner the row
    of ``coordinate_bytes`` (n, 8 * dimension) that holds its vertex's
    coordinates as they lie in memory. ``k * (13 + 32 * dimension)`` bytes,
    coordinates bit for bit."""
    size = POLYGON_HEADER_BYTES + 4 * coordinate_bytes.shape[1]
    out = np.empty(triangles.shape[0] * size, np.uint8)
    write_polygon_records(out, np.int64(0), coordinate_bytes, triangles, corners, header)
    return out


@kernel
def write_polygon_records(out, at, coordinate_bytes, triangles, corners, header):
    """:func:`triangle_polygon_records` written into ``out`` from byte ``at``.
    (The loops run over fixed counts of bytes, 13 and 8, which the compiler
    unrolls: twice as fast as over the row's length.)"""
    dimension = coordinate_bytes.shape[1] // 8
    p = at
    for t in range(triangles.shape[0]):
        for j in range(POLYGON_HEADER_BYTES):
            out[p + j] = header[j]
        p += POLYGON_HEADER_BYTES
        for c in range(4):
            v = triangles[t, corners[c]]
            for i in range(dimension):
                for j in range(8):
                    out[p + j] = coordinate_bytes[v, 8 * i + j]
                p += 8
