"""The kinds of value a command reads and writes, and their names in reports."""

from __future__ import annotations

from typing import TypeAlias

from geomexact.cli.errors import UsageProblem
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3

Value: TypeAlias = Mesh2 | PSLG | PolygonMesh | Mesh3 | MixedMesh3
"""What a command reads."""

Writable: TypeAlias = Value | MixedMeshData
"""What a command writes: what it reads, or a mixed mesh with cell data."""

KIND_NAMES = {Mesh2: "triangle_mesh", PSLG: "pslg", PolygonMesh: "polygon_mesh",
              Mesh3: "tetrahedral_mesh", MixedMesh3: "mixed_mesh",
              MixedMeshData: "mixed_mesh"}


def kind_name(kind: type) -> str:
    """The report name of a kind of value (``"triangle_mesh"``, ``"pslg"``, …)."""
    return KIND_NAMES.get(kind, kind.__name__)


def held_kinds(kinds: tuple[type, ...]) -> str:
    """The kinds a format holds, in words: ``"triangle mesh or tetrahedral mesh"``."""
    names = dict.fromkeys(kind_name(kind).replace("_", " ") for kind in kinds)
    return " or ".join(names)


KIND_PHRASES = {Mesh2: "a triangle mesh", PSLG: "a PSLG", PolygonMesh: "a polygon mesh",
                Mesh3: "a tetrahedral mesh (3D)", MixedMesh3: "a mixed-cell mesh (3D)",
                MixedMeshData: "a mixed-cell mesh (3D)"}


def wrong_kind(path: str, value: object, command: str, needs: str) -> UsageProblem:
    """The error of ``command`` given ``value``, read from ``path``, of a kind it does not
    work on: ``PATH: is a tetrahedral mesh (3D): COMMAND works on NEEDS``, naming the 3D
    commands when the value is 3D."""
    kind = KIND_PHRASES.get(type(value), f"a {type(value).__name__}")
    text = f"{path}: is {kind}: {command} works on {needs}"
    if isinstance(value, Mesh3 | MixedMesh3 | MixedMeshData):
        text += "; see geomexact octree for 3D meshing (check, info, convert and view " \
                "also read tetrahedral and mixed-cell meshes)"
    return UsageProblem(text)
