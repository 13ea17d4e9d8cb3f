"""Fitting the octree's tetrahedra to a closed surface (issue 24; ``specs/domain.md``).

Given tetrahedra that cover a box around a closed, outward-oriented surface
(:class:`~geomexact.mesh3d.surface.value.TriangleSurface`), :func:`fit_to_surface` keeps
the part inside it, exactly:

1. **Sides.**  Every vertex is inside, on or outside the surface.  Tetrahedra whose
   bounding box meets no triangle's are *clean*: their vertices share a side, so each
   connected region of clean tetrahedra is classified by one exact ray.  Along each
   remaining edge the side flips with each proper crossing (exact
   :meth:`~geomexact.mesh3d.surface.queries.SurfaceIndex.segment_hits`); a vertex no
   clean path reaches gets its own ray.  A vertex exactly on a triangle is *on*.
2. **Cut points.**  On every edge from an inside vertex to an outside one, the first point
   of the surface from the inside end: a rational point exactly on a triangle.
   A tetrahedron whose four vertices are all on the surface is kept when its centre is
   inside.
3. **Warping.**  A vertex whose first surface point along one of its crossing edges is
   within :data:`WARP_FRACTION` of the edge is moved there (Labelle and Shewchuk's
   isosurface stuffing), when every tetrahedron around it stays positive; this removes
   the slivers that cut points next to a vertex make.  A warp that pinches the domain
   is undone.
4. **Pieces.**  Each tetrahedron keeps the convex hull of its inside and on vertices and
   its cut points.  Its parts on the tetrahedron's faces are cut by one rule that reads
   only the face (fans from the least vertex id; cut points numbered after the lattice),
   so neighbouring pieces meet face to face; the piece is the cones from its least
   inside-or-on vertex over its faces that do not contain it, the cut surface (a
   triangle or a quad, not on any other piece) fanned from whichever diagonal keeps every
   cone positive.  Every tetrahedron made is checked positive by exact ``orient3d``; a
   piece with no positive fan is reported (``unfit``), never kept inverted.

The boundary of the result is made of faces whose vertices are cut points and on
vertices: every boundary vertex lies exactly on the surface.  The faces between them are
chords of the surface, so the mesh's volume approaches the enclosed volume as the
tetrahedra near the surface shrink (measured in the tests)."""

from __future__ import annotations

from collections import deque
from collections.abc import Sequence
from typing import Any, Final

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point3, point3
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.surface.queries import INSIDE, ON, OUTSIDE, SurfaceIndex
from geomexact.mesh3d.transient import mesh3_from_positive_arrays
from geomexact.mesh3d.validation import manifold_violations

__all__ = ["SurfaceFit", "fit_to_surface"]


@attrs.frozen(slots=True, eq=False)
class SurfaceFit:
    """The result of :func:`fit_to_surface`: the ``mesh`` of the domain (its vertices: the
    kept lattice vertices in id order, then the cut points in edge order), how many of
    its vertices are ``cut_points``, the ids of its ``surface_vertices`` (cut points and
    lattice vertices exactly on the surface), ``sides`` (lattice vertex -> INSIDE, ON or
    OUTSIDE), ``rays`` (exact rays cast) and ``unfit`` (the input tetrahedra whose piece
    had no positive fan: 0 in a valid fit), how many lattice vertices were ``warped``
    onto the surface, the ``pinches`` left (where the domain is thinner than the
    tetrahedra: two parts meeting at an edge or a vertex) and, for each mesh vertex that
    is a lattice vertex, its lattice id (``lattice_ids``, the first ones)."""

    mesh: Mesh3
    cut_points: int
    surface_vertices: tuple[int, ...]
    sides: Any
    rays: int
    unfit: tuple[int, ...]
    warped: int = 0
    pinches: tuple[str, ...] = ()
    lattice_ids: tuple[int, ...] = ()


def _clean_tetrahedra(points: Sequence[Point3], tetrahedra: Any, index: SurfaceIndex) -> Any:
    """A boolean per tetrahedron: its bounding box (doubles rounded outward) meets no
    bucket that holds a triangle (a conservative test: every clean one is clean)."""
    coordinates = np.array([[p.fx, p.fy, p.fz] for p in points], dtype=np.float64)
    corners = coordinates[tetrahedra]
    low = np.nextafter(corners.min(axis=1), -np.inf)
    high = np.nextafter(corners.max(axis=1), np.inf)
    shape = np.array(index.shape)
    occupied = np.zeros(tuple(shape), dtype=np.int64)
    for cell in index.buckets:
        occupied[cell] = 1
    table = np.zeros(tuple(shape + 1), dtype=np.int64)
    table[1:, 1:, 1:] = occupied.cumsum(0).cumsum(1).cumsum(2)

    def bucket(values: Any, rounding: Any) -> Any:
        cells = rounding((values - index.origin) / index.step).astype(np.int64)
        return cells

    first = bucket(low, np.floor)
    last = bucket(high, np.floor)
    outside = ((last < 0) | (first >= shape)).any(axis=1)
    first = np.clip(first, 0, shape - 1)
    last = np.clip(last, 0, shape - 1) + 1
    x0, y0, z0 = first.T
    x1, y1, z1 = last.T
    count = (table[x1, y1, z1] - table[x0, y1, z1] - table[x1, y0, z1] - table[x1, y1, z0]
             + table[x0, y0, z1] + table[x0, y1, z0] + table[x1, y0, z0] - table[x0, y0, z0])
    return outside | (count == 0)


def _components(vertex_count: int, edges: Any) -> Any:
    """A label per vertex: the least vertex id of its connected component (``edges``:
    (m, 2) ids), by label propagation."""
    labels = np.arange(vertex_count, dtype=np.int64)
    if len(edges) == 0:
        return labels
    u, v = edges[:, 0], edges[:, 1]
    while True:
        low = np.minimum(labels[u], labels[v])
        before = labels.copy()
        np.minimum.at(labels, u, low)
        np.minimum.at(labels, v, low)
        labels = labels[labels]  # jump to the label's label
        if np.array_equal(labels, before):
            return labels


_TETRAHEDRON_EDGES = ((0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3))
_FACES = ((1, 2, 3), (0, 3, 2), (0, 1, 3), (0, 2, 1))
"""The outward faces of a positive tetrahedron (a, b, c, d), by position."""


def _dirty_neighbours(tetrahedra: Any, clean: Any) -> dict[int, set[int]]:
    """Each vertex of a tetrahedron that is not clean -> its neighbours along the edges
    of such tetrahedra."""
    neighbours: dict[int, set[int]] = {}
    for i, j in _TETRAHEDRON_EDGES:
        for u, v in tetrahedra[~clean][:, [i, j]].tolist():
            neighbours.setdefault(u, set()).add(v)
            neighbours.setdefault(v, set()).add(u)
    return neighbours


def _sides(points: Sequence[Point3], tetrahedra: Any, clean: Any,
           index: SurfaceIndex) -> tuple[Any, int]:
    """(side per vertex, rays cast)."""
    count = len(points)
    used = np.zeros(count, dtype=bool)
    used[tetrahedra.ravel()] = True
    clean_edges = np.concatenate([tetrahedra[clean][:, [i, j]]
                                  for i, j in _TETRAHEDRON_EDGES]) if clean.any() else (
        np.zeros((0, 2), dtype=np.int64))
    labels = _components(count, clean_edges)
    sides = np.full(count, 2, dtype=np.int64)  # 2: not known yet
    in_clean = np.zeros(count, dtype=bool)
    in_clean[tetrahedra[clean].ravel()] = True
    rays = 0
    for label in np.unique(labels[in_clean]).tolist():
        side = index.side(points[label])
        rays += 1
        sides[(labels == label) & in_clean] = side
    neighbours = _dirty_neighbours(tetrahedra, clean)
    for vertex in neighbours:
        if sides[vertex] == 2 and index.on_surface(points[vertex]):
            sides[vertex] = ON
    queue = deque(v for v in sorted(neighbours) if sides[v] in (INSIDE, OUTSIDE))
    while True:
        while queue:
            u = queue.popleft()
            for v in sorted(neighbours[u]):
                if sides[v] != 2:
                    continue
                hits = index.segment_hits(points[u], points[v])
                if all(hit.proper for hit in hits):
                    sides[v] = sides[u] * (-1) ** len(hits)
                    queue.append(v)
        unknown = [v for v in sorted(neighbours) if sides[v] == 2]
        if not unknown:
            break
        sides[unknown[0]] = index.side(points[unknown[0]])
        rays += 1
        if sides[unknown[0]] != ON:
            queue.append(unknown[0])
    sides[~used] = OUTSIDE
    return sides, rays


def _warped(points: list[Point3], tetrahedra: Any, clean: Any, sides: dict[int, int],
            index: SurfaceIndex, fraction: Rational, frozen: set[int]) -> set[int]:
    """Snap lattice vertices to the surface (Labelle and Shewchuk's warping): a vertex
    whose first surface point along one of its crossing edges lies within ``fraction`` of
    the edge from it moves there (the nearest such point), and becomes *on*, when every
    tetrahedron around it stays positive (exact ``orient3d``).  Vertices in id order, not
    the ``frozen`` ones; ``points`` and ``sides`` are updated in place.  Returns the
    vertices moved."""
    neighbours = _dirty_neighbours(tetrahedra, clean)
    order = np.argsort(tetrahedra.ravel(), kind="stable")
    owners = order // 4
    starts = np.searchsorted(tetrahedra.ravel()[order], np.arange(len(points) + 1))
    moved: set[int] = set()
    for v in sorted(neighbours):
        if sides[v] == ON or v in frozen:
            continue
        best: tuple[Rational, Point3] | None = None
        for w in sorted(neighbours[v]):
            if sides[v] * sides[w] != -1:
                continue
            hits = index.segment_hits(points[v], points[w])
            if hits and hits[0].t < fraction and (best is None or hits[0].t < best[0]):
                start, end = points[v], points[w]
                t = hits[0].t
                best = (t, point3(*(start[a] + t * (end[a] - start[a]) for a in range(3))))
        if best is None:
            continue
        around = tetrahedra[owners[starts[v]:starts[v + 1]]].tolist()
        target = best[1]

        def at(u: int, target: Point3 = target, v: int = v) -> Point3:
            return target if u == v else points[u]

        if all(orient3d(*(at(u) for u in tetrahedron)) > 0 for tetrahedron in around):
            points[v] = target
            sides[v] = ON
            moved.add(v)
    return moved


def _cut_point(index: SurfaceIndex, inside: Point3, outside: Point3) -> Point3:
    hits = index.segment_hits(inside, outside)
    if not hits:  # pragma: no cover - the sides differ, so the segment meets the surface
        raise PreconditionError("fit_to_surface", f"the edge {inside}-{outside} changes "
                                "side without meeting the surface")
    t = hits[0].t
    return point3(*(inside[a] + t * (outside[a] - inside[a]) for a in range(3)))


def _face_part(face: Sequence[int], sides: dict[int, int],
               cuts: dict[tuple[int, int], int]) -> list[int]:
    """The part of a tetrahedron face (outward vertex cycle) inside the surface: its
    inside and on vertices and its cut points, in the face's order."""
    part = []
    for position, u in enumerate(face):
        v = face[(position + 1) % 3]
        if sides[u] != OUTSIDE:
            part.append(u)
        cut = cuts.get((min(u, v), max(u, v)))
        if cut is not None:
            part.append(cut)
    return part


def _fan(polygon: Sequence[int]) -> list[tuple[int, int, int]]:
    """A polygon's triangles: the fan from its least id (the rule both sides share)."""
    start = polygon.index(min(polygon))
    ring = [*polygon[start:], *polygon[:start]]
    return [(ring[0], ring[i], ring[i + 1]) for i in range(1, len(ring) - 1)]


def _piece(tetrahedron: Sequence[int], sides: dict[int, int],
           cuts: dict[tuple[int, int], int], point: Any
           ) -> list[tuple[int, int, int, int]] | None:
    """The positive tetrahedra of one tetrahedron's inside piece, or None when no fan of
    its cut surface keeps every cone positive."""
    kept = [v for v in tetrahedron if sides[v] != OUTSIDE]
    apex = min(kept)
    parts = [_face_part([tetrahedron[i] for i in face], sides, cuts) for face in _FACES]
    on_tetra_edges: set[tuple[int, int]] = set()
    for part in parts:
        if len(part) < 3:
            continue  # a face touching the surface at a vertex or an edge: no area
        for i, u in enumerate(part):
            on_tetra_edges.add((u, part[(i + 1) % len(part)]))
    # the cut surface: the parts' edges that are not matched by a reversed edge
    rim = {(u, v) for (u, v) in on_tetra_edges if (v, u) not in on_tetra_edges}
    cycle: list[int] = []
    if rim:
        following = {v: u for (u, v) in rim}  # reversed: the cut face points out of it
        start = min(following)
        cycle = [start]
        while following[cycle[-1]] != start and len(cycle) <= len(following):
            cycle.append(following[cycle[-1]])
    fixed = [triangle for part in parts if len(part) >= 3 and apex not in part
             for triangle in _fan(part)]
    options = [cycle[i:] + cycle[:i] for i in range(min(2, len(cycle)))] if cycle else [[]]
    for option in options:
        cut_triangles = ([(option[0], option[i], option[i + 1])
                          for i in range(1, len(option) - 1)] if option else [])
        cones = [(a, c, b, apex) for a, b, c in [*fixed, *cut_triangles]
                 if apex not in (a, b, c)]
        if all(orient3d(*(point(v) for v in cone)) > 0 for cone in cones):
            return cones
    return None


WARP_FRACTION: Final = mpq(1, 3)
"""How near a vertex must be to the surface, as a fraction of an edge, to be snapped onto
it (Labelle and Shewchuk use 0.24657 and 0.41391 for the BCC lattice's long and short
edges; on the octree's pattern tetrahedra 1/3 gave the widest angles on spot and fandisk:
minimum dihedral 10°–16° against 8° at 1/4, 2° at 2/5 and 0.1° unwarped)."""


def fit_to_surface(points: Sequence[Point3], tetrahedra: Any, index: SurfaceIndex, *,
                   warp: Rational | None = WARP_FRACTION) -> SurfaceFit:
    """The tetrahedra (positive, (T, 4) ids into ``points``, covering a box that holds the
    closed outward surface of ``index`` strictly inside) cut to the surface's inside
    (module docstring); with ``warp``, vertices that near to the surface are first
    snapped onto it (:func:`_warped`).  A warp that pinches the domain (two parts of it
    meeting only along an edge or at a vertex) is undone and the fit made again; a pinch
    that no warp made is reported (``pinches``)."""
    tetrahedra = np.asarray(tetrahedra, dtype=np.int64).reshape(-1, 4)
    clean = _clean_tetrahedra(points, tetrahedra, index)
    sides_array, rays = _sides(points, tetrahedra, clean, index)
    frozen: set[int] = set()
    while True:
        sides = dict(enumerate(sides_array.tolist()))
        moved = list(points)
        warped = set() if warp is None else _warped(moved, tetrahedra, clean, sides, index,
                                                    warp, frozen)
        fit = _assembled(moved, tetrahedra, clean, sides, index, rays)
        pinches = manifold_violations(fit.mesh.tetrahedra())
        lattice_ids = fit.lattice_ids
        at_pinch = {lattice_ids[v] for violation in pinches for v in violation.elements
                    if v < len(lattice_ids) and lattice_ids[v] in warped}
        if not at_pinch:
            return attrs.evolve(fit, warped=len(warped),
                                pinches=tuple(str(violation) for violation in pinches))
        frozen |= at_pinch


def _assembled(points: list[Point3], tetrahedra: Any, clean: Any, sides: dict[int, int],
               index: SurfaceIndex, rays: int) -> SurfaceFit:
    sides_array = np.array([sides[v] for v in range(len(points))], dtype=np.int64)
    kept_sides = sides_array[tetrahedra]
    keep_clean = clean & (kept_sides != OUTSIDE).all(axis=1) & (kept_sides == INSIDE).any(
        axis=1)
    crossing = ~clean & (kept_sides == INSIDE).any(axis=1)
    # every vertex on the surface: the tetrahedron is inside or outside as its centre is
    for row in np.flatnonzero(~clean & (kept_sides == ON).all(axis=1)).tolist():
        corners = [points[v] for v in tetrahedra[row].tolist()]
        centre = point3(*(sum((p[a] for p in corners), mpq(0)) / 4 for a in range(3)))
        crossing[row] = index.side(centre) == INSIDE
    cut_edges: set[tuple[int, int]] = set()
    for tetrahedron in tetrahedra[crossing].tolist():
        for i, j in _TETRAHEDRON_EDGES:
            u, v = tetrahedron[i], tetrahedron[j]
            if sides[u] * sides[v] == -1:
                cut_edges.add((min(u, v), max(u, v)))
    all_points = list(points)
    cuts: dict[tuple[int, int], int] = {}
    for u, v in sorted(cut_edges):
        inside, outside = (u, v) if sides[u] == INSIDE else (v, u)
        cuts[(u, v)] = len(all_points)
        all_points.append(_cut_point(index, points[inside], points[outside]))
    for cut in cuts.values():
        sides[cut] = ON
    made: list[Any] = [tetrahedra[keep_clean]]
    unfit = []
    for row, tetrahedron in zip(np.flatnonzero(crossing).tolist(),
                                tetrahedra[crossing].tolist(), strict=True):
        cones = _piece(tetrahedron, sides, cuts, all_points.__getitem__)
        if cones is None:
            unfit.append(row)
        elif cones:
            made.append(np.array(cones, dtype=np.int64).reshape(-1, 4))
    kept = np.concatenate(made) if made else np.zeros((0, 4), dtype=np.int64)
    used = np.unique(kept)
    renumber = np.full(len(all_points), -1, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    mesh = mesh3_from_positive_arrays([all_points[i] for i in used.tolist()], renumber[kept])
    on = [int(renumber[v]) for v in used.tolist() if sides[v] == ON]
    lattice_ids = tuple(v for v in used.tolist() if v < len(points))
    return SurfaceFit(mesh, len(cuts), tuple(on), sides_array, rays, tuple(unfit),
                      lattice_ids=lattice_ids)
