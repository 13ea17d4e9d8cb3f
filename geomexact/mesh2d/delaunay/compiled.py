"""The compiled Delaunay construction: glue between
:func:`geomexact.mesh2d.delaunay.triangulation.triangulate_points` and the typed kernel
:mod:`geomexact.mesh2d.delaunay.delaunay_kernel` (a Cython extension, optional).

``run_compiled(points, start, first, rest)`` runs what ``ReferenceDelaunay`` runs —
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

from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.engine_names import compiled_kernel
from geomexact.mesh2d.snapshot import Mesh2, TableSource
from geomexact.trace.deferred import deferred_trace
from geomexact.trace.step import Step

__all__ = ["AVAILABLE", "CompiledConstrained", "CompiledConstruction", "open_builder",
           "run_compiled", "run_compiled_constrained", "shuffled_ids"]


_delaunay_kernel: Any = compiled_kernel("geomexact.mesh2d.delaunay.delaunay_kernel")

AVAILABLE: bool = _delaunay_kernel is not None
"""True when the extension is built and importable."""


@attrs.frozen(slots=True)
class CompiledConstruction:
    """What ``triangulate_points`` needs from a run: the sealed mesh, the steps and the
    digest after each step."""

    mesh: Mesh2
    steps: Sequence[Step]
    digests: Sequence[int]


def open_builder(points: Sequence[Point2]) -> Any:
    """The kernel's builder on ``points`` (the ``Point2`` of every vertex id), or None
    when the kernel is not built.  Its ``vertex_hashes`` give the start mesh's digest
    (:func:`~geomexact.mesh2d.delaunay.triangulation.vertices_mesh`) before it runs."""
    return None if _delaunay_kernel is None else _delaunay_kernel.Builder(points)


def shuffled_ids(count: int, seed: int) -> Any:
    """``random.Random(seed).shuffle(list(range(count)))`` made by the kernel (the same
    Mersenne Twister words and swaps, tested equal) as an int64 array, or None when it is
    not built or ``count`` is beyond it."""
    if _delaunay_kernel is None or count >= 1 << 31:
        return None
    return _delaunay_kernel.shuffled_ids(count, seed)


def run_compiled(
    builder: Any,
    start: Mesh2,
    first: tuple[int, int, int],
    rest: Sequence[int],
) -> CompiledConstruction:
    """The incremental Delaunay construction in the kernel's ``builder``
    (:func:`open_builder` on the points of ``start``): ``start`` is the mesh of isolated
    vertices (its digest starts the run, the result is ``start`` with the triangles);
    ``first``: the vertices of ``make_triangle``; ``rest``: the vertices inserted after,
    in order."""
    builder.begin(start.digest)
    builder.run(first[0], first[1], first[2], rest)
    halfedges, hints, triangle_count, digest = builder.finish()
    mesh = _built_mesh(start, builder.points, halfedges, hints, triangle_count, digest,
                       start.segments)
    return CompiledConstruction(mesh, *deferred_trace(builder))


def _built_mesh(start: Mesh2, points: Sequence[Point2], halfedges: Any, hints: Any,
                triangle_count: int, digest: int, segments: Any) -> Mesh2:
    """``start`` with the kernel's final arrays: its tables are built from them on first
    use (:class:`TableSource`)."""
    return attrs.evolve(
        start,
        halfedges=None,
        outgoing=None,
        segments=segments,
        triangle_count=triangle_count,
        digest=digest,
        source=TableSource(points, halfedges, hints, start),
    )


@attrs.frozen(slots=True)
class CompiledConstrained:
    """What ``triangulate`` needs from a constrained run in the kernel: the sealed mesh,
    the steps (the point triangulation's, then segment recovery, the Lawson pass and
    carving) with the digest after each, and the indices of the hole seeds in no
    triangle."""

    mesh: Mesh2
    steps: Sequence[Step]
    digests: Sequence[int]
    ignored_holes: tuple[int, ...]


INT64 = range(-(1 << 63), 1 << 63)


def run_compiled_constrained(
    builder: Any,
    start: Mesh2,
    first: tuple[int, int, int],
    rest: Sequence[int],
    segments: Sequence[tuple[int, int, int]],
    *,
    split_segments: bool,
    carve_exterior: bool,
    holes: Sequence[Point2],
) -> CompiledConstrained | None:
    """The constrained Delaunay triangulation in the kernel: ``run_compiled``'s point
    triangulation, then each of ``segments`` (``(u, v, marker)``, duplicates remapped)
    recovered in order, the Lawson pass, the exterior carved (when ``carve_exterior`` and
    it is not empty) and each hole carved — what ``triangulate`` runs on a transient,
    step for step, in the kernel's ``builder`` (:func:`open_builder`).  None when the
    kernel declines: a marker beyond int64, a crossing point to insert
    (``split_segments``), a :class:`SegmentError` to raise; then the caller runs the
    reference ops (and raises there)."""
    if any(marker not in INT64 for _, _, marker in segments):
        return None
    builder.begin(start.digest)
    builder.run(first[0], first[1], first[2], rest)
    builder.begin_constrained()
    if builder.recover(segments, split_segments) != _delaunay_kernel.RECOVERED:  # type: ignore[union-attr]
        return None
    builder.lawson()
    if carve_exterior:
        builder.carve_exterior()
    ignored = []
    for index, hole in enumerate(holes):
        seed = point2(hole.x, hole.y)
        if builder.carve(seed, (seed.x, seed.y)) < 0:
            ignored.append(index)
    halfedges, hints, segment_map, triangle_count, digest = builder.finish_constrained()
    mesh = _built_mesh(start, builder.points, halfedges, hints, triangle_count, digest,
                       segment_map)
    return CompiledConstrained(mesh, *deferred_trace(builder), tuple(ignored))
