"""The kinds of value a command reads and writes, and their names in reports."""

from __future__ import annotations

from typing import TypeAlias

from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh

KIND_NAMES = {Mesh2: "triangle_mesh", PSLG: "pslg", PolygonMesh: "polygon_mesh"}


def kind_name(kind: type) -> str:
    """The report name of a kind of value (``"triangle_mesh"``, ``"pslg"``, …)."""
    return KIND_NAMES.get(kind, kind.__name__)
