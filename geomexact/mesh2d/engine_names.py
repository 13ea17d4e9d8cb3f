"""The names of the engines that run a 2D algorithm (``engine=`` of ``refine`` and
``triangulate``; ``--engine`` of the CLI).

* ``"auto"`` (the default): the compiled kernel where it applies, else the pure-Python
  engine;
* ``"compiled"``: the Cython kernel, or :class:`~geomexact.errors.PreconditionError` when it
  is not built or the run is outside what it implements (never something else silently);
* ``"reference"``: the pure ops on a transient, the definition (``"python"`` names it
  too): two tiers, the reference and the compiled kernel (issue 25 retired the batch
  engines in between).

All record the same trace; the engine is never a parameter of it.  ``"fast"`` and
``"transient"`` are the old names of ``"auto"`` and ``"reference"``, still accepted with a
:class:`~geomexact.errors.GeomexactDeprecationWarning`.
:func:`compiled_kernel` says whether a ``"compiled"`` engine is there.
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any, Literal, TypeAlias

from geomexact.errors import PreconditionError, warn_deprecated

Engine: TypeAlias = Literal["auto", "compiled", "python", "reference", "fast", "transient"]

ENGINES: tuple[str, ...] = ("auto", "compiled", "python", "reference")
"""The engine names, each saying what runs."""

OLD_NAMES: Mapping[str, str] = MappingProxyType({"fast": "auto", "transient": "reference"})
"""Old engine name -> its name now."""


def engine_named(op: str, engine: str, engines: tuple[str, ...] = ENGINES, *,
                 stacklevel: int = 3) -> str:
    """The engine ``engine`` names (an old name gives the new one, with a deprecation
    warning pointing ``stacklevel`` frames up: the caller of ``op`` by default), which
    must be one of ``engines`` (those of the algorithm ``op``); else
    :class:`PreconditionError`."""
    name = OLD_NAMES.get(engine, engine)
    if name != engine and name in engines:
        warn_deprecated(f"engine {engine!r}", f"engine {name!r}", stacklevel=stacklevel)
    if name not in engines:
        choices = ", ".join(repr(e) for e in engines)
        old = ", ".join(f"{o!r} for {n!r}" for o, n in OLD_NAMES.items() if n in engines)
        if name in ENGINES:
            raise PreconditionError(
                op, f"there is no {name!r} engine for {op}; choose from {choices}"
            )
        raise PreconditionError(
            op, f"unknown engine {engine!r}; choose from {choices} (old names: {old})"
        )
    return name


def compiled_kernel(module: str) -> Any:
    """The compiled kernel ``module`` (an optional Cython extension), or None when it is
    not built: then engine ``"auto"`` runs the pure-Python engine and ``"compiled"``
    refuses."""
    try:
        return importlib.import_module(module)
    except ImportError:
        return None
