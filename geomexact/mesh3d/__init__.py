"""Tetrahedral meshes: the :class:`~geomexact.mesh3d.snapshot.Mesh3` snapshot and its
transient, the reference steps (``split_tetra``, Joe's flips, ``insert_cuboid``) in
``ops``, ``validation``, ``measures`` and ``quality``; ``cuboid/`` partitions 1-irregular
cuboids and runs their census; ``octree/`` is the octree mesher built on them
(``docs/design.md``); ``mixed/`` holds meshes of mixed cells (hexahedra, wedges, pyramids,
tetrahedra, convex polyhedra: ``specs/mixed.md``)."""

from __future__ import annotations

from typing import Any

from geomexact.mesh3d.ops import OPERATIONS as _OPERATIONS
from geomexact.mesh3d.snapshot import Mesh3 as _Mesh3
from geomexact.mesh3d.transient import Transient3 as _Transient3
from geomexact.trace.protocols import MeshKind as _MeshKind
from geomexact.trace.protocols import bind_kind as _bind_kind
from geomexact.trace.step import Step as _Step


def _insert_cuboid(t: _Transient3, step: _Step) -> None:
    """The ``insert_cuboid`` step (``cuboid/insertion``, loaded on its first use)."""
    from geomexact.mesh3d.cuboid.insertion import apply_insert_cuboid

    apply_insert_cuboid(t, step)


def _bulk_digest(points: Any, rows: Any) -> int | None:
    """The cuboid kernel's digest of a mesh given in bulk (None where it is not built)."""
    from geomexact.mesh3d.cuboid.compiled import bulk_digest

    return bulk_digest(points, rows)


# The tetrahedral mesh kind, bound here, above the modules it joins: the snapshot reaches
# its transient, the step table (with insert_cuboid, which builds on ops) and the compiled
# bulk digest through it; none of them imports a module built on it (tests/architecture).
_bind_kind(_Mesh3, _MeshKind(_Transient3, {**_OPERATIONS, "insert_cuboid": _insert_cuboid},
                             bulk_digest=_bulk_digest))
