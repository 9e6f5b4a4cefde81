"""A missing optional package: an ImportError naming the extra that brings it, from every
place that needs one (adapters at import, plots, comparisons, GIS readers), before
anything compiles. Each case runs in a fresh interpreter where the package cannot be
imported (a meta-path finder refuses it, as if it were not installed)."""
import subprocess
import sys
import textwrap

import pytest

from cdt_plugin.optional import EXTRA_OF, MissingPackageError, missing, require

BLOCKER = """
import importlib.abc, sys
BLOCKED = {blocked!r}
class NotInstalled(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)
        return None
sys.meta_path.insert(0, NotInstalled())
import numba.core.registry   # (numba imports lazily: fail here, not inside a compile)
"""

CASES = {
    "shapely adapter": ("shapely", "import cdt_plugin.adapters.shapely", "shapely"),
    "trimesh adapter": ("trimesh", "import cdt_plugin.adapters.trimesh", "trimesh"),
    "Open3D adapter": ("open3d", "import cdt_plugin.adapters.open3d", "open3d"),
    "geo adapter": ("shapely", "import cdt_plugin.adapters.geo", "gis"),
    "geo.read": ("geopandas", "from cdt_plugin.adapters import geo\n"
                              "geo.read('../shared/corpus/x.geojson')", "gis"),
    "plot": ("matplotlib", "import cdt_plugin.plot as p\np.plot(([[0, 0], [1, 0], [0, 1]], [[0, 1, 2]]))",
             "plot"),
    "to_matplotlib": ("matplotlib", "import cdt_plugin\n"
                                    "cdt_plugin.delaunay([[0, 0], [1, 0], [0, 1]]).to_matplotlib()",
                      "plot"),
    "earcut comparison": ("mapbox_earcut", "from cdt_plugin.report import earcut\n"
                                           "earcut({'type': 'Polygon', 'coordinates': "
                                           "[[(0, 0), (1, 0), (0, 1), (0, 0)]]})", "bench"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_missing_package_names_its_extra(case):
    blocked, code, extra = CASES[case]
    script = textwrap.dedent(BLOCKER.format(blocked=[blocked])) + code
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode != 0, f"{case} ran without {blocked}:\n{run.stdout}"
    last = run.stderr.strip().splitlines()[-1]
    assert last.startswith("cdt_plugin.optional.MissingPackageError: "), run.stderr[-2000:]
    assert f"needs {blocked}: pip install 'cdt-plugin[{extra}]'" in last, last


def test_every_named_extra_exists():
    import tomllib
    from pathlib import Path
    with open(Path(__file__).parents[2] / "pyproject.toml", "rb") as f:
        extras = tomllib.load(f)["project"]["optional-dependencies"]
    assert set(EXTRA_OF.values()) <= set(extras), set(EXTRA_OF.values()) - set(extras)
    package_of = {"skfem": "scikit_fem"}         # import names that are not their package's
    for module, extra in EXTRA_OF.items():      # the extra really lists the module's package
        listed = " ".join(extras[extra]).lower().replace("-", "_")
        assert package_of.get(module, module).lower() in listed, (module, extra)


def test_missing_and_require():
    err = missing("scipy.spatial", "a comparison")
    assert isinstance(err, ModuleNotFoundError) and err.name == "scipy"
    assert str(err) == "a comparison needs scipy: pip install scipy"     # no extra brings it
    assert "pip install 'cdt-plugin[gis]'" in str(missing("pyproj", "projecting"))
    assert "pip install 'cdt-plugin[gis]'" in str(missing("shapely", "the geo adapter", extra="gis"))
    with pytest.raises(MissingPackageError, match="needs no_such_package_here"):
        require("no_such_package_here.sub", "this test")
    assert require("json", "this test").dumps([1]) == "[1]"
