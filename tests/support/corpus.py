"""Loaders for every input in the shared corpus (``../shared/corpus`` beside the repo).

The corpus (see its README.md) holds four formats:

* ``triangle/``: Shewchuk's Triangle ``.node`` (point sets) and ``.poly`` (PSLGs with hole
  points and region lines), read with :mod:`cdt_plugin.io`;
* ``cdt/``: artem-ogre/CDT ``.txt`` inputs, a whitespace token stream ``nV nE``, nV
  coordinate pairs, nE 0-based edges (CRLF in some files, spaces in the names);
* ``earcut/``: mapbox/earcut fixtures, a JSON array of rings (ring 0 outer, later rings
  holes; closed or open; orientation not normalised);
* ``gis/``: Natural Earth GeoJSON FeatureCollections, one PLC per feature (all its
  polygons together), parsed with the :mod:`json` module only.

Every loader returns :class:`PLCInput` objects. Polygon inputs (earcut, GeoJSON) turn each
ring into a closed chain of segments over FRESH vertex indices (the closing duplicate point
dropped): a position shared by two rings is two vertices, exactly as the corpus statistics
count it (``stats.py``). A ring of k >= 2 points gives k vertices and k segments (k = 2:
the same segment twice, once each way); a 1-point ring (earcut ``steiner.json``) gives one
vertex and no segment; an empty ring is skipped. Nothing is merged or repaired here: the
defects are the point of the corpus.

The corpus is found at ``<repo>/../shared/corpus`` or at ``$CDT_CORPUS``.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Dict, Iterator, List, Optional

import numpy as np

from cdt_plugin import io as tio
from cdt_plugin.errors import FileFormatError

__all__ = ["PLCInput", "corpus_dir", "corpus_files", "load", "load_file", "load_triangle",
           "load_cdt_txt", "load_earcut_json", "load_geojson", "iter_point_sets",
           "iter_plcs", "read_stats_table"]

KINDS = ("triangle-node", "triangle-poly", "cdt", "earcut", "geojson")


@dataclass
class PLCInput:
    """One corpus input as a planar straight-line complex (vertices as given)."""
    name: str                       # "folder/file" (+ "#i feature name" for GeoJSON)
    vertices: np.ndarray            # (n, 2) float64, duplicates kept
    segments: np.ndarray            # (m, 2) int64, zero-based
    holes: np.ndarray               # (h, 2) float64 hole seed points (Triangle .poly only)
    rings: Optional[List[np.ndarray]]  # polygon inputs: vertex indices of each ring, else None
    kind: str                       # one of KINDS
    polygons: Optional[List[List[int]]] = None   # ring indices per polygon, shell first
    regions: Optional[np.ndarray] = None         # (r, 4) x, y, attribute, max_area (.poly)
    path: Optional[Path] = None
    properties: Dict = field(default_factory=dict)  # GeoJSON feature properties

    @property
    def hole_rings(self) -> int:
        """Number of interior rings (polygon inputs)."""
        if self.polygons is None:
            return 0
        return sum(len(p) - 1 for p in self.polygons)

    def __repr__(self) -> str:  # keep pytest ids and failure messages short
        return (f"PLCInput({self.name!r}, kind={self.kind}, V={len(self.vertices)}, "
                f"S={len(self.segments)}, holes={len(self.holes)}, "
                f"rings={None if self.rings is None else len(self.rings)})")


# ----------------------------------------------------------------------------------------
# locating files
# ----------------------------------------------------------------------------------------

def corpus_dir() -> Path:
    """The corpus folder: ``$CDT_CORPUS`` if set, else ``<repo>/../shared/corpus``."""
    env = os.environ.get("CDT_CORPUS")
    if env:
        return Path(env)
    return Path(__file__).resolve().parents[2].parent / "shared" / "corpus"


def corpus_files() -> List[Path]:
    """Every input file of the corpus, sorted by folder then name."""
    root = corpus_dir()
    out = []
    for sub, pats in (("triangle", ("*.node", "*.poly")), ("cdt", ("*.txt",)),
                      ("earcut", ("*.json",)), ("gis", ("*.geojson",))):
        for pat in pats:
            out.extend((root / sub).glob(pat))
    return sorted(out, key=lambda p: (p.parent.name, p.name))


def _rel(path: Path) -> str:
    return f"{path.parent.name}/{path.name}"


# ----------------------------------------------------------------------------------------
# loaders
# ----------------------------------------------------------------------------------------

def _empty_pts() -> np.ndarray:
    return np.zeros((0, 2), dtype=np.float64)


def _empty_segs() -> np.ndarray:
    return np.zeros((0, 2), dtype=np.int64)


def load_triangle(path) -> PLCInput:
    """A Triangle ``.node`` (point set) or ``.poly`` (PSLG with hole points) file."""
    path = Path(path)
    if path.suffix == ".node":
        nd = tio.read_node(path)
        return PLCInput(_rel(path), nd.vertices, _empty_segs(), _empty_pts(), None,
                        "triangle-node", path=path)
    pd = tio.read_poly(path)
    return PLCInput(_rel(path), pd.vertices, pd.segments, pd.holes, None, "triangle-poly",
                    regions=pd.regions, path=path)


def load_cdt_txt(path) -> PLCInput:
    """An artem-ogre/CDT input: tokens ``nV nE``, nV pairs ``x y``, nE pairs ``i j``."""
    path = Path(path)
    toks = path.read_text().split()
    name = path.name

    def bad(msg):
        return FileFormatError(f"{name}: {msg}")

    if len(toks) < 2:
        raise bad("expected the counts 'nV nE'")
    try:
        nv, ne = int(toks[0]), int(toks[1])
    except ValueError:
        raise bad(f"expected integer counts 'nV nE', got {toks[0]!r} {toks[1]!r}") from None
    need = 2 + 2 * nv + 2 * ne
    if nv < 0 or ne < 0 or len(toks) != need:
        raise bad(f"nV={nv}, nE={ne} need {need} tokens, the file has {len(toks)}")
    try:
        v = np.array([float(t) for t in toks[2:2 + 2 * nv]], dtype=np.float64).reshape(nv, 2)
        s = np.array([int(t) for t in toks[2 + 2 * nv:]], dtype=np.int64).reshape(ne, 2)
    except ValueError as exc:
        raise bad(f"unparsable number ({exc})") from None
    if not np.isfinite(v).all():
        raise bad("non-finite coordinate")
    if ne and (s.min() < 0 or s.max() >= nv):
        j = int(np.flatnonzero(((s < 0) | (s >= nv)).any(axis=1))[0])
        raise bad(f"edge {j} {s[j].tolist()} refers to a vertex out of range 0..{nv - 1}")
    return PLCInput(_rel(path), v, s, _empty_pts(), None, "cdt", path=path)


def _rings_to_plc(name, polygons_coords, kind, path, props=None) -> PLCInput:
    """polygons_coords: list of polygons, each a list of rings of [x, y] (closed or open)."""
    verts: List = []
    segs: List = []
    rings: List[np.ndarray] = []
    polygons: List[List[int]] = []
    for poly in polygons_coords:
        pidx = []
        for ring in poly:
            pts = [(float(c[0]), float(c[1])) for c in ring]
            if len(pts) > 1 and pts[0] == pts[-1]:
                pts = pts[:-1]
            if not pts:
                continue
            base, k = len(verts), len(pts)
            verts.extend(pts)
            if k >= 2:
                segs.extend((base + i, base + (i + 1) % k) for i in range(k))
            pidx.append(len(rings))
            rings.append(np.arange(base, base + k, dtype=np.int64))
        if pidx:
            polygons.append(pidx)
    v = np.asarray(verts, dtype=np.float64).reshape(-1, 2)
    s = np.asarray(segs, dtype=np.int64).reshape(-1, 2)
    return PLCInput(name, v, s, _empty_pts(), rings, kind, polygons=polygons, path=path,
                    properties=props or {})


def load_earcut_json(path) -> PLCInput:
    """A mapbox/earcut fixture: ring 0 is the outer ring, later rings are holes."""
    path = Path(path)
    data = json.loads(path.read_text())
    return _rings_to_plc(_rel(path), [data], "earcut", path)


def load_geojson(path) -> List[PLCInput]:
    """A GeoJSON FeatureCollection: one PLCInput per Polygon/MultiPolygon feature."""
    path = Path(path)
    data = json.loads(path.read_text())
    out = []
    for i, feat in enumerate(data.get("features", [])):
        g = feat.get("geometry") or {}
        props = feat.get("properties") or {}
        label = props.get("name") or props.get("NAME") or props.get("admin") or str(i)
        if g.get("type") == "Polygon":
            polys = [g["coordinates"]]
        elif g.get("type") == "MultiPolygon":
            polys = g["coordinates"]
        else:
            continue
        out.append(_rings_to_plc(f"{_rel(path)}#{i} {label}", polys, "geojson", path, props))
    return out


def load_file(path) -> List[PLCInput]:
    """All PLCs of one corpus file (one, except for GeoJSON: one per feature)."""
    path = Path(path)
    suf = path.suffix.lower()
    if suf in (".node", ".poly"):
        return [load_triangle(path)]
    if suf == ".txt":
        return [load_cdt_txt(path)]
    if suf == ".geojson":
        return load_geojson(path)
    if suf == ".json":
        return [load_earcut_json(path)]
    raise ValueError(f"not a corpus input: {path}")


def load(name: str) -> List[PLCInput]:
    """Load by corpus-relative name, e.g. ``load("triangle/A.poly")``."""
    return load_file(corpus_dir() / name)


def iter_plcs() -> Iterator[PLCInput]:
    """Every corpus input (each GeoJSON feature separately)."""
    for path in corpus_files():
        yield from load_file(path)


def iter_point_sets() -> Iterator[PLCInput]:
    """Every corpus input usable as a plain point set: all ``.node`` files and the CDT
    files without edges as they are, then the vertices of every other input (segments,
    holes and rings dropped; kind unchanged; duplicates kept)."""
    for plc in iter_plcs():
        if len(plc.segments) == 0 and plc.rings is None:
            yield plc
        else:
            yield replace(plc, segments=_empty_segs(), holes=_empty_pts(), rings=None,
                          polygons=None, regions=None)


# ----------------------------------------------------------------------------------------
# the README's statistics table
# ----------------------------------------------------------------------------------------

def read_stats_table() -> Dict[str, Dict[str, str]]:
    """Rows of the statistics table in the corpus README, keyed by ``folder/file``."""
    text = (corpus_dir() / "README.md").read_text()
    rows: Dict[str, Dict[str, str]] = {}
    header = None
    for line in text.splitlines():
        if not line.startswith("|"):
            header = None if not line.strip() else header
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells and cells[0] == "file" and "V" in cells:
            header = cells
            continue
        if header and len(cells) == len(header) and "/" in cells[0]:
            rows[cells[0]] = dict(zip(header, cells))
    return rows
