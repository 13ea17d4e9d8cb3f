"""A 1-irregular cuboid as one step of a larger mesh: ``insert_cuboid`` adds the partition of
an axis-aligned box whose corners and Steiner points are existing vertices (an octree
leaf), with the tetrahedra of :func:`~geomexact.mesh3d.cuboid.partition.partition_cuboid`
(conforming order) mapped to those vertices.

The partition in *point codes* (corner k: k; Steiner point of bit i: 8 + i) depends only on
the pattern and the template: the conforming order sorts the Steiner points
lexicographically, which no translation or positive per-axis scaling changes, and a split
only bisects.  The flips of the improvement also depend on the box's shape (insphere is not
invariant under per-axis scaling).  :func:`partition_codes` computes it once per key, by
the compiled cuboid kernel when it is built and can take the shape (proven equal to the
reference in ``tests/mesh3d/test_cuboid_kernel.py``), else by the reference.
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache
from typing import Any, Final

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid import compiled
from geomexact.mesh3d.cuboid.boxes import Box, unit_cube
from geomexact.mesh3d.cuboid.numbering import BIT_COUNT
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.cuboid.split_order import split_sequence
from geomexact.mesh3d.cuboid.templates import check_template
from geomexact.mesh3d.ops import step_ints
from geomexact.mesh3d.transient import Transient3
from geomexact.trace.step import Step

__all__ = ["ABSENT", "CodedPartition", "insert_cuboid_in", "partition_codes"]

ABSENT: Final = -1
"""The vertex id of a Steiner point that is not in the pattern."""


@attrs.frozen(slots=True, eq=False)
class CodedPartition:
    """A cuboid partition in point codes: ``tetrahedra`` (T x 4 read-only int array, each
    positive on any box) and the improvement's ``flips`` (op, sorted code triple), in the
    order applied (empty without the improvement)."""

    pattern: int
    template: int
    tetrahedra: Any
    flips: tuple[tuple[str, tuple[int, ...]], ...]


@lru_cache(maxsize=1 << 16)
def partition_codes(pattern: int, template: int, shape: Box | None = None,
                    improve: bool = False) -> CodedPartition:
    """The partition of ``pattern`` from ``template`` in the conforming order, in point
    codes; with ``improve``, Joe's flips inside the box of ``shape`` (boundary flips off).
    ``shape`` matters only for the improvement (default: the unit cube)."""
    check_template(template)
    box = shape if shape is not None and improve else unit_cube()
    sequence = split_sequence(pattern, box, "conforming")
    local_to_code = np.array(list(range(8)) + [8 + bit for bit in sequence], dtype=np.int64)
    if compiled.unsupported(box) is None:
        run = compiled.run_compiled(pattern, box, template=template, improve=improve)
        tetrahedra: Sequence[Sequence[int]] = run.tetrahedra
        steps: Sequence[Step] = run.steps
    else:
        reference = partition_cuboid(pattern, box, template=template, improve=improve)
        tetrahedra = reference.mesh.tetrahedra()
        steps = reference.trace.steps
    codes = local_to_code[np.array(tetrahedra, dtype=np.int64).reshape(-1, 4)]
    codes.setflags(write=False)
    flips = tuple(
        (step.op, tuple(sorted(int(local_to_code[int(v)]) for v in step.args)))  # type: ignore[call-overload]
        for step in steps if step.op != "split_tetra"
    )
    return CodedPartition(pattern, template, codes, flips)


def apply_insert_cuboid(t: Transient3, step: Step) -> None:
    """The ``insert_cuboid`` entry of the 3D step table (template, 8 corners, 18
    points)."""
    values = step_ints(step, 27)
    insert_cuboid_in(t, values[0], values[1:9], values[9:])


def insert_cuboid_in(t: Transient3, template: int, corners: Sequence[int],
                     steiner: Sequence[int]) -> None:
    """Add the partition of the box whose corner k is vertex ``corners[k]`` and whose
    Steiner point of bit i is vertex ``steiner[i]`` (:data:`ABSENT` when not in the
    pattern), and record the step.  :class:`PreconditionError` unless the corners form an
    axis-aligned box in the numbering's order, each Steiner vertex is exactly at its
    point, and the box's space is free (no face of it already has a tetrahedron on that
    side)."""
    op = "insert_cuboid"
    check_template(template)
    if len(corners) != 8 or len(steiner) != BIT_COUNT:
        raise PreconditionError(op, f"a cuboid has 8 corners and {BIT_COUNT} Steiner slots, "
                                f"not {len(corners)} and {len(steiner)}")
    count = t.vertex_count
    if not all(0 <= v < count for v in corners) or not all(
            v == ABSENT or 0 <= v < count for v in steiner):
        raise PreconditionError(op, f"a vertex id is outside 0..{count - 1}")
    low, high = t.point(corners[0]), t.point(corners[7])
    try:
        box = Box(low[:3], high[:3])
    except PreconditionError:
        raise PreconditionError(op, f"corners 0 and 7 ({corners[0]}, {corners[7]}) are not "
                                "the low and high corners of a box") from None
    for k, vertex in enumerate(corners):
        if t.point(vertex) != box.corner(k):
            raise PreconditionError(op, f"vertex {vertex} is not corner {k} of the box")
    pattern = 0
    for bit, vertex in enumerate(steiner):
        if vertex == ABSENT:
            continue
        if t.point(vertex) != box.steiner_point(bit):
            raise PreconditionError(op, f"vertex {vertex} is not the Steiner point of bit "
                                    f"{bit}")
        pattern |= 1 << bit
    ids = [*corners, *steiner]
    for tetrahedron in partition_codes(pattern, template).tetrahedra.tolist():
        t.add_tetrahedron(*(ids[code] for code in tetrahedron))
    t.record(Step(op, (template, *corners, *steiner)))
