"""Every status code of the compiled core, named, in one place.

Compiled code returns codes; the Python layer turns them into exceptions
(:mod:`cdt_plugin.errors`) or grows arrays and calls again. Each group below is
the vocabulary of one kind of call; values repeat across groups, never within one.
"""

# point location (locate.locate) and vertex insertion (insertion.insert_vertex)
INSIDE = 0            # strictly inside the triangle of the returned half-edge
ON_EDGE = 1           # strictly inside the edge of the returned half-edge
ON_VERTEX = 2         # at the origin vertex of the returned half-edge
LOCATE_FAILED = -1    # the walk found no triangle (never on a valid mesh)
SUBMERGED = -2        # insert_vertex: the weighted point is submerged, not inserted

# whole insertion loops (insertion.insert_vertices, delaunay routes)
OK = 0
LOCATION_FAILED = 1

# one segment task (segments.insert_one)
DONE = 0              # the segment (or its first piece) is an edge now
SPLIT_AT = 1          # a vertex lies on the segment: pieces queued
CROSSING = 2          # the segment crosses a constrained edge (``info`` = half-edge)
OVERLAP = 3           # the edge is already a piece of another segment
ON_INPUT = 4          # a vertex on the input segment, off this rounded piece: pieces queued
TASK_LOST = -1        # internal failure (a vertex could not be found)
BUFFERS_TOO_SMALL = -2  # the walk buffers are too small: make them larger, try again

# the segment task loop (segments.insert_segments)
ALL_DONE = 0
STOP_CROSSING = 1     # intersections="raise": info = (segment, other segment)
STOP_OVERLAP = 2      # intersections="raise": info = (segment, other segment)
NEED_VERTEX_ROOM = 3  # a Steiner point needs room: grow and call again
NEED_EDGE_ROOM = 4    # the walk buffers are too small: grow and call again
STOP_LIMIT = 5        # too many Steiner points: refuse rather than loop
LOST = 6              # internal failure (a vertex could not be found)

# refinement (refine.refine_loop / refine_run)
FINISHED = 0
NEED_ROOM = 1         # grow the arrays and call again
LIMIT = 2             # the Steiner budget is spent
HEAP_FULL = 3         # grow the bad-triangle queue and call again
PIECES_FULL = 4       # grow the piece stack and call again
WALK_FAILED = -1      # refine.walk_to: no path to the point
WALK_BLOCKED = -3     # refine.walk_to: a segment is in the way

# one constrained Delaunay route (pipeline.cdt_route)
ROUTE_OK = 0
ROUTE_COLLINEAR = 1        # all vertices on one line: no triangles (handled in Python)
ROUTE_CROSSING = 2         # info = (segment id, other segment id) 1-based
ROUTE_OVERLAP = 3          # info = (segment id, other segment id) 1-based
ROUTE_STEINER_LIMIT = 4    # intersections: info = (segment id, other segment id, limit, points needed or 0)
ROUTE_HOLE_OUTSIDE = 5     # info = (ring,) a hole ring entered from outside its shell
ROUTE_REFINE_LIMIT = 6     # refinement ran out of Steiner points (the mesh is complete)
ROUTE_INTERNAL = 7         # info = (stage, code)
ROUTE_RANGE = 8            # info = (row of the finest bit, row of the largest magnitude): no shift fits
ROUTE_POLYGONS_OVERLAP = 9  # info = (polygon, other polygon, input vertex, input vertex) of an edge
ROUTE_UNRESOLVED = 10     # split: info = (segment id, bad pieces, x bits, y bits) pieces out of order
ROUTE_NEEDS_SNAP = 11     # split: segments cross; call again with .snap.snap_route's crossings
