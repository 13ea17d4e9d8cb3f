"""The properties ``geomexact trace bisect --fails CHECK`` names, collected from the
library (:mod:`geomexact.mesh2d.properties`, :mod:`geomexact.mesh3d.properties`, the
Delaunay tests) by name, and a user's ``module:function``."""

from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Callable
from typing import Any

import attrs

from geomexact.cli.errors import UsageProblem
from geomexact.errors import GeomexactError
from geomexact.kernel.numbers import format_rational, parse_rational
from geomexact.mesh2d.delaunay.triangulation import is_delaunay
from geomexact.mesh2d.measures import total_area
from geomexact.mesh2d.properties import has_area, has_min_angle, is_valid
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.measures import is_delaunay3, total_volume
from geomexact.mesh3d.properties import has_volume, is_valid3
from geomexact.mesh3d.snapshot import Mesh3

CHECKS_HELP = (
    "valid (2D validate / 3D validate3 finds nothing), delaunay, min-angle:DEGREES (2D: "
    "every smallest angle >= DEGREES, 0 < DEGREES < 60), area (2D: the input's total area, "
    "exactly), volume (3D: the input's volume, exactly), conforming (3D: validate3, closed "
    "boundary included), or module:function (a callable taking the mesh, truthy when the "
    "property holds)"
)


@attrs.frozen
class NamedCheck:
    """A property of the meshes of a trace: ``name`` as given, ``holds(mesh)``."""

    name: str
    holds: Callable[[Any], bool]


def named_check(spec: str, start: Mesh2 | Mesh3) -> NamedCheck:
    """The check ``spec`` names for meshes like ``start`` (the trace's input); a
    :class:`UsageProblem` for an unknown name, one of the other dimension, a bad angle or
    a ``module:function`` that does not import."""
    three = isinstance(start, Mesh3)
    dimension = "3D" if three else "2D"
    if spec == "valid":
        return NamedCheck(spec, is_valid3 if three else is_valid)
    if spec == "delaunay":
        return NamedCheck(spec, is_delaunay3 if three else is_delaunay)
    if spec == "conforming":
        if not three:
            raise UsageProblem("--fails conforming is a check of tetrahedral meshes (3D); "
                               "for a 2D trace use --fails valid")
        return NamedCheck(spec, is_valid3)
    if spec == "area":
        if three:
            raise UsageProblem("--fails area is a check of triangle meshes (2D); for a 3D "
                               "trace use --fails volume")
        area = total_area(start)  # type: ignore[arg-type]
        return NamedCheck(spec, lambda mesh: has_area(mesh, area))
    if spec == "volume":
        if not three:
            raise UsageProblem("--fails volume is a check of tetrahedral meshes (3D); for a "
                               "2D trace use --fails area")
        volume = total_volume(start)  # type: ignore[arg-type]
        return NamedCheck(spec, lambda mesh: has_volume(mesh, volume))
    if spec.startswith("min-angle:"):
        if three:
            raise UsageProblem(f"--fails {spec} is a check of triangle meshes (2D), but the "
                               f"trace is {dimension}")
        return NamedCheck(spec, _min_angle(spec.removeprefix("min-angle:")))
    if ":" in spec:
        return NamedCheck(spec, _user_check(spec))
    raise UsageProblem(f"--fails {spec!r}: unknown check; use one of {CHECKS_HELP}")


def _min_angle(text: str) -> Callable[[Any], bool]:
    try:
        degrees = parse_rational(text)
    except GeomexactError as error:
        raise UsageProblem(f"--fails min-angle:{text}: {text!r} is not an exact number "
                           "of degrees") from error
    if not 0 < degrees < 60:
        raise UsageProblem(f"--fails min-angle:{text}: the angle must be strictly between 0 "
                           f"and 60 degrees, not {format_rational(degrees)}")
    return lambda mesh: has_min_angle(mesh, degrees)


def _user_check(spec: str) -> Callable[[Any], bool]:
    """``module:function`` imported (the current directory searched too)."""
    module_name, _, function_name = spec.partition(":")
    if not module_name or not function_name:
        raise UsageProblem(f"--fails {spec!r}: a user check is module:function")
    if os.getcwd() not in sys.path and "" not in sys.path:
        sys.path.append(os.getcwd())
    try:
        module = importlib.import_module(module_name)
    except Exception as error:  # any failure of the user's module is bad input
        raise UsageProblem(f"--fails {spec}: cannot import {module_name}: "
                           f"{type(error).__name__}: {error}") from error
    function = getattr(module, function_name, None)
    if not callable(function):
        raise UsageProblem(f"--fails {spec}: {module_name} has no function {function_name}")

    def holds(mesh: Any) -> bool:
        try:
            return bool(function(mesh))
        except Exception as error:  # the user's check failed: say so, no traceback
            raise UsageProblem(f"--fails {spec} raised {type(error).__name__}: {error}"
                               ) from error

    return holds
