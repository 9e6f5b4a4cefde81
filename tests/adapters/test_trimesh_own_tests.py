"""trimesh's own tests of creation, extrusion, sweeps, sections, paths and primitives, run
with our engine registered as trimesh's default (``register(default=True)``).

trimesh's wheel has no tests; its source distribution on PyPI has them, for the
installed version, without their helper module ``generic.py`` and the ``models/``
directory. So the sdist is downloaded once (``pip download``, kept in pytest's
cache), the chosen modules are unpacked next to a ``generic`` module of our own
(what those modules use from theirs; a test that loads a model file is skipped,
naming the file) and a ``conftest.py`` that registers the engine before their
modules are imported, and they run in a pytest subprocess. Every assertion is
trimesh's, about what our engine and our replacements of trimesh's extrusion,
sweep and capped slicing give. Without network the test skips, except in CI
(``CI=true``), where it fails.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tarfile
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

trimesh = pytest.importorskip("trimesh")
pytest.importorskip("shapely")

#: trimesh's test modules run here (creation, extrusion, sweeps, sections, paths, primitives)
MODULES = ["test_creation.py", "test_extrude.py", "test_sweep.py", "test_section.py",
           "test_paths.py", "test_polygons.py", "test_path_creation.py", "test_primitives.py"]

GENERIC = '''"""What trimesh's test modules use from their ``generic`` helper (not in the sdist)."""
import itertools, json, logging, os, random as _random, timeit, unittest
import networkx as nx
import numpy as np
import pytest
import trimesh
from numpy.linalg import inv, norm
from numpy.testing import assert_allclose
from shapely.geometry import Point, Polygon
from trimesh.constants import tol, tol_path
from trimesh.grouping import group_rows

try:
    import jsonschema
except ImportError:
    jsonschema = None

log = logging.getLogger("trimesh")
random = np.random.random
has_path = True
has_earcut = trimesh.creation._engines[0][1]
tf = trimesh.transformations
# rotations about the origin, as their helper's (their tests expect the centre kept)
transforms = [np.eye(4), tf.rotation_matrix(0.7, [0, 0, 1]), tf.rotation_matrix(2.1, [1, 2, 3]),
              tf.rotation_matrix(np.pi, [1, 0, 0]), tf.random_rotation_matrix()]


def random_transforms(count, translate=1000):
    for _ in range(count):
        matrix = tf.random_rotation_matrix()
        matrix[:3, 3] = (np.random.random(3) - 0.5) * translate
        yield matrix


def _no_models(name=""):
    pytest.skip(f"needs trimesh's models/ directory ({name}), which its sdist does not ship")


def get_mesh(file_name, *args, **kwargs):
    _no_models(file_name)


def get_2D(count=None):
    _no_models("2D drawings")


class _Data(dict):
    def __missing__(self, key):
        _no_models(key)


data = _Data()


def check_path2D(path):
    """The invariants trimesh's helper checks of a Path2D."""
    assert len(path.root) == len(path.polygons_full)
    assert len(path.polygons_closed) == len(path.paths)
    for polygon in path.polygons_full:
        assert polygon.is_valid
    assert isinstance(path.identifier_hash, str)


def to_glb_bytes(geometry):
    return trimesh.Scene(geometry).export(file_type="glb")


def from_glb_bytes(data):
    import io
    return trimesh.load(io.BytesIO(data), file_type="glb")
'''

CONFTEST = '''import pytest
import cdt_plugin.adapters.trimesh as ct

ct.register(default=True)      # before trimesh's modules import anything from trimesh.creation


@pytest.fixture(autouse=True)
def still_ours():
    yield
    assert ct.is_registered(), "a test unregistered the engine"
    ct.register(default=True)
'''

# pyinstrument is a profiler test_sweep.py imports to time one sweep; where it is
# not installed a no-op stand-in lets the module's assertions run
PYINSTRUMENT = '''class Profiler:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def print(self):
        pass
'''


def _sdist(cache_dir: Path) -> Path:
    """trimesh's sdist for the installed version, downloaded into ``cache_dir`` once."""
    version = trimesh.__version__
    found = sorted(cache_dir.glob(f"trimesh-{version}.tar.gz"))
    if found:
        return found[0]
    command = [sys.executable, "-m", "pip", "download", f"trimesh=={version}", "--no-binary",
               ":all:", "--no-deps", "-q", "-d", str(cache_dir)]
    done = subprocess.run(command, capture_output=True, text=True, timeout=300)
    found = sorted(cache_dir.glob(f"trimesh-{version}.tar.gz"))
    if done.returncode or not found:
        reason = f"could not download trimesh {version}'s sdist: {done.stderr.strip()[-300:]}"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(reason)
        pytest.skip(reason)
    return found[0]


@pytest.fixture(scope="module")
def suite(request, tmp_path_factory) -> Path:
    """trimesh's chosen test modules, unpacked with our generic, conftest and stand-ins."""
    cache = getattr(request.config, "cache", None)      # (None under -p no:cacheprovider)
    archive = _sdist(Path(cache.mkdir("trimesh-sdist")) if cache is not None
                     else tmp_path_factory.mktemp("trimesh-sdist"))
    root = tmp_path_factory.mktemp("trimesh-tests")
    with tarfile.open(archive) as tar:
        for member in tar.getmembers():
            parts = Path(member.name).parts
            if len(parts) == 3 and parts[1] == "tests" and parts[2] in MODULES:
                (root / parts[2]).write_bytes(tar.extractfile(member).read())
    missing = sorted(set(MODULES) - {p.name for p in root.iterdir()})
    assert not missing, f"trimesh {trimesh.__version__}'s sdist has no {missing}"
    (root / "generic.py").write_text(GENERIC)
    (root / "conftest.py").write_text(CONFTEST)
    try:
        import pyinstrument  # noqa: F401
    except ImportError:
        (root / "pyinstrument.py").write_text(PYINSTRUMENT)
    return root


def _outcomes(report: Path) -> dict[str, list[str]]:
    """Test names by outcome from a JUnit XML report."""
    outcomes: dict[str, list[str]] = {"passed": [], "failed": [], "skipped": []}
    for case in ElementTree.parse(report).getroot().iter("testcase"):
        name = f"{case.get('classname')}::{case.get('name')}"
        kinds = {child.tag for child in case}
        if kinds & {"failure", "error"}:
            outcomes["failed"].append(name)
        elif "skipped" in kinds:
            outcomes["skipped"].append(name)
        else:
            outcomes["passed"].append(name)
    return outcomes


def test_trimesh_own_tests_pass_with_our_engine_as_the_default(suite):
    report = suite / "report.xml"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(suite), os.environ.get("PYTHONPATH", "")])}
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "-p", "no:randomly", f"--junitxml={report}", "-W", "ignore", *MODULES],
                         cwd=suite, env=env, capture_output=True, text=True, timeout=900)
    outcomes = _outcomes(report)
    assert not outcomes["failed"], run.stdout[-6000:]
    # their tests ran: most of each module, not skipped for a model file
    assert len(outcomes["passed"]) > 40, run.stdout[-3000:]
    ran = {name.split("::")[0].split(".")[0] for name in outcomes["passed"]}
    assert ran >= {m[:-3] for m in MODULES}, ran
