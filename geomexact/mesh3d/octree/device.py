"""Devices made of material boxes (met's layered semiconductor devices; issue 24, item 2;
``specs/formats/device.md``), meshed by the octree with every box face fitted exactly.

A :class:`Device` is a list of boxes, each with a material id; where boxes overlap, **the
later box wins** (the list paints the device in order); space in the bounding box that no
box covers is not part of the device.  :func:`generate_device` makes the box faces lattice
planes: the octree starts from a grid of equal cubes whose side is the greatest common
divisor of every box coordinate's distance from the device's low corner (exact rational
gcd), so a layer of any rational thickness is a union of leaves; each tetrahedron then
lies in one grid cube, and its material is the last box holding its centre.  Each
material's volume is exact and equals the painted volume of its boxes."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import ZERO, Rational, mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.criteria import MaxEdgeLength, RefineToMaxLevel
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.refinement import MAX_LEVEL
from geomexact.mesh3d.octree.stages import BoxGrid, RefineWhere
from geomexact.mesh3d.octree.tree import Octree
from geomexact.mesh3d.snapshot import Mesh3, signed_volume6
from geomexact.mesh3d.transient import mesh3_from_positive_arrays

__all__ = [
    "MAX_GRID_CELLS",
    "Device",
    "DeviceBox",
    "DeviceMesh",
    "device_grid",
    "generate_device",
    "painted_volumes",
]

MAX_GRID_CELLS = 1 << 18
"""The most cubes the exact grid of a device may have (about 1.3 million tetrahedra)."""


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
    """The result of :func:`generate_device`: the ``device``, the ``grid`` of cubes, the
    balanced ``octree``, the ``mesh`` (tetrahedra of the device only), the ``materials``
    of its tetrahedra (aligned with ``mesh.tetrahedra()``), each material's exact
    ``volumes`` and the stage ``seconds``."""

    device: Device
    grid: tuple[int, int, int]
    octree: Octree
    mesh: Mesh3
    materials: Any
    volumes: dict[int, Rational]
    seconds: dict[str, float]


def _rational_gcd(a: Rational, b: Rational) -> Rational:
    a, b = mpq(a), mpq(b)
    numerator = math.gcd(int(a.numerator) * int(b.denominator),
                         int(b.numerator) * int(a.denominator))
    return mpq(numerator, int(a.denominator) * int(b.denominator))


def device_grid(device: Device) -> tuple[Box, tuple[int, int, int], Rational]:
    """(the device's bounding box, the grid of equal cubes over it, their side): the side
    is the gcd of every box coordinate's distance from the low corner, on all axes."""
    bounds = device.bounds()
    step = ZERO
    for item in device.boxes:
        for corner in (item.box.low, item.box.high):
            for axis in range(3):
                distance = corner[axis] - bounds.low[axis]
                if distance:
                    step = distance if step == 0 else _rational_gcd(step, distance)
    grid = tuple(int(extent / step) for extent in bounds.extents)
    return bounds, (grid[0], grid[1], grid[2]), step


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
                    on_stage: Callable[[str], None] | None = None) -> DeviceMesh:
    """The tetrahedral mesh of ``device`` (module docstring): the grid of cubes refined
    everywhere to ``level`` (or while a leaf's edges are longer than ``max_edge``),
    balanced, each leaf's pattern tetrahedra; the tetrahedra outside every box left
    out.  :class:`PreconditionError` when the exact grid would have more than
    :data:`MAX_GRID_CELLS` cubes."""
    if not device.boxes:
        raise PreconditionError("generate_device", "a device needs one or more boxes")
    if not 0 <= level <= MAX_LEVEL:
        raise PreconditionError("generate_device", f"the level is 0 .. {MAX_LEVEL}, not "
                                f"{level}")
    bounds, grid, step = device_grid(device)
    cells = grid[0] * grid[1] * grid[2]
    if cells > MAX_GRID_CELLS:
        raise PreconditionError(
            "generate_device", f"fitting every box face exactly needs a grid of "
            f"{grid[0]} x {grid[1]} x {grid[2]} cubes of side {step} (the gcd of the box "
            f"coordinates), more than {MAX_GRID_CELLS}; give the boxes coordinates with a "
            "larger common step (cells split along one or two axes only are not built yet)")
    criterion: Callable[[Box], bool] = (RefineToMaxLevel() if max_edge is None
                                        else MaxEdgeLength(max_edge))
    deepest = level if max_edge is None or level > 0 else MAX_LEVEL
    run = generate(bounds, initial=BoxGrid(*grid),
                   refinement=RefineWhere(deepest, criterion=criterion), trace=False,
                   on_stage=on_stage)
    lattice = run.leaf_mesh.lattice
    points = lattice.exact_points()
    tetrahedra = np.asarray(run.leaf_mesh.tetrahedra, dtype=np.int64).reshape(-1, 4)
    materials = np.zeros(len(tetrahedra), dtype=np.int64)
    for row, tetrahedron in enumerate(tetrahedra.tolist()):
        corners = [points[v] for v in tetrahedron]
        centre = tuple(sum((p[a] for p in corners), mpq(0)) / 4 for a in range(3))
        materials[row] = device.material_at(centre) or 0
    kept = tetrahedra[materials > 0]
    used = np.unique(kept)
    renumber = np.full(len(points), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    mesh = mesh3_from_positive_arrays([points[v] for v in used.tolist()], renumber[kept])
    by_row = {tuple(sorted(row)): m for row, m in zip(renumber[kept].tolist(),
                                                       materials[materials > 0].tolist(),
                                                       strict=True)}
    aligned = np.array([by_row[tuple(sorted(t))] for t in mesh.tetrahedra()], dtype=np.int64)
    aligned.setflags(write=False)
    volumes = {m: ZERO for m in device.materials()}
    for (a, b, c, d), material in zip(mesh.tetrahedra(), aligned.tolist(), strict=True):
        volumes[material] += signed_volume6(mesh.point(a), mesh.point(b), mesh.point(c),
                                            mesh.point(d))
    volumes = {m: v / 6 for m, v in volumes.items()}
    return DeviceMesh(device, grid, run.octree, mesh, aligned, volumes, dict(run.seconds))
