"""Build hook: the optional compiled kernels.

* ``geomexact/mesh2d/refinement/engines/lepp_kernel.pyx``: Lepp-bisection (``geomexact.mesh2d.refinement.api``);
* ``geomexact/mesh2d/delaunay/delaunay_kernel.pyx``: the Delaunay triangulation of a point set
  (``geomexact.mesh2d.delaunay.triangulation.triangulate_points``);
* ``geomexact/mesh3d/cuboid/cuboid_kernel.pyx``: the cuboid partition, its improvement and its
  census row (``geomexact.mesh3d.cuboid.compiled``);
* ``geomexact/kernel/triangle_store.pyx``: the base type of the two 2D kernels (it owns
  their triangle store, ``geomexact/kernel/ctriangulation.pxd``, and reads back its step
  records); they import it, so without it they do not load either;
* ``geomexact/kernel/cfilters.pyx``: test-facing wrappers of the C filters, so that the tests
  can check them against the exact predicates (nothing in the package imports it).

All include the shared C pieces ``geomexact/kernel/ckernel.h`` (declared in
``geomexact/kernel/ckernel.pxd``); the Lepp kernel also ``geomexact/kernel/grid_rational.h``
(mpq objects built through gmpy2's C API, with gmpy2's headers when they are found).  All metadata lives in pyproject.toml.  The extensions
are optional, each on its own: without Cython or a C compiler, or when a build fails, the
package installs without it and the caller uses its pure-Python code
(``geomexact.mesh2d.refinement.engines.compiled`` / ``geomexact.mesh2d.delaunay.compiled`` return None).
Set ``GEOMEXACT_NO_EXTENSION=1`` to skip them on purpose.
"""

from __future__ import annotations

import os
import sys
from typing import Any

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class OptionalBuildExt(build_ext):
    """build_ext that warns instead of failing when the kernel cannot be compiled."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as error:  # any failure only loses the speed-up
            _warn(error)

    def build_extension(self, ext: Any) -> None:
        try:
            super().build_extension(ext)
        except Exception as error:
            _warn(error)
            _remove_stale(ext.name)


def _warn(error: BaseException) -> None:
    print(
        f"geomexact: a compiled kernel was not built ({error}); "
        "the pure-Python code runs instead",
        file=sys.stderr,
    )


def _remove_stale(name: str) -> None:
    """Delete a kernel built earlier in the source tree (an editable install): when the
    kernel no longer compiles, the old build must not keep running stale code."""
    from importlib.machinery import EXTENSION_SUFFIXES

    stem = os.path.join(os.path.dirname(os.path.abspath(__file__)), *name.split("."))
    for suffix in EXTENSION_SUFFIXES:
        if os.path.exists(stem + suffix):
            os.remove(stem + suffix)


KERNELS = [
    ("geomexact.mesh2d.refinement.engines.lepp_kernel", "geomexact/mesh2d/refinement/engines/lepp_kernel.pyx"),
    ("geomexact.mesh2d.delaunay.delaunay_kernel", "geomexact/mesh2d/delaunay/delaunay_kernel.pyx"),
    ("geomexact.kernel.triangle_store", "geomexact/kernel/triangle_store.pyx"),
    ("geomexact.kernel.cfilters", "geomexact/kernel/cfilters.pyx"),
    ("geomexact.mesh3d.cuboid.cuboid_kernel", "geomexact/mesh3d/cuboid/cuboid_kernel.pyx"),
]


def _gmpy2_headers() -> tuple[list[str], list[tuple[str, str]]]:
    """The include directory and macros of ``geomexact/kernel/grid_rational.h`` when the
    gmpy2 at build time ships its C headers (gmpy2.h, gmp.h, mpfr.h, mpc.h); none
    otherwise (the kernels then build their grid rationals in Python)."""
    try:
        import gmpy2
    except ImportError:
        return [], []
    folder = os.path.dirname(os.path.abspath(gmpy2.__file__))
    if not all(os.path.exists(os.path.join(folder, name))
               for name in ("gmpy2.h", "gmp.h", "mpfr.h", "mpc.h")):
        return [], []
    return [folder], [("GX_WITH_GMPY2", "1"), ("GX_GMPY2_VERSION", f'"{gmpy2.version()}"')]


def _extensions() -> list[Extension]:
    if os.environ.get("GEOMEXACT_NO_EXTENSION"):
        return []
    try:
        from Cython.Build import cythonize
    except ImportError:
        _warn(ImportError("Cython is not installed"))
        return []
    built = []
    gmpy2_folders, gmpy2_macros = _gmpy2_headers()
    for name, source in KERNELS:
        extension = Extension(
            name,
            [source],
            include_dirs=["geomexact/kernel", *gmpy2_folders],  # ckernel.h, grid_rational.h
            define_macros=gmpy2_macros,
            depends=["geomexact/kernel/ckernel.h", "geomexact/kernel/ckernel.pxd",
                     "geomexact/kernel/ctriangulation.pxd",
                     "geomexact/kernel/triangle_store.pxd",
                     "geomexact/kernel/grid_rational.h"],
            # the float filters' error bounds assume one rounding per operation: no FMA
            extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"],
        )
        try:  # each kernel on its own: one failing to compile keeps the others
            built.extend(cythonize([extension], language_level=3, quiet=True))
        except Exception as error:
            _warn(error)
            _remove_stale(name)
    return built


setup(ext_modules=_extensions(), cmdclass={"build_ext": OptionalBuildExt})
