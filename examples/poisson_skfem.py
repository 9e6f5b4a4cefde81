"""A Poisson problem solved with scikit-fem on a meshed shapely polygon with holes.

    python examples/poisson_skfem.py

The domain is a square with two holes (a 32-gon and a small square); the exterior
boundary is marked 1 and the holes 2 (``markers=`` of the shapely adapter), so that
:meth:`cdt_plugin.Triangulation.to_skfem` names them as scikit-fem boundaries.
The solution is manufactured, ``u = exp(x) sin(pi y)``: ``-laplace(u) = (pi**2 - 1) u``
inside, ``u`` given on both boundaries (Dirichlet values by boundary name). Linear
elements on meshes refined by ``max_area`` give an L2 error that falls with the square
of the mesh size h ~ N**-1/2 (N nodes): the printed rate, the least-squares slope of
log(error) against log(h) over the table, is near 2 (the rates between two meshes
scatter around it, as Delaunay refinement does not split every triangle alike).
Needs shapely and scikit-fem.
"""
from __future__ import annotations

import math

import numpy as np
import shapely
from skfem import Basis, BilinearForm, ElementTriP1, Functional, LinearForm, condense, solve
from skfem.helpers import dot, grad

from cdt_plugin.adapters.shapely import triangulate

#: The areas of the meshes of the convergence table (each a quarter of the one before).
MAX_AREAS = (0.004, 0.001, 0.00025, 0.0000625)


def exact(x, y):
    return np.exp(x) * np.sin(np.pi * y)


def domain() -> shapely.Polygon:
    """The unit square with a round hole (32 sides) and a square hole."""
    t = np.linspace(0.0, 2.0 * np.pi, 32, endpoint=False)
    circle = np.column_stack([0.3 + 0.12 * np.cos(t), 0.6 + 0.12 * np.sin(t)])
    square = [(0.6, 0.2), (0.8, 0.2), (0.8, 0.4), (0.6, 0.4)]
    return shapely.Polygon([(0, 0), (1, 0), (1, 1), (0, 1)], [circle, square])


@BilinearForm
def laplace(u, v, w):
    return dot(grad(u), grad(v))


@LinearForm
def load(v, w):
    x, y = w.x
    return (np.pi ** 2 - 1.0) * exact(x, y) * v


@Functional
def squared_error(w):
    x, y = w.x
    return (w["uh"] - exact(x, y)) ** 2


def solve_poisson(max_area: float) -> tuple[int, float]:
    """Mesh the domain with triangles of area at most ``max_area`` (angles of 30
    degrees at least), solve with linear elements; the node count and the L2 error."""
    tri = triangulate(domain(), markers={"exterior": 1, "holes": 2}, max_area=max_area,
                      min_angle=30)
    mesh = tri.to_skfem(boundaries={"exterior": 1, "holes": 2})
    basis = Basis(mesh, ElementTriP1(), intorder=4)
    A, b = laplace.assemble(basis), load.assemble(basis)
    fixed = basis.get_dofs(["exterior", "holes"])        # Dirichlet: u on both boundaries
    x, y = basis.doflocs
    uh = solve(*condense(A, b, x=exact(x, y), D=fixed))
    return int(mesh.nvertices), math.sqrt(squared_error.assemble(basis, uh=basis.interpolate(uh)))


def convergence(max_areas=MAX_AREAS) -> tuple[list[tuple[float, int, float]], float]:
    """``(max_area, nodes, L2 error)`` per mesh, and the observed order: the
    least-squares slope of log(error) against log(h), h = nodes**-1/2."""
    rows = [(area, *solve_poisson(area)) for area in max_areas]
    nodes, errors = np.array([r[1] for r in rows], float), np.array([r[2] for r in rows])
    return rows, float(-2 * np.polyfit(np.log(nodes), np.log(errors), 1)[0])


def main() -> None:
    rows, rate = convergence()
    print(f"{'max_area':>10} {'nodes':>7} {'L2 error':>10}")
    for area, nodes, error in rows:
        print(f"{area:>10.6g} {nodes:>7} {error:>10.3e}")
    print(f"observed order {rate:.2f} (linear elements: 2)")


if __name__ == "__main__":
    main()
