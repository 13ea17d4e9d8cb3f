"""The final mesh of an octree: every leaf partitioned into tetrahedra by its Steiner
pattern (``mesh3d/cuboid``), optionally improved by Joe's flips inside the leaf.

Two implementations, proven equal by ``tests/mesh3d/test_octree.py``:

* the reference, :func:`octree_trace`: from the start snapshot (the vertices alone,
  :func:`octree_start_mesh`), one ``insert_cuboid`` step per leaf (in leaf order), then,
  for the Delaunay variant, each leaf's flips (``flip23`` ...) in leaf order -- a
  replayable trace;
* the fast assembly, :func:`assemble_tetrahedra`: each distinct (pattern, template) is
  partitioned once (:func:`~geomexact.mesh3d.cuboid.insertion.partition_codes`) and its
  tetrahedra, in point codes, are mapped to the vertex ids of every leaf with that
  pattern at once (numpy).
"""

from __future__ import annotations

from typing import Any, Final, Literal, get_args

import numpy as np

from geomexact._version import __version__
from geomexact.errors import PreconditionError
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents
from geomexact.mesh3d.cuboid.insertion import CodedPartition, insert_cuboid_in, partition_codes
from geomexact.mesh3d.octree.lattice import OctreeLattice
from geomexact.mesh3d.ops import flip_in
from geomexact.mesh3d.snapshot import Mesh3, empty_mesh3
from geomexact.mesh3d.transient import Transient3
from geomexact.trace.record import Trace

__all__ = [
    "FINAL_KINDS",
    "FinalKind",
    "assemble_tetrahedra",
    "octree_start_mesh",
    "octree_trace",
]

FinalKind = Literal["patterns", "delaunay"]
FINAL_KINDS: Final[tuple[FinalKind, ...]] = get_args(FinalKind)


def _check_kind(kind: str) -> None:
    if kind not in FINAL_KINDS:
        raise PreconditionError("octree", f"the final mesh is one of {FINAL_KINDS}, not "
                                f"{kind!r}")


def _shape_box(lattice: OctreeLattice) -> Box:
    """A box of the leaves' shape (every leaf is one, scaled by a power of two); the
    Delaunay final needs one shape, so not a rectilinear grid's."""
    if lattice.octree.planes is not None:
        raise PreconditionError("octree", "the delaunay final needs equal grid cells; a "
                                "rectilinear grid takes the patterns, mixed or polyhedral "
                                "final")
    return box_of_extents(*lattice.octree.cell_extents(0))


def _coded(lattice: OctreeLattice, pattern: int, template: int, kind: str) -> CodedPartition:
    if kind == "delaunay":
        return partition_codes(pattern, template, _shape_box(lattice), True)
    return partition_codes(pattern, template)


def _groups(lattice: OctreeLattice) -> dict[tuple[int, int], Any]:
    """(pattern, template) -> the rows of the leaves that have it, increasing."""
    combined = lattice.patterns * 2 + lattice.templates
    order = np.argsort(combined, kind="stable")
    values, starts = np.unique(combined[order], return_index=True)
    bounds = [*starts.tolist(), len(order)]
    return {(int(v) >> 1, int(v) & 1): order[bounds[n]:bounds[n + 1]]
            for n, v in enumerate(values.tolist())}


def assemble_tetrahedra(lattice: OctreeLattice, kind: FinalKind = "patterns") -> Any:
    """The final tetrahedra (T x 4 global vertex ids, each positive), leaf group by leaf
    group ((pattern, template) increasing, leaves in order within a group)."""
    _check_kind(kind)
    blocks = [lattice.codes[rows][:, _coded(lattice, pattern, template, kind).tetrahedra]
              .reshape(-1, 4)
              for (pattern, template), rows in _groups(lattice).items()]
    return np.concatenate(blocks) if blocks else np.zeros((0, 4), dtype=np.int64)


def octree_start_mesh(lattice: OctreeLattice) -> Mesh3:
    """The snapshot an octree trace starts from: every vertex (ids as in the lattice: the
    leaf corners in lexicographic order of their exact points), no tetrahedron."""
    t = Transient3(empty_mesh3())
    for point in lattice.exact_points():
        t.add_vertex(point)
    return t.seal()


def octree_trace(lattice: OctreeLattice, kind: FinalKind = "patterns",
                 parameters: dict[str, Any] | None = None) -> tuple[Mesh3, Mesh3, Trace]:
    """(start, final mesh, trace) by the reference steps: ``insert_cuboid`` for each leaf
    in leaf order, then (Delaunay) each leaf's flips in leaf order."""
    _check_kind(kind)
    start = octree_start_mesh(lattice)
    t = start.transient()
    codes = lattice.codes.tolist()
    rows = list(zip(lattice.patterns.tolist(), lattice.templates.tolist(), codes,
                    strict=True))
    for _, template, ids in rows:
        insert_cuboid_in(t, template, ids[:8], ids[8:])
    if kind == "delaunay":
        for pattern, template, ids in rows:
            for op, face in _coded(lattice, pattern, template, kind).flips:
                flip_in(t, op, tuple(sorted(ids[code] for code in face)))  # type: ignore[arg-type]
    trace = Trace(start.digest, t.steps, t.step_digests, parameters, __version__)
    return start, t.seal(), trace

