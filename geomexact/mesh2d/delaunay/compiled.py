"""The compiled Delaunay construction: glue between
:func:`geomexact.mesh2d.delaunay.triangulation.triangulate_points` and the typed kernel
:mod:`geomexact.mesh2d.delaunay.delaunay_kernel` (a Cython extension, optional).

``run_compiled(points, start, first, rest)`` runs what ``BatchDelaunay`` runs —
``make_triangle(*first)`` then ``insert(v)`` for each ``v`` of ``rest`` — and returns a
:class:`CompiledConstruction` with the same steps, the same digest after every step and
the same final ``Mesh2`` (``outgoing`` hints included), or None when the kernel is not
built.  ``triangulate_points(..., engine="auto")`` uses it whenever it is built, and the
Python engine otherwise; ``engine="compiled"`` uses it or raises
:class:`~geomexact.errors.PreconditionError`; ``engine="python"`` never uses it (the tests
compare them).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import attrs

from geomexact.kernel.points import Point2
from geomexact.mesh2d.engine_names import compiled_kernel
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.trace.step import Step

__all__ = ["AVAILABLE", "CompiledConstruction", "run_compiled"]


_delaunay_kernel: Any = compiled_kernel("geomexact.mesh2d.delaunay.delaunay_kernel")

AVAILABLE: bool = _delaunay_kernel is not None
"""True when the extension is built and importable."""


@attrs.frozen(slots=True)
class CompiledConstruction:
    """What ``triangulate_points`` needs from a run: the sealed mesh, the steps and the
    digest after each step."""

    mesh: Mesh2
    steps: list[Step]
    digests: list[int]


def run_compiled(
    points: Sequence[Point2],
    start: Mesh2,
    first: tuple[int, int, int],
    rest: Sequence[int],
) -> CompiledConstruction | None:
    """The incremental Delaunay construction in the kernel, or None when it is not built.

    ``points``: the ``Point2`` of every vertex id; ``start``: the mesh of isolated vertices
    (its digest starts the run, the result is ``start`` with the triangles);
    ``first``: the vertices of ``make_triangle``; ``rest``: the vertices inserted after,
    in order.  The kernel refuses a run that would exceed its internal counters (about
    2**31 half-edge insertions) with ``OverflowError``; then this returns None too."""
    if _delaunay_kernel is None:
        return None
    builder = _delaunay_kernel.Builder(points, start.digest)
    try:
        builder.run(first[0], first[1], first[2], rest)
    except OverflowError:
        return None
    halfedges, outgoing, triangle_count, digest = builder.finish()
    mesh = attrs.evolve(
        start,
        halfedges=halfedges,
        outgoing=outgoing,
        triangle_count=triangle_count,
        digest=digest,
    )
    return CompiledConstruction(mesh, builder.steps(), builder.digests())
