"""Devices made of material boxes (met's layered semiconductor devices; issue 24, item 2;
``specs/formats/device.md``), meshed by the octree with every box face fitted exactly.

A :class:`Device` is a list of boxes, each with a material id; where boxes overlap, **the
later box wins** (the list paints the device in order); space in the bounding box that no
box covers is not part of the device.  :func:`generate_device` makes the box faces grid
planes: the octree starts from the *rectilinear* grid whose lines are the boxes'
coordinates on each axis (:func:`~geomexact.mesh3d.octree.tree.octree_of_planes`), so a
layer of any rational thickness is a row of grid cells, however thin; each tetrahedron
then lies in one grid cell, and its material is the last box holding its centre.  Each
material's volume is exact and equals the painted volume of its boxes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Final, Literal

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import ZERO, Rational, mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.cell_templates import relabelled
from geomexact.mesh3d.mixed.cell_geometry import cell_volume
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.octree.criteria import MaxEdgeLength, RefineToMaxLevel
from geomexact.mesh3d.octree.pipeline import generate, generate_cells
from geomexact.mesh3d.octree.refinement import MAX_LEVEL
from geomexact.mesh3d.octree.stages import MixedPartition, PolyhedralPartition, RefineWhere
from geomexact.mesh3d.octree.tree import Octree, octree_of_planes
from geomexact.mesh3d.snapshot import Mesh3, signed_volume6
from geomexact.mesh3d.transient import mesh3_from_positive_arrays

__all__ = [
    "DEVICE_FINALS",
    "Device",
    "DeviceBox",
    "DeviceFinal",
    "DeviceMesh",
    "device_planes",
    "generate_device",
    "painted_volumes",
]

DeviceFinal = Literal["patterns", "mixed", "polyhedral"]
DEVICE_FINALS: Final[tuple[DeviceFinal, ...]] = ("patterns", "mixed", "polyhedral")


@attrs.frozen(slots=True)
class DeviceBox:
    """One box of a device: its exact corners and its material (a positive integer)."""

    box: Box
    material: int


@attrs.frozen(slots=True)
class Device:
    """``boxes`` in painting order (a later box wins where they overlap) and the
    materials' ``names`` (id -> name; ids without a name are allowed)."""

    boxes: tuple[DeviceBox, ...]
    names: tuple[tuple[int, str], ...] = ()

    def bounds(self) -> Box:
        low = tuple(min(b.box.low[a] for b in self.boxes) for a in range(3))
        high = tuple(max(b.box.high[a] for b in self.boxes) for a in range(3))
        return Box(low, high)

    def materials(self) -> list[int]:
        return sorted({b.material for b in self.boxes})

    def material_at(self, point: Sequence[Rational]) -> int | None:
        """The material of the last box holding ``point`` (closed boxes), or None."""
        for item in reversed(self.boxes):
            if all(item.box.low[a] <= point[a] <= item.box.high[a] for a in range(3)):
                return item.material
        return None


@attrs.frozen(slots=True, eq=False)
class DeviceMesh:
    """The result of :func:`generate_device`: the ``device``, the ``grid`` (cells per axis
    of its rectilinear grid), the
    balanced ``octree``, the ``mesh`` (tetrahedra of the device only), the ``materials``
    of its tetrahedra (aligned with ``mesh.tetrahedra()``), each material's exact
    ``volumes`` and the stage ``seconds``."""

    device: Device
    grid: tuple[int, int, int]
    octree: Octree
    mesh: Mesh3 | MixedMesh3
    materials: Any
    volumes: dict[int, Rational]
    seconds: dict[str, float]


def device_planes(device: Device) -> tuple[tuple[Rational, ...], ...]:
    """The grid lines of the device's rectilinear grid: every box coordinate, per axis,
    sorted."""
    return tuple(tuple(sorted({c for item in device.boxes
                               for c in (item.box.low[a], item.box.high[a])}))
                 for a in range(3))


def painted_volumes(device: Device) -> dict[int, Rational]:
    """Each material's exact volume, painted box by box on the grid of the boxes' own
    coordinates (independent of the octree)."""
    planes = [sorted({c for item in device.boxes for c in (item.box.low[a], item.box.high[a])})
              for a in range(3)]
    volumes: dict[int, Rational] = {m: ZERO for m in device.materials()}
    for x0, x1 in zip(planes[0], planes[0][1:], strict=False):
        for y0, y1 in zip(planes[1], planes[1][1:], strict=False):
            for z0, z1 in zip(planes[2], planes[2][1:], strict=False):
                material = device.material_at(((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2))
                if material is not None:
                    volumes[material] += (x1 - x0) * (y1 - y0) * (z1 - z0)
    return volumes


def generate_device(device: Device, *, level: int = 0, max_edge: Rational | None = None,
                    final: DeviceFinal = "patterns",
                    on_stage: Callable[[str], None] | None = None) -> DeviceMesh:
    """The mesh of ``device`` (module docstring): the rectilinear grid of its box
    coordinates refined everywhere to ``level`` (or while a leaf's edges are longer than
    ``max_edge``), balanced, each leaf cut by the ``final`` (its pattern tetrahedra, or
    the mixed or polyhedral cells: a thin layer's flat leaves are then flat hexahedra);
    the elements outside every box left out."""
    if not device.boxes:
        raise PreconditionError("generate_device", "a device needs one or more boxes")
    if not 0 <= level <= MAX_LEVEL:
        raise PreconditionError("generate_device", f"the level is 0 .. {MAX_LEVEL}, not "
                                f"{level}")
    if final not in DEVICE_FINALS:
        raise PreconditionError("generate_device", f"the final is one of {DEVICE_FINALS}, "
                                f"not {final!r}")
    planes = device_planes(device)
    bounds = device.bounds()
    criterion: Callable[[Box], bool] = (RefineToMaxLevel() if max_edge is None
                                        else MaxEdgeLength(max_edge))
    deepest = level if max_edge is None or level > 0 else MAX_LEVEL
    stages: dict[str, Any] = {
        "initial": lambda _: octree_of_planes(planes),
        "refinement": RefineWhere(deepest, criterion=criterion), "trace": False,
        "on_stage": on_stage}
    if final == "patterns":
        run = generate(bounds, **stages)
        points = run.leaf_mesh.lattice.exact_points()
        tetrahedra = np.asarray(run.leaf_mesh.tetrahedra, dtype=np.int64).reshape(-1, 4)
        cells: list[Any] = [tuple(t) for t in tetrahedra.tolist()]
        vertex_lists = cells
    else:
        cell_run = generate_cells(bounds, MixedPartition() if final == "mixed"
                                  else PolyhedralPartition(), **stages)
        run = cell_run  # type: ignore[assignment]
        whole = cell_run.mesh
        points = [whole.point(v) for v in range(whole.vertex_count)]
        cells = whole.cell_list()
        vertex_lists = [cell.vertices for cell in cells]
    materials = []
    for vertices in vertex_lists:
        centre = tuple(sum((points[v][a] for v in vertices), mpq(0)) / len(vertices)
                       for a in range(3))
        materials.append(device.material_at(centre) or 0)
    kept = [index for index, material in enumerate(materials) if material]
    used = sorted({v for index in kept for v in vertex_lists[index]})
    renumber = {v: i for i, v in enumerate(used)}
    kept_points = [points[v] for v in used]
    volumes = {m: ZERO for m in device.materials()}
    if final == "patterns":
        rows = np.array([[renumber[v] for v in cells[index]] for index in kept],
                        dtype=np.int64).reshape(-1, 4)
        tetrahedral = mesh3_from_positive_arrays(kept_points, rows)
        by_cell = {tuple(sorted(row)): materials[index]
                   for row, index in zip(rows.tolist(), kept, strict=True)}
        aligned = np.array([by_cell[tuple(sorted(t))] for t in tetrahedral.tetrahedra()],
                           dtype=np.int64)
        for (a, b, c, d), material in zip(tetrahedral.tetrahedra(), aligned.tolist(),
                                          strict=True):
            volumes[material] += signed_volume6(tetrahedral.point(a), tetrahedral.point(b),
                                                tetrahedral.point(c), tetrahedral.point(d)) / 6
        mesh: Mesh3 | MixedMesh3 = tetrahedral
    else:
        renamed = [relabelled(cells[index], [renumber.get(v, -1)
                                             for v in range(len(points))])
                   for index in kept]
        mesh = mixed_mesh_from_cells(kept_points, renamed)
        by_cell_mixed = {cell: materials[index]
                         for cell, index in zip(renamed, kept, strict=True)}
        aligned = np.array([by_cell_mixed[cell] for cell in mesh.cell_list()],
                           dtype=np.int64)
        for cell, material in zip(mesh.cell_list(), aligned.tolist(), strict=True):
            volumes[material] += cell_volume(cell, mesh.vertices)
    aligned.setflags(write=False)
    return DeviceMesh(device, run.octree.grid, run.octree, mesh, aligned, volumes,
                      dict(run.seconds))
