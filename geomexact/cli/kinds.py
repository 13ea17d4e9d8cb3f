"""The kinds of value a command reads and writes, and their names in reports."""

from __future__ import annotations

from typing import TypeAlias

from geomexact.mesh2d import Mesh2
from geomexact.polymesh import PolygonMesh
from geomexact.pslg import PSLG

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh

KIND_NAMES = {Mesh2: "triangle_mesh", PSLG: "pslg", PolygonMesh: "polygon_mesh"}


def kind_name(kind: type) -> str:
    """The report name of a kind of value (``"triangle_mesh"``, ``"pslg"``, …)."""
    return KIND_NAMES.get(kind, kind.__name__)
