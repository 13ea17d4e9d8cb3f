"""Cell templates of a 1-irregular cuboid for the octree's mixed and polyhedral finals
(issue 23; ``specs/octree.md``, "Mixed and polyhedral finals").

Both work in *point codes* (corner k: k; Steiner point of bit i: 8 + i; added points
from :data:`CENTRE` on) on the cuboid's half-lattice (every coordinate 0, 1 or 2), so one
template serves every leaf with that pattern and shape.

**The face rule** (:func:`face_polygons`).  Each face of the cuboid is cut into the
co-circular polygons of the 2D Delaunay tessellation of the points on it (exact
incircle; the tessellation is unique), a rule that reads only that face's points, so two
leaves sharing a face cut it alike and the mesh conforms (a coarse face against four
finer leaves has its centre and four midpoints, and is cut into the four quads they
show; a face with one midpoint into three triangles).

**Mixed** (:func:`mixed_template`).  No Steiner point: one hexahedron.  Otherwise, of
the templates below whose boundary polygons are exactly the face rule's, the one with
the fewest cells (then the fewest added points; ties in this order):

1. an *extrusion* along an axis (no Steiner point on the edges along it nor a centre on
   the faces along it, the same cut on both end faces): the end face's polygons swept
   across -- triangles give wedges, quads hexahedra;
2. a *star* from a midpoint A (on each face through A, the cut is triangles through A):
   the cone from A over every polygon of the faces not through A -- pyramids and
   tetrahedra (one midpoint on one edge gives four pyramids, as met's ``Patterns`` says);
3. *delaunay*: the polyhedral template below, each polyhedron cut into the cones from
   one of its vertices whose faces are all triangles, or else from the midpoint of its
   first two vertices sharing no face (an added point, on the quarter lattice);
4. the *cone from the body centre* over every polygon: pyramids and tetrahedra, and one
   added point (always applies).

**Polyhedral** (:func:`polyhedral_template`).  The exact Delaunay tessellation of the
cuboid's points with every co-spherical group one cell
(:func:`~geomexact.mesh3d.cuboid.polyhedral_census.pattern_cells`); a cell whose faces are
a standard kind's is that kind (the whole cuboid, when it has no Steiner point, is a
hexahedron).  A leaf's face is cut into the co-circular polygons of its points' 2D
Delaunay tessellation, which is unique, so the leaves conform.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import cache, cmp_to_key
from itertools import combinations, pairwise
from math import gcd
from typing import Any, Final

import attrs

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.kernel.points import Point3, point3
from geomexact.kernel.vectors import cross3, dot3, sub3
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents
from geomexact.mesh3d.cuboid.numbering import (
    CORNER_POSITIONS,
    PATTERN_COUNT,
    check_pattern,
    steiner_position2,
)
from geomexact.mesh3d.cuboid.partition import recorded_box
from geomexact.mesh3d.mixed.cells import (
    Cell,
    CellKind,
    cell_of_faces,
    polygon_key,
    reversed_face,
    standard_cell,
)
from geomexact.mesh3d.mixed.recording import recorded_cells
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.trace.record import Trace

__all__ = [
    "CENTRE",
    "CellTemplate",
    "CuboidCells",
    "cell_template",
    "cuboid_cells",
    "cuboid_start_points",
    "face_polygons",
    "mixed_template",
    "polyhedral_template",
    "recorded_cell_start",
    "relabelled",
]

CENTRE: Final = 26
"""The first code past the cuboid's own points: a template's added points (the body
centre of the cone template, the centroid of a polyhedron) are codes 26, 27, …"""

Position = tuple[int, int, int]
Point2 = tuple[Rational, Rational]
Position3 = tuple[Rational, Rational, Rational]

POSITIONS: Final[tuple[Position, ...]] = (
    *((2 * x, 2 * y, 2 * z) for x, y, z in CORNER_POSITIONS),
    *(steiner_position2(bit) for bit in range(18)),
)
"""Point code -> its half-lattice position."""

_CODE_AT: Final[dict[Position, int]] = {p: code for code, p in enumerate(POSITIONS)}


@attrs.frozen(slots=True)
class CellTemplate:
    """A cuboid's cells in point codes (canonical :class:`Cell` over codes), the name of
    the template (``hexahedron``, ``extrusion-x`` …, ``star``, ``delaunay``, ``centre``)
    and the ``points`` it adds inside the cuboid (codes 26, 27, …: exact half-lattice
    positions)."""

    cells: tuple[Cell, ...]
    name: str
    points: tuple[Position3, ...] = ()


def _present(pattern: int, code: int) -> bool:
    return code < 8 or (code < CENTRE and bool(pattern >> (code - 8) & 1))


def _face_frame(face: int) -> tuple[int, int, int, int]:
    """(normal axis, its half-lattice value, first in-face axis, second)."""
    axis = face // 2
    u, v = (a for a in range(3) if a != axis)
    return axis, 2 * (face % 2), u, v


def _at(axis: int, value: int, u: int, v: int, pu: int, pv: int) -> int:
    position = [0, 0, 0]
    position[axis], position[u], position[v] = value, pu, pv
    return _CODE_AT[(position[0], position[1], position[2])]


def _incircle(a: Point2, b: Point2, c: Point2, d: Point2) -> int:
    """The sign of d against the circle through a, b, c (counter-clockwise): > 0 inside."""
    rows = [(p[0] - d[0], p[1] - d[1]) for p in (a, b, c)]
    lifted = [(x, y, x * x + y * y) for x, y in rows]
    (ax, ay, al), (bx, by, bl), (cx, cy, cl) = lifted
    value = ax * (by * cl - bl * cy) - ay * (bx * cl - bl * cx) + al * (bx * cy - by * cx)
    return int(value > 0) - int(value < 0)


def _turn(a: Point2, b: Point2, c: Point2) -> Rational:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _cocircular_polygons(points: dict[int, Point2]) -> list[tuple[int, ...]]:
    """The 2D Delaunay tessellation of ``points`` (code -> exact point, in general no
    three collinear on an empty circle) with each co-circular group one polygon,
    counter-clockwise, each starting at its least code: every empty circle through three
    of them, once."""
    codes = sorted(points)
    found: set[tuple[int, ...]] = set()
    for i, j, k in combinations(codes, 3):
        a, b, c = points[i], points[j], points[k]
        turn = _turn(a, b, c)
        if turn == 0:
            continue
        if turn < 0:
            b, c = c, b
        signs = {code: _incircle(a, b, c, points[code]) for code in codes}
        if any(sign > 0 for sign in signs.values()):
            continue
        on = [code for code, sign in signs.items() if sign == 0]
        found.add(_convex_cycle(on, points))
    return sorted(found)


def _convex_cycle(codes: Sequence[int], points: dict[int, Point2]) -> tuple[int, ...]:
    """Points in convex position, counter-clockwise from the least code."""
    first = min(codes)
    origin = points[first]
    rest = [code for code in codes if code != first]
    # all others lie on one side of the hull vertex ``first``: sort by the turn

    def before(p: int, q: int) -> int:
        return -1 if _turn(origin, points[p], points[q]) > 0 else 1

    ordered = sorted(rest, key=cmp_to_key(before))
    return (first, *ordered)


@cache
def face_polygons(pattern: int, face: int, shape: Box) -> tuple[tuple[int, ...], ...]:
    """The cut of ``face`` (0..5, bit 12 + face) of a cuboid of ``shape`` with ``pattern``:
    the co-circular polygons of the 2D Delaunay tessellation of its points, as cycles of
    point codes counter-clockwise in the face's (u, v) axes, each from its least code."""
    check_pattern(pattern)
    axis, value, u, v = _face_frame(face)
    points = {}
    for code, position in enumerate(POSITIONS):
        if position[axis] == value and _present(pattern, code):
            points[code] = (position[u] * shape.extents[u], position[v] * shape.extents[v])
    return tuple(_cocircular_polygons(points))


def _normal(polygon: Sequence[int]) -> Position:
    """The (unnormalised) right-hand normal of a planar convex polygon of codes."""
    a, b, c = (POSITIONS[code] for code in polygon[:3])
    return cross3(sub3(b, a), sub3(c, a))


def _cone(apex: int, polygon: Sequence[int],
          at: tuple[Rational, Rational, Rational] | None = None) -> Cell:
    """The tetrahedron or pyramid over ``polygon`` with ``apex`` (a cuboid point, or an
    added one ``at`` that position), in VTK's orientation (the base's normal points to
    the apex)."""
    base = list(polygon)
    top = POSITIONS[apex] if at is None else at
    origin = POSITIONS[base[0]]
    if dot3(_normal(base), (top[0] - origin[0], top[1] - origin[1],  # type: ignore[arg-type]
                            top[2] - origin[2])) < 0:
        base.reverse()
    kind = CellKind.TETRA if len(base) == 3 else CellKind.PYRAMID
    return standard_cell(kind, [*base, apex])


def _faces_through(code: int) -> list[int]:
    position = POSITIONS[code]
    return [face for face in range(6) if position[face // 2] == 2 * (face % 2)]


def _star(pattern: int, shape: Box, apex: int) -> tuple[Cell, ...] | None:
    through = _faces_through(apex)
    for face in through:
        polygons = face_polygons(pattern, face, shape)
        if any(len(polygon) != 3 or apex not in polygon for polygon in polygons):
            return None
    return tuple(_cone(apex, polygon) for face in range(6) if face not in through
                 for polygon in face_polygons(pattern, face, shape))


def _rotated(polygon: Sequence[int]) -> tuple[int, ...]:
    start = polygon.index(min(polygon))
    return (*polygon[start:], *polygon[:start])


def _extrusion(pattern: int, shape: Box, axis: int) -> tuple[Cell, ...] | None:
    for code in range(8, CENTRE):
        along = POSITIONS[code][axis] == 1  # an edge along the axis, a face parallel to it
        if along and _present(pattern, code):
            return None
    low = face_polygons(pattern, 2 * axis, shape)

    def lifted(code: int) -> int:
        position = list(POSITIONS[code])
        position[axis] = 2
        return _CODE_AT[(position[0], position[1], position[2])]

    if ({_rotated([lifted(code) for code in polygon]) for polygon in low}
            != set(face_polygons(pattern, 2 * axis + 1, shape))):
        return None
    cells = []
    for polygon in low:
        base = list(polygon)
        if _normal(base)[axis] > 0:  # a wedge's first triangle faces away from its second
            base.reverse()
        if len(base) == 3:
            cells.append(standard_cell(CellKind.WEDGE, [*base, *map(lifted, base)]))
        else:
            base.reverse()  # a hexahedron's bottom faces its top
            cells.append(standard_cell(CellKind.HEXAHEDRON, [*base, *map(lifted, base)]))
    return tuple(cells)


def _fanned(face: Sequence[int]) -> list[tuple[int, ...]]:
    """A face of five or more vertices as the fan from its least code (the cell on its
    other side fans it alike); a triangle or quad as itself."""
    if len(face) <= 4:
        return [tuple(face)]
    first = _rotated(face)
    return [(first[0], b, c) for b, c in pairwise(first[1:])]


def _inner_point(cell: Cell) -> Position3:
    """A point strictly inside the convex ``cell``: the midpoint of its first two vertices
    (code order) that share no face -- a quarter-lattice point, so a file of doubles keeps
    it exactly -- else the average of its vertices."""
    for u, v in combinations(cell.vertices, 2):
        if not any(u in face and v in face for face in cell.faces):
            return (mpq(POSITIONS[u][0] + POSITIONS[v][0], 2),
                    mpq(POSITIONS[u][1] + POSITIONS[v][1], 2),
                    mpq(POSITIONS[u][2] + POSITIONS[v][2], 2))
    centroid = [sum((mpq(POSITIONS[v][axis]) for v in cell.vertices), mpq(0))
                / len(cell.vertices) for axis in range(3)]
    return (centroid[0], centroid[1], centroid[2])


def _split_polyhedron(cell: Cell, code: int) -> tuple[tuple[Cell, ...], Position3 | None]:
    """A polyhedral cell in standard cells: the cones from one of its vertices whose
    faces are all triangles over its other faces, the fewest; without such a vertex, the
    cones from a point inside it (:func:`_inner_point`, a new point, code ``code``) over
    all its faces.  Returns the cells and the added point's half-lattice position (None
    when none is added)."""
    best: tuple[Cell, ...] | None = None
    for apex in cell.vertices:
        if any(len(face) != 3 for face in cell.faces if apex in face):
            continue
        cones = tuple(_cone(apex, piece) for face in cell.faces if apex not in face
                      for piece in _fanned(face))
        if best is None or len(cones) < len(best):
            best = cones
    if best is not None:
        return best, None
    at = _inner_point(cell)
    return tuple(_cone(code, piece, at) for face in cell.faces
                 for piece in _fanned(face)), at


def _boundary_keys(cells: Sequence[Cell]) -> set[tuple[int, ...]]:
    faces = {face for cell in cells for face in cell.faces}
    return {polygon_key(face) for face in faces if reversed_face(face) not in faces}


@cache
def mixed_template(pattern: int, shape: Box) -> CellTemplate:
    """The mixed template of ``pattern`` in a cuboid of ``shape`` (module docstring)."""
    check_pattern(pattern)
    if pattern == 0:
        return CellTemplate((standard_cell(CellKind.HEXAHEDRON, (0, 1, 3, 2, 4, 5, 7, 6)),),
                            "hexahedron")
    candidates: list[CellTemplate] = []
    for axis in range(3):
        extruded = _extrusion(pattern, shape, axis)
        if extruded is not None:
            candidates.append(CellTemplate(extruded, "extrusion-" + "xyz"[axis]))
    for apex in range(8, CENTRE):
        if _present(pattern, apex):
            starred = _star(pattern, shape, apex)
            if starred is not None:
                candidates.append(CellTemplate(starred, "star"))
    delaunay: list[Cell] = []
    added: list[Position3] = []
    for cell in polyhedral_template(pattern, shape).cells:
        if cell.kind != CellKind.POLYHEDRON:
            delaunay.append(cell)
            continue
        split, point = _split_polyhedron(cell, CENTRE + len(added))
        delaunay += split
        if point is not None:
            added.append(point)
    candidates.append(CellTemplate(tuple(delaunay), "delaunay", tuple(added)))
    centre = (mpq(1), mpq(1), mpq(1))
    candidates.append(CellTemplate(
        tuple(_cone(CENTRE, polygon, centre) for face in range(6)
              for polygon in face_polygons(pattern, face, shape)), "centre", (centre,)))
    cut = {polygon_key(polygon) for face in range(6)
           for polygon in face_polygons(pattern, face, shape)}
    return min((candidate for candidate in candidates
                if _boundary_keys(candidate.cells) == cut),
               key=lambda candidate: (len(candidate.cells), len(candidate.points)))


def _reduced(normal: Position) -> Position:
    divisor = gcd(*normal)
    return (normal[0] // divisor, normal[1] // divisor, normal[2] // divisor)


@cache
def polyhedral_template(pattern: int, shape: Box) -> CellTemplate:
    """The polyhedral Delaunay cells of ``pattern`` in a cuboid of ``shape`` (module
    docstring): each cell's faces are the planes of its tetrahedra's outer faces, each
    the cycle of those faces' edges met once."""
    from geomexact.mesh3d.cuboid.polyhedral_census import pattern_cells

    check_pattern(pattern)
    mesh, found = pattern_cells(pattern, shape)
    codes = {}
    for vertex in range(mesh.vertex_count):
        point = mesh.point(vertex)
        codes[vertex] = _CODE_AT[tuple(  # type: ignore[index]
            int(2 * (point[axis] - shape.low[axis]) / shape.extents[axis]) for axis in range(3))]
    cells = []
    for cell in found:
        triangles: set[tuple[int, int, int]] = set()
        for a, b, c, d in cell.tetrahedra:  # positive: (b, c, d), (a, d, c) … face out
            triangles.update(((b, c, d), (a, d, c), (a, b, d), (a, c, b)))
        outer = [(codes[a], codes[b], codes[c]) for a, b, c in triangles
                 if not any((x, z, y) in triangles for x, y, z in ((a, b, c), (b, c, a),
                                                                  (c, a, b)))]
        planes: dict[tuple[Position, int], list[tuple[int, int, int]]] = {}
        for triangle in outer:
            normal = _reduced(_normal(triangle))
            planes.setdefault((normal, dot3(normal, POSITIONS[triangle[0]])), []).append(
                triangle)
        faces = []
        for group in planes.values():
            edges = {(p, q) for a, b, c in group for p, q in ((a, b), (b, c), (c, a))}
            following = {p: q for p, q in edges if (q, p) not in edges}
            start = min(following)
            face = [start]
            while following[face[-1]] != start:
                face.append(following[face[-1]])
            faces.append(tuple(face))
        cells.append(cell_of_faces(faces))
    return CellTemplate(tuple(cells), "delaunay")


def relabelled(cell: Cell, ids: Sequence[int]) -> Cell:
    """``cell`` (over point codes) with code c renamed ``ids[c]``."""
    if cell.kind == CellKind.POLYHEDRON:
        return cell_of_faces([[ids[code] for code in face] for face in cell.faces])
    return standard_cell(cell.kind, [ids[code] for code in cell.vertices])


@attrs.frozen(slots=True, eq=False)
class CuboidCells:
    """One cuboid's cell final (``geomexact cuboid P --final mixed|polyhedral``): its
    ``template``, the ``start`` (the cuboid's corners and Steiner points, ids in code
    order, no cell), the ``mesh`` (the template's added points after them) and, when
    recorded, the ``trace`` from ``start`` to ``mesh``."""

    template: CellTemplate
    start: MixedMesh3
    mesh: MixedMesh3
    trace: Trace | None


def cell_template(pattern: int, box: Box, kind: str) -> CellTemplate:
    """The ``kind`` (``mixed`` or ``polyhedral``) template of ``pattern`` in ``box``."""
    if kind not in ("mixed", "polyhedral"):
        raise PreconditionError("cuboid_cells", f"a cell final is mixed or polyhedral, not "
                                f"{kind!r}")
    shape = box_of_extents(*box.extents)
    return mixed_template(pattern, shape) if kind == "mixed" else polyhedral_template(
        pattern, shape)


def cuboid_start_points(pattern: int, box: Box) -> list[Point3]:
    """The exact points of the corners and Steiner points of ``pattern`` in ``box``, in
    code order (the start of :func:`cuboid_cells`)."""
    return [_at_position(box, POSITIONS[code]) for code in range(CENTRE)
            if _present(pattern, code)]


def _at_position(box: Box, position: Sequence[Rational | int]) -> Point3:
    return point3(*(box.low[axis] + box.extents[axis] * mpq(position[axis]) / 2
                    for axis in range(3)))


def cuboid_cells(pattern: int, box: Box, kind: str, *, trace: bool = False,
                 parameters: Mapping[str, Any] | None = None) -> CuboidCells:
    """The ``kind`` final of ``pattern`` in ``box``: its template's cells on the cuboid's
    exact points; with ``trace``, built by the reference steps (``parameters`` recorded)."""
    template = cell_template(pattern, box, kind)
    points = cuboid_start_points(pattern, box)
    codes = [code for code in range(CENTRE) if _present(pattern, code)]
    ids = [-1] * (CENTRE + len(template.points))
    for index, code in enumerate(codes):
        ids[code] = index
    for index in range(len(template.points)):
        ids[CENTRE + index] = len(codes) + index
    added = [_at_position(box, position) for position in template.points]
    cells = tuple(sorted(relabelled(cell, ids) for cell in template.cells))
    if trace:
        start, mesh, recorded = recorded_cells(points, [(added, cells)], parameters or {})
        return CuboidCells(template, start, mesh, recorded)
    return CuboidCells(template, mixed_mesh_from_cells(points, ()),
                       mixed_mesh_from_cells([*points, *added], cells), None)


def recorded_cell_start(trace: Trace) -> MixedMesh3:
    """The start of a trace of :func:`cuboid_cells` (its ``final``, ``pattern`` and
    ``box`` parameters): the cuboid's points, no cell.  A :class:`PreconditionError` for
    another trace or malformed parameters; the caller still checks the digest."""
    box = recorded_box(trace)
    final, pattern = trace.parameter("final"), trace.parameter("pattern")
    if final not in ("mixed", "polyhedral"):
        raise PreconditionError("recorded_start", f"the trace's final {final!r} is not a "
                                "cell final (mixed or polyhedral)")
    if isinstance(pattern, bool) or not isinstance(pattern, int) or not (
            0 <= pattern < PATTERN_COUNT):
        raise PreconditionError("recorded_start", f"the trace's pattern {pattern!r} is not "
                                f"0 .. {PATTERN_COUNT - 1}")
    return mixed_mesh_from_cells(cuboid_start_points(pattern, box), ())
