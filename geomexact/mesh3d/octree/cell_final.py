"""The octree's ``mixed`` and ``polyhedral`` finals: every leaf becomes the cells of its
pattern's template (:mod:`geomexact.mesh3d.cuboid.cell_templates`) in one
:class:`~geomexact.mesh3d.mixed.snapshot.MixedMesh3`.

Vertex ids: the lattice's (the leaf corners, lexicographic), then the body centres of the
leaves whose template uses one, in leaf order.  Two constructions, proven equal by
``tests/mesh3d/test_octree_cells.py``:

* the reference, with a trace: from the start (the lattice's vertices, no cell), for each
  leaf in leaf order an ``add_vertex`` for its centre if it has one, then one ``add_cell``
  per cell of its template (sorted);
* without a trace, the same cells handed to the bulk builder
  (:func:`~geomexact.mesh3d.mixed.transient.mixed_mesh_from_cells`), no step checks.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable
from itertools import islice
from typing import Any, Final, Literal, get_args

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point3, point3
from geomexact.mesh3d.cuboid.boxes import box_of_extents
from geomexact.mesh3d.cuboid.cell_templates import (
    POSITIONS,
    CellTemplate,
    mixed_template,
    polyhedral_template,
    relabelled,
)
from geomexact.mesh3d.mixed.cells import Cell
from geomexact.mesh3d.mixed.recording import recorded_cells
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import validate_mixed
from geomexact.mesh3d.octree.balance import balance_two_to_one
from geomexact.mesh3d.octree.conformity import FaceConformity
from geomexact.mesh3d.octree.lattice import OctreeLattice, octree_lattice
from geomexact.mesh3d.octree.tree import Octree
from geomexact.trace.record import Trace

__all__ = [
    "CELL_FINAL_KINDS",
    "CellConformity",
    "CellFinalKind",
    "CellLeafMesh",
    "cell_conformity",
    "cell_final",
]

CellFinalKind = Literal["mixed", "polyhedral"]
CELL_FINAL_KINDS: Final[tuple[CellFinalKind, ...]] = get_args(CellFinalKind)


@attrs.frozen(slots=True, eq=False)
class CellLeafMesh:
    """What a cell final makes: the balanced ``octree``, its ``lattice``, the ``mesh``,
    each cell's leaf level (``levels``, aligned with ``mesh.cell_list()``), the points
    the templates added inside leaves (``added``), the ``templates`` used (name ->
    leaves), the distinct templates (``distinct``), the forced splits; with a trace, its
    ``start`` and ``trace``."""

    octree: Octree
    lattice: OctreeLattice
    mesh: MixedMesh3
    levels: Any
    added: int
    templates: dict[str, int]
    distinct: tuple[CellTemplate, ...]
    forced_splits: int
    start: MixedMesh3 | None = None
    trace: Trace | None = None


@attrs.frozen(slots=True, kw_only=True)
class CellConformity(FaceConformity):
    """The exact check of a cell final (:func:`cell_conformity`, :class:`FaceConformity`)
    of its ``cells``."""

    cells: int


def _templates(lattice: OctreeLattice, kind: str) -> list[CellTemplate]:
    """Each leaf's template, by row (each distinct pattern and leaf shape computed once;
    a rectilinear grid's cells have several shapes)."""
    if kind not in CELL_FINAL_KINDS:
        raise PreconditionError("octree", f"a cell final is one of {CELL_FINAL_KINDS}, "
                                f"not {kind!r}")
    octree = lattice.octree
    if octree.planes is None:
        shapes = [box_of_extents(*octree.cell_extents(0))] * len(octree.leaves)
    else:
        shapes = [box_of_extents(*octree.grid_cell_extents(leaf)) for leaf in octree.leaves]
    found: dict[tuple[int, object], CellTemplate] = {}
    templates = []
    for pattern, shape in zip(lattice.patterns.tolist(), shapes, strict=True):
        key = (pattern, shape)
        if key not in found:
            found[key] = (mixed_template(pattern, shape) if kind == "mixed"
                          else polyhedral_template(pattern, shape))
        templates.append(found[key])
    return templates


def _added_points(lattice: OctreeLattice, templates: list[CellTemplate]) -> list[Point3]:
    """The exact points the leaves' templates add, in leaf order (a template's in its
    order): half-lattice position p of a leaf of level L at corner c is the lattice
    point c * 2**(depth - L) + p * 2**(depth - L - 1)."""
    rows = [row for row, template in enumerate(templates) if template.points]
    if not rows:
        return []
    cells = np.array(lattice.octree.leaves, dtype=np.int64).reshape(-1, 4)[rows].tolist()
    found = []
    for (level, *corner), row in zip(cells, rows, strict=True):
        half = 1 << (lattice.depth - level - 1)
        for position in templates[row].points:
            found.append(point3(*(lattice.coordinate(axis, 2 * half * corner[axis]
                                                     + half * position[axis])
                                  for axis in range(3))))
    return found


def cell_final(octree: Octree, kind: CellFinalKind, trace: bool = False) -> CellLeafMesh:
    """The ``kind`` final of ``octree`` (balanced 2:1 first; the splits that took are
    reported), by the reference steps with ``trace``, else by the bulk builder."""
    balanced = balance_two_to_one(octree)
    lattice = octree_lattice(balanced)
    templates = _templates(lattice, kind)
    points = lattice.exact_points()
    added = _added_points(lattice, templates)
    next_id = iter(range(len(points), len(points) + len(added)))
    leaves: list[tuple[int, tuple[Cell, ...]]] = []
    for codes, template in zip(lattice.codes.tolist(), templates, strict=True):
        ids = [*codes, *(next(next_id) for _ in template.points)]
        leaves.append((len(template.points),
                       tuple(sorted(relabelled(cell, ids) for cell in template.cells))))
    forced = (balanced.leaf_count - octree.leaf_count) // 7
    start = recorded = None
    if trace:
        new_points = iter(added)
        start, mesh, recorded = recorded_cells(
            points, ((list(islice(new_points, count)), cells) for count, cells in leaves),
            {"algorithm": "octree", "final": kind})
    else:
        mesh = mixed_mesh_from_cells([*points, *added],
                                     (cell for _, cells in leaves for cell in cells))
    level_of = {cell: leaf[0] for leaf, (_, cells) in zip(balanced.leaves, leaves, strict=True)
                for cell in cells}
    levels = np.array([level_of[cell] for cell in mesh.cell_list()], dtype=np.int64)
    levels.setflags(write=False)
    used = Counter(template.name for template in templates)
    return CellLeafMesh(balanced, lattice, mesh, levels, len(added), dict(sorted(used.items())),
                        tuple(dict.fromkeys(templates)), forced, start, recorded)


def cell_conformity(mesh: MixedMesh3, volume: Rational,
                    templates: Iterable[CellTemplate] | None = None) -> CellConformity:
    """The exact validation of ``mesh`` (:func:`~geomexact.mesh3d.mixed.validation.
    validate_mixed`, the volume ``volume``).  Given the ``templates`` its leaves used,
    each is validated once in the half-lattice cube (every leaf is its image by a
    translation and a positive diagonal scaling, which keeps faces planar and convex,
    cells convex and volumes positive), and the mesh without the per-cell geometry: the
    same verdict, several times faster."""
    problems: list[object] = []
    if templates is not None:
        for template in dict.fromkeys(templates):
            shown = mixed_mesh_from_cells([*POSITIONS, *template.points], template.cells)
            problems += [f"template {template.name} {template.cells}: {problem}"
                         for problem in validate_mixed(shown, volume=8, check_digest=False)]
    problems += validate_mixed(mesh, volume=volume, check_digest=False,
                               cell_geometry=templates is None)
    return CellConformity(cells=mesh.cell_count, interior_faces=len(mesh.interior_faces()),
                          boundary_faces=len(mesh.boundary_faces()),
                          problems=tuple(map(str, problems)))
