"""The compiled kernels of cdt_plugin: private, no user-facing API.

Imports run one way, from the bottom up:

    predicates          exact orient2d / incircle / lifted test (Shewchuk's expansions)
    scaling             every finite double into the predicates' range by a power of two
    kernel              the tests on mesh vertices: ghosts, symbolic perturbation (Sec. 2.9)
    mesh                the flat half-edge store (topology only) and its growth
    status              every status code, named
    locate, flips, insertion, divide     the operations on the store
    construct           the Delaunay triangulation of the mesh vertices (three ways)
    options             the route's options as the kernels read them (RouteOptions)
    segments, regions, refine, rings, certify, output
    pipeline            the constrained Delaunay route, once (cdt_route), and the batch
                        loop over it (mesh_geometries)

The public front ends (:mod:`cdt_plugin.cdt`, :mod:`cdt_plugin.delaunay`,
:mod:`cdt_plugin.batch`) validate, make one compiled call and wrap the result.
"""
