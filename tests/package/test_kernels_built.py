"""The optional compiled kernels are built wherever they can be, and are never stale.

A kernel that fails to compile only warns at install (the pure-Python engines take over),
so without these checks a compile error would pass CI silently: every kernel test would
skip.  Where a C compiler and the Python headers exist (as on our machines and in CI), every
kernel (and the test-facing C filters) must be importable; and an in-tree build must be
newer than its sources."""

from __future__ import annotations

import importlib
import os
import shutil
import sysconfig
from pathlib import Path

import pytest

from geomexact.mesh2d.delaunay import compiled as delaunay_compiled
from geomexact.mesh2d.refinement.engines import compiled as compiled_engine
from geomexact.mesh3d.cuboid import compiled as cuboid_compiled

PACKAGE = Path(__file__).resolve().parents[2] / "geomexact"
SOURCES = {
    "geomexact.mesh2d.refinement.engines.lepp_kernel": PACKAGE / "mesh2d" / "refinement" / "engines" / "lepp_kernel.pyx",
    "geomexact.mesh2d.delaunay.delaunay_kernel": PACKAGE / "mesh2d" / "delaunay" / "delaunay_kernel.pyx",
    "geomexact.kernel.cfilters": PACKAGE / "kernel" / "cfilters.pyx",
    "geomexact.mesh3d.cuboid.cuboid_kernel": PACKAGE / "mesh3d" / "cuboid" / "cuboid_kernel.pyx",
}
SHARED = [PACKAGE / "kernel" / "ckernel.h", PACKAGE / "kernel" / "ckernel.pxd"]


def can_build() -> bool:
    headers = Path(sysconfig.get_paths()["include"]) / "Python.h"
    compiler = shutil.which("cc") or shutil.which("gcc")
    return bool(compiler) and headers.exists() and not os.environ.get("GEOMEXACT_NO_EXTENSION")


@pytest.mark.skipif(not can_build(), reason="no C compiler or Python headers here, or "
                    "GEOMEXACT_NO_EXTENSION is set")
def test_kernels_are_built_where_they_can_be() -> None:
    assert compiled_engine.AVAILABLE, "the Lepp kernel did not build: see pip's warning"
    assert delaunay_compiled.AVAILABLE, "the Delaunay kernel did not build: see pip's warning"
    assert cuboid_compiled.AVAILABLE, "the cuboid kernel did not build: see pip's warning"
    try:
        importlib.import_module("geomexact.kernel.cfilters")
    except ImportError as error:
        pytest.fail(f"the test-facing C filters did not build ({error}): see pip's warning")


@pytest.mark.parametrize("name", sorted(SOURCES))
def test_an_in_tree_kernel_is_newer_than_its_sources(name: str) -> None:
    try:
        module = importlib.import_module(name)
    except ImportError:
        pytest.skip(f"{name} is not built")
    built = Path(module.__file__ or "")
    if built.parent != SOURCES[name].parent:
        pytest.skip("installed outside the source tree")
    newest = max(path.stat().st_mtime for path in [SOURCES[name], *SHARED])
    assert built.stat().st_mtime >= newest, (
        f"{built.name} is older than its sources: reinstall (pip install -e .)")
