"""Plots rendered to PNG with the Agg backend and read back pixel by pixel:
triangles filled, holes left empty, segments in bold, the worst triangles
highlighted with their circumcircles, the angle histogram with the ``against``
triangulation overlaid."""
from __future__ import annotations

import doctest

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.tri  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.colors import to_rgb  # noqa: E402
from matplotlib.patches import Circle, Rectangle, StepPatch  # noqa: E402

import cdt_plugin  # noqa: E402
import cdt_plugin.plot as cplot  # noqa: E402
from cdt_plugin.report import triangle_quality  # noqa: E402
from checker import assert_valid  # noqa: E402

SQUARE_WITH_HOLE = ([[0, 0], [4, 0], [4, 4], [0, 4], [1, 1], [3, 1], [3, 3], [1, 3]],
                    [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4]])
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_docstring_examples():
    result = doctest.testmod(cplot)
    assert result.attempted >= 5 and result.failed == 0


def _render(fig, path, dpi=100):
    fig.savefig(path, dpi=dpi)
    assert path.read_bytes()[:8] == PNG_SIGNATURE
    return matplotlib.image.imread(path)[..., :3]


def _pixel(img, ax, fig, xy, dpi=100):
    """RGB of the rendered image at data point ``xy`` of ``ax``."""
    px, py = ax.transData.transform(xy)
    height = img.shape[0]
    return img[int(round(height - py)), int(round(px))]


def test_plot_fills_triangles_leaves_holes_empty_and_draws_segments(tmp_path):
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE)
    fig, ax = plt.subplots(figsize=(5, 5))
    assert tri.plot(ax, worst=0) is ax
    img = _render(fig, tmp_path / "mesh.png")
    assert img.shape == (500, 500, 3)
    assert np.allclose(_pixel(img, ax, fig, (2.0, 2.0)), 1.0)               # the hole: white
    face = _pixel(img, ax, fig, (0.45, 2.2))                                # inside the domain
    assert np.allclose(face, to_rgb(cplot.FACE), atol=0.02)
    assert np.allclose(_pixel(img, ax, fig, (4.0, 2.2)), to_rgb(cplot.SEGMENT), atol=0.1)
    # bold: the segment is several pixels wide, a triangle edge about one
    col = int(round(ax.transData.transform((4.0, 2.2))[0]))
    row = img.shape[0] - int(round(ax.transData.transform((4.0, 2.2))[1]))
    dark = (img[row, col - 6: col + 7].sum(axis=1) < 0.5).sum()
    assert dark >= 3
    plt.close(fig)


def test_plot_highlights_the_worst_triangles_with_circumcircles(tmp_path):
    # a fan with one sliver: it must be the highlighted one
    V = [[0, 0], [10, 0], [10, 10], [0, 10], [10, 0.4]]
    tri = cdt_plugin.triangulate(V, [[0, 1], [1, 4], [4, 2], [2, 3], [3, 0]])
    q = triangle_quality(tri.vertices, tri.triangles)
    worst = int(np.argmin(q["angles"].min(axis=1)))
    fig, ax = plt.subplots(figsize=(5, 5))
    cplot.plot(tri, ax, worst=1)
    circles = [p for p in ax.patches if isinstance(p, Circle)]
    assert len(circles) == 1
    assert circles[0].radius == pytest.approx(q["circumradius"][worst])
    corners = tri.vertices[tri.triangles[worst]]
    for corner in corners:                      # the circle passes through the 3 corners
        assert np.hypot(*(corner - circles[0].center)) == pytest.approx(circles[0].radius)
    polys = [c for c in ax.collections if isinstance(c, PolyCollection)]
    assert len(polys) == 2 and len(polys[1].get_paths()) == 1
    assert np.allclose(polys[1].get_paths()[0].vertices[:3], corners)
    img = _render(fig, tmp_path / "worst.png")
    centroid = corners.mean(axis=0)
    assert np.allclose(_pixel(img, ax, fig, centroid), to_rgb(cplot.WORST), atol=0.15)
    plt.close(fig)


def test_plot_without_segments_and_new_axes():
    tri = cdt_plugin.delaunay(np.random.default_rng(1).uniform(0, 1, (50, 2)))
    ax = tri.plot(worst=2, circumcircles=False, title="points")
    lines = [c for c in ax.collections if isinstance(c, LineCollection) and not isinstance(c, PolyCollection)]
    assert len(lines) == 1 and len(lines[0].get_segments()) == 0
    assert not [p for p in ax.patches if isinstance(p, Circle)]
    assert ax.get_title() == "points" and ax.get_aspect() == 1.0
    plt.close(ax.figure)


def test_histogram_with_against_overlay(tmp_path):
    pytest.importorskip("mapbox_earcut")
    from cdt_plugin.report import earcut
    t = np.linspace(0, 2 * np.pi, 30, endpoint=False)
    gi = {"type": "Polygon", "coordinates": [np.column_stack([3 * np.cos(t), np.sin(t)]).tolist()]}
    tri = cdt_plugin.triangulate(gi)
    rep = tri.report(against=earcut(gi), against_name="earcut")
    ax = cplot.histogram(tri, against=earcut(gi), against_name="earcut")
    heights = [p.get_height() for p in ax.patches if isinstance(p, Rectangle)]
    assert heights == rep.angle_counts.tolist()
    stairs = [p for p in ax.patches if isinstance(p, StepPatch)]
    assert len(stairs) == 1
    assert stairs[0].get_data().values.tolist() == rep.against.angle_counts.tolist()
    assert {t.get_text() for t in ax.get_legend().get_texts()} == {"cdt_plugin", "earcut"}
    # the same from a Report, and from bare arrays
    assert [p.get_height() for p in cplot.histogram(rep).patches if isinstance(p, Rectangle)] == heights
    assert sum(p.get_height() for p in cplot.histogram((tri.vertices, tri.triangles)).patches) == 3 * 28
    plt.close("all")


def test_save_writes_both_panels(tmp_path):
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE)
    path = tmp_path / "out.png"
    cplot.save(tri, path, dpi=50, size=(8.0, 4.0))
    img = matplotlib.image.imread(path)
    assert path.read_bytes()[:8] == PNG_SIGNATURE
    assert img.shape[:2] == (200, 400)
    fig = cplot.figure(tri)
    assert [ax.get_title() for ax in fig.axes] == ["cdt_plugin: 8 triangles", "angle histogram"]
    plt.close(fig)
    fan = (tri.vertices, [[0, 1, 5], [0, 5, 4], [1, 2, 5], [2, 6, 5], [2, 3, 6], [3, 7, 6],
                          [3, 0, 7], [0, 4, 7]])
    fig = cplot.figure(tri, against=fan, against_name="fan")
    ours, theirs, hist = fig.axes
    assert theirs.get_title() == "fan: 8 triangles" and hist.get_title() == "angle histogram"
    drawn = [c for c in theirs.collections if isinstance(c, PolyCollection)][0]
    assert len(drawn.get_paths()) == 8
    assert theirs.get_xlim() == ours.get_xlim() and theirs.get_ylim() == ours.get_ylim()
    plt.close(fig)


# ------------------------------------------------------------- to_matplotlib
def test_to_matplotlib_is_the_same_triangulation(tmp_path):
    tri = cdt_plugin.triangulate(*SQUARE_WITH_HOLE)
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments")
    mtri = tri.to_matplotlib()
    assert isinstance(mtri, matplotlib.tri.Triangulation)
    assert np.array_equal(mtri.x, tri.vertices[:, 0]) and np.array_equal(mtri.y, tri.vertices[:, 1])
    assert np.array_equal(mtri.triangles, tri.triangles)
    assert_valid(np.column_stack([mtri.x, mtri.y]), mtri.triangles, segments=tri.segments, domain="segments")
    # matplotlib's neighbour j lies across edge (j, j+1): ours across the edge opposite vertex j+2
    assert np.array_equal(mtri.neighbors, tri.neighbors[:, [2, 0, 1]])
    # matplotlib's own point location and interpolation on it: the hole is no triangle,
    # and a linear field is reproduced exactly inside
    finder = mtri.get_trifinder()
    assert finder(2.0, 2.0) == -1 and finder(0.5, 2.0) >= 0
    field = matplotlib.tri.LinearTriInterpolator(mtri, mtri.x + 2 * mtri.y)
    assert float(field(0.5, 2.0)) == pytest.approx(4.5, rel=1e-12)
    assert np.ma.is_masked(field(2.0, 2.0))
    # and it draws: triangles filled, the hole left white
    fig, ax = plt.subplots(figsize=(4, 4))
    ax.tripcolor(mtri, facecolors=np.ones(len(tri.triangles)), cmap="Greys", vmin=0, vmax=1)
    ax.set_xlim(-0.5, 4.5)
    ax.set_ylim(-0.5, 4.5)
    img = _render(fig, tmp_path / "tripcolor.png")
    assert np.allclose(_pixel(img, ax, fig, (2.0, 2.0)), 1.0)
    assert _pixel(img, ax, fig, (0.5, 2.0)).max() < 0.2
    plt.close(fig)


def test_to_matplotlib_copies_coordinates():
    tri = cdt_plugin.triangulate([[0, 0], [2, 0], [2, 1], [0, 1], [5, 5]], [[0, 1], [1, 2], [2, 3], [3, 0]])
    assert_valid(tri.vertices, tri.triangles, segments=tri.segments, domain="segments",
                 require_all_vertices=False)
    mtri = tri.to_matplotlib()
    assert len(mtri.x) == 5                              # the outside vertex stays: indices agree
    mtri.x[0] = 99.0
    assert tri.vertices[0, 0] == 0.0


def test_to_matplotlib_without_triangles_is_an_error():
    tri = cdt_plugin.triangulate([[0, 0], [1, 1], [2, 2]])      # all collinear: edges only
    assert len(tri.triangles) == 0 and len(tri.edges) == 2
    with pytest.raises(cdt_plugin.CDTError, match="has no triangles"):
        tri.to_matplotlib()
