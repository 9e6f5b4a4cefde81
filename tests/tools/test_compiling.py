"""The cache guard of cdt_plugin.compiling: numba checks a cached function against its
own source file only, so a cached route would run the old code of a kernel in another
file that has changed since (an upgrade, an edit). The engine's cache files are
removed when the sources' stamp differs from the one kept beside them."""
import os

from cdt_plugin import compiling, report
from cdt_plugin._core.pipeline import cdt_route


def test_cache_paths_are_numbas_own():
    core = compiling._cache_path(os.path.join(compiling._PACKAGE, "_core", "pipeline.py"))
    top = compiling._cache_path(os.path.join(compiling._PACKAGE, "report.py"))
    assert core == cdt_route._cache._cache_path
    assert top == report._orientation_signs._cache._cache_path


def test_stale_cache_files_are_removed_once(tmp_path, monkeypatch):
    core, top = tmp_path / "core", tmp_path / "top"
    core.mkdir()
    top.mkdir()
    paths = {"pipeline.py": str(core), "report.py": str(top)}
    monkeypatch.setattr(compiling, "_cache_path", lambda py_file: paths[os.path.basename(py_file)])

    def plant():
        for name in ("pipeline.cdt_route-304.py311.nbi", "pipeline.cdt_route-304.py311.1.nbc"):
            (core / name).write_bytes(b"old")
        (top / "report._orientation_signs-208.py311.nbi").write_bytes(b"old")
        (top / "report.cpython-311.pyc").write_bytes(b"bytecode")     # not numba's: kept
        (top / "other.f-1.py311.nbi").write_bytes(b"another module's")  # not the engine's: kept

    plant()
    assert compiling.drop_stale_cache()                   # no stamp yet: the cache predates it
    assert sorted(p.name for p in core.iterdir()) == [compiling._MARK]
    assert sorted(p.name for p in top.iterdir()) == ["other.f-1.py311.nbi", "report.cpython-311.pyc"]
    assert (core / compiling._MARK).read_text() == compiling._source_stamp()

    plant()
    assert not compiling.drop_stale_cache()               # same sources: the cache stays
    assert len(list(core.iterdir())) == 3

    (core / compiling._MARK).write_text("a source changed since\n")
    assert compiling.drop_stale_cache()
    assert sorted(p.name for p in core.iterdir()) == [compiling._MARK]


def test_an_unreadable_cache_never_stops_an_import(tmp_path, monkeypatch):
    monkeypatch.setattr(compiling, "_cache_path", lambda py_file: str(tmp_path / "missing" / "\0"))
    assert compiling.drop_stale_cache() is False
