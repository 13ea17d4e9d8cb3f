"""The kinds of value a command reads and writes, and their names in reports."""

from __future__ import annotations

from typing import TypeAlias

from geomexact.cli.errors import UsageProblem
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


KIND_PHRASES = {Mesh2: "a triangle mesh", PSLG: "a PSLG", PolygonMesh: "a polygon mesh",
                Mesh3: "a tetrahedral mesh (3D)"}


def wrong_kind(path: str, value: object, command: str, needs: str) -> UsageProblem:
    """The error of ``command`` given ``value``, read from ``path``, of a kind it does not
    work on: ``PATH: is a tetrahedral mesh (3D): COMMAND works on NEEDS``, naming the 3D
    commands when the value is 3D."""
    kind = KIND_PHRASES.get(type(value), f"a {type(value).__name__}")
    text = f"{path}: is {kind}: {command} works on {needs}"
    if isinstance(value, Mesh3):
        text += "; see geomexact octree for 3D meshing (check, info, convert and view " \
                "also read tetrahedral meshes)"
    return UsageProblem(text)
