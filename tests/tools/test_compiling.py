"""The cache guard of cdt_plugin.compiling: numba checks a cached function against its
own source file only, so a cached route would run the old code of a kernel in another
file that has changed since (an upgrade, an edit). The engine's cache files are
removed when the sources' stamp differs from the one kept beside them. And the
compile command (``cdt_plugin.warmup``) above it."""
import os

import pytest

import cdt_plugin
from cdt_plugin import compiling
from cdt_plugin._core.pipeline import cdt_route_packed


def test_cache_paths_are_numbas_own():
    cdt_plugin.triangulate([[0, 0], [1, 0], [0, 1]])      # (a kernel opens its cache when compiled or loaded)
    core = compiling._cache_path(os.path.join(compiling._PACKAGE, "_core", "pipeline.py"))
    assert core == cdt_route_packed._cache._cache_path


def test_stale_cache_files_are_removed_once(tmp_path, monkeypatch):
    core = tmp_path / "core"
    core.mkdir()
    monkeypatch.setattr(compiling, "_cache_path", lambda py_file: str(core))

    def plant():
        for name in ("pipeline.cdt_route-304.py311.nbi", "pipeline.cdt_route-304.py311.1.nbc"):
            (core / name).write_bytes(b"old")
        (core / "pipeline.cpython-311.pyc").write_bytes(b"bytecode")     # not numba's: kept

    plant()
    assert compiling.drop_stale_cache()                   # no stamp yet: the cache predates it
    assert sorted(p.name for p in core.iterdir()) == [compiling._MARK, "pipeline.cpython-311.pyc"]
    assert (core / compiling._MARK).read_text() == compiling._source_stamp()

    plant()
    assert not compiling.drop_stale_cache()               # same sources: the cache stays
    assert len(list(core.iterdir())) == 4

    (core / compiling._MARK).write_text("a source changed since\n")
    assert compiling.drop_stale_cache()
    assert sorted(p.name for p in core.iterdir()) == [compiling._MARK, "pipeline.cpython-311.pyc"]


def test_an_unreadable_cache_never_stops_an_import(tmp_path, monkeypatch):
    monkeypatch.setattr(compiling, "_cache_path", lambda py_file: str(tmp_path / "missing" / "\0"))
    assert compiling.drop_stale_cache() is False


def test_the_compile_command_names_an_unknown_route():
    """``cdt-plugin compile ROUTE``: a route that does not exist is named, before any
    route compiles."""
    from cdt_plugin.warmup import compile_routes
    with pytest.raises(cdt_plugin.CDTError, match=r"unknown route 'nope'; the routes are \['batch'"):
        compile_routes(["delaunay", "nope"])
