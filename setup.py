"""Build hook: the optional compiled Lepp-bisection kernel (``geomexact/refinement/lepp_kernel.pyx``).

All metadata lives in pyproject.toml.  The extension is optional: without Cython or a C
compiler, or when its build fails, the package installs without it and
``geomexact.refine`` uses its pure-Python engine (``geomexact.refinement.compiled_engine``
returns None).  Set ``GEOMEXACT_NO_EXTENSION=1`` to skip it on purpose.
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


def _warn(error: BaseException) -> None:
    print(
        f"geomexact: the compiled kernel was not built ({error}); "
        "refinement uses the pure-Python engine",
        file=sys.stderr,
    )


def _extensions() -> list[Extension]:
    if os.environ.get("GEOMEXACT_NO_EXTENSION"):
        return []
    try:
        from Cython.Build import cythonize
    except ImportError:
        _warn(ImportError("Cython is not installed"))
        return []
    extension = Extension(
        "geomexact.refinement.lepp_kernel",
        ["geomexact/refinement/lepp_kernel.pyx"],
        # the float filters' error bounds assume one rounding per operation: no FMA
        extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"],
    )
    try:
        return list(cythonize([extension], language_level=3, quiet=True))
    except Exception as error:
        _warn(error)
        return []


setup(ext_modules=_extensions(), cmdclass={"build_ext": OptionalBuildExt})
