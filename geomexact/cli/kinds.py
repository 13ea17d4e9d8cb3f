"""The kinds of value a command reads and writes, and their names in reports."""

from __future__ import annotations

from typing import TypeAlias

from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.snapshot import Mesh3

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh | Mesh3

KIND_NAMES = {Mesh2: "triangle_mesh", PSLG: "pslg", PolygonMesh: "polygon_mesh",
              Mesh3: "tetrahedral_mesh"}


def kind_name(kind: type) -> str:
    """The report name of a kind of value (``"triangle_mesh"``, ``"pslg"``, …)."""
    return KIND_NAMES.get(kind, kind.__name__)
