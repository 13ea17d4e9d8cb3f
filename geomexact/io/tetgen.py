"""Hang Si's TetGen files for tetrahedral meshes: ``.node`` (3D), ``.ele`` and ``.face``.

Spec: ``specs/formats/tetgen.md``.  Written in TetGen's own orientations: every
tetrahedron positive in our ``orient3d``, every boundary face inward.  A mesh is named by
its ``.ele`` file (or its stem); the ``.node`` beside it is required; a ``.face`` beside
it, when present, must list exactly the boundary faces (any order, any orientation).
Indices are 0- or 1-based as the first vertex number says.  Tetrahedra must all have the
same orientation: all positive (our ``orient3d``) are kept, all negative are reversed
with a note, a file mixing them is refused naming one tetrahedron of each (the rule of
:mod:`geomexact.io.tetrahedron_orientation`).  Vertex attributes and markers and
tetrahedron attributes are not part of a :class:`Mesh3`: they are dropped with a note.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from geomexact.errors import FormatError, PreconditionError
from geomexact.io.bulk import (
    NotPlain,
    PlainLines,
    integer_column,
    number_column,
    numbered,
    numbered_corners,
    plain_first,
    rows_text,
)
from geomexact.io.registry import (
    CountHeader,
    FixedField,
    NumberStyle,
    NumberText,
    Value,
    WriteReport,
    check_file_set,
    check_index,
    check_numbering,
    counted,
    expect_exact_fields,
    file_lines,
    file_set_stem,
    parse_count,
    parse_int,
    parse_marker_flag,
    parse_number,
    read_header,
    with_extension,
    write_files,
    written_value,
)
from geomexact.io.tetrahedron_orientation import flat_problem, mixed_problem, negative_note
from geomexact.kernel.array_filters import orient3d_signs, point_doubles3
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point3, point3
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates3d import orient3d
from geomexact.mesh3d.snapshot import Mesh3, empty_mesh3, tetrahedron_faces
from geomexact.mesh3d.transient import Transient3, mesh3_from_positive_arrays

NODE, ELE, FACE = ".node", ".ele", ".face"

_NODE_HEADER = CountHeader(
    "the vertex header", "count 3 attributes markers", "vertex count",
    FixedField("dimension", 3, default=2,
               problem=lambda dimension: f"dimension is {dimension}; a TetGen mesh is 3"),
)
"""The header of a ``.node``: a TetGen mesh is 3D."""


def _corners_problem(corners: int) -> str:
    if corners == 3:
        return ("lists 3-node triangles, but its .node is 3D (dimension 3): only 2D Triangle "
                "meshes and TetGen meshes of 4-node tetrahedra are supported")
    return f"tetrahedra have {corners} nodes; only 4-node tetrahedra are supported"


_ELE_HEADER = CountHeader(
    "the .ele header", "count 4 attributes", "tetrahedron count",
    FixedField("corners per tetrahedron", 4, default=4, problem=_corners_problem),
)
"""The header of an ``.ele``: only 4-node tetrahedra are read."""


def mesh_stem(path: Path) -> Path:
    """The stem of a mesh named by any of its files (``x.1.ele``, ``x.1.node``,
    ``x.1.face``) or by the stem itself."""
    return file_set_stem(path, (ELE, NODE, FACE))


def node_dimension(path: Path) -> int | None:
    """The dimension in the header of the ``.node`` beside the mesh ``path`` names (2 when
    the header omits it), or None when there is no such file or no readable header."""
    node_path = with_extension(mesh_stem(path), NODE)
    if not node_path.exists():
        return None
    lines = file_lines(node_path)
    if lines.at_end():
        return None
    _, tokens = lines.next("the header")
    if len(tokens) < 2:
        return 2
    try:
        return int(tokens[1])
    except ValueError:
        return None


def _node_fields(header: list[str]) -> int | None:
    values = integer_column(header) if len(header) <= 4 else None
    if values is None or len(values) < 2 or values[1] != 3 or (values < 0).any():
        return None
    attributes = int(values[2]) if len(values) > 2 else 0
    markers = int(values[3]) if len(values) > 3 else 0
    return 4 + attributes + markers if markers in (0, 1) else None


def _bulk_nodes(path: Path, notes: list[str]) -> tuple[list[Point3], int] | None:
    """:func:`_read_nodes` of a plain file (:mod:`geomexact.io.bulk`): regular lines,
    vertices numbered 0, 1, … or 1, 2, …, plain numbers; None for anything else (the
    line reader then reads it, or names the error)."""
    points: list[Point3] = []
    cache: dict[str, tuple[Rational, float]] = {}
    dropped = 0
    base = 0
    try:
        with PlainLines(path) as lines:
            header, _ = lines.next_line()
            fields = _node_fields(header)
            if fields is None:
                return None
            count = int(header[0])
            attributes = int(header[2]) if len(header) > 2 else 0
            markers = fields - 4 - attributes
            for tokens, _ in lines.chunks(count, fields):
                if not points:
                    base = 1 if tokens[0] == "1" else 0
                first = base + len(points)
                size = len(tokens) // fields
                if tokens[0::fields] != [str(label) for label in range(first, first + size)]:
                    return None
                columns = [number_column(tokens[column::fields], cache)
                           for column in range(1, 4 + attributes)]
                marker_column = integer_column(tokens[fields - 1 :: fields]) if markers else None
                if any(column is None for column in columns) or (
                    markers and marker_column is None
                ):
                    return None
                (xs, fxs), (ys, fys), (zs, fzs) = columns[:3]  # type: ignore[misc]
                points.extend(map(Point3, xs, ys, zs, fxs, fys, fzs))
                if marker_column is not None:
                    dropped += int(np.count_nonzero(marker_column))
            if not lines.at_end():
                return None
    except NotPlain:
        return None
    if attributes:
        notes.append(f"dropped the {counted(attributes, 'attribute')} of each vertex")
    if dropped:
        notes.append(f"dropped {counted(dropped, 'nonzero vertex marker')}")
    return points, base


@plain_first(_bulk_nodes)
def _read_nodes(path: Path, notes: list[str]) -> tuple[list[Point3], int]:
    """The points of a 3D ``.node`` file and its numbering base; a plain file in bulk
    (:func:`_bulk_nodes`)."""
    name = str(path)
    lines, header = _NODE_HEADER.read(path)
    count, attributes, markers = header.count, header.attributes, header.markers
    fields = 4 + attributes + markers
    shape = (
        "a vertex line 'number x y z" + " attributes" * bool(attributes)
        + " marker" * markers + "'"
    )
    points: list[Point3] = []
    base = 0
    dropped = 0
    for index in range(count):
        number, tokens = lines.next_item(
            index, count, f"vertex {index + base} (of {count})", "vertices"
        )
        expect_exact_fields(name, number, tokens, fields, shape)
        label = parse_int(name, number, tokens[0], "vertex number")
        base = check_numbering(name, number, label, index, base, "vertex")
        x, y, z = (
            parse_number(name, number, token, f"{axis} of vertex {label}")
            for token, axis in zip(tokens[1:4], "xyz", strict=True)
        )
        for token in tokens[4 : 4 + attributes]:
            parse_number(name, number, token, f"attribute of vertex {label}")
        if markers and parse_int(name, number, tokens[-1], f"marker of vertex {label}"):
            dropped += 1
        points.append(point3(x, y, z))
    lines.expect_end(f"the {counted(count, 'vertex', 'vertices')}")
    if attributes:
        notes.append(f"dropped the {counted(attributes, 'attribute')} of each vertex")
    if dropped:
        notes.append(f"dropped {counted(dropped, 'nonzero vertex marker')}")
    return points, base


def _bulk_tetrahedra(
    path: Path, points: list[Point3], base: int, notes: list[str]
) -> tuple[list[tuple[int, int, int, int]], list[int]] | None:
    """:func:`_read_tetrahedra` of a plain file (:mod:`geomexact.io.bulk`): regular
    lines, tetrahedra numbered 0, 1, … or 1, 2, …, indices in range, distinct corners,
    one orientation; None for anything else (the line reader then reads it, or names the
    error, having read no further than its line)."""
    tetrahedra: list[tuple[int, int, int, int]] = []
    numbers: list[int] = []
    positive = negative = False
    first = 0
    doubles = point_doubles3(points)
    try:
        with PlainLines(path) as lines:
            header, _ = lines.next_line()
            values = integer_column(header) if len(header) <= 3 else None
            if values is None or (values < 0).any() or (len(values) > 1 and values[1] != 4):
                return None
            attributes = int(values[2]) if len(values) > 2 else 0
            fields = 5 + attributes
            for tokens, rows_lines in lines.chunks(int(values[0]), fields):
                for column in range(5, fields):
                    if number_column(tokens[column::fields], {}) is None:
                        return None
                corner_tokens = tokens if not attributes else [
                    token for row in zip(*(tokens[c::fields] for c in range(5)), strict=True)
                    for token in row
                ]
                found = integer_column(corner_tokens)
                if found is None:
                    return None
                rows = found.reshape(-1, 5)
                if not numbers:
                    first = int(rows[0, 0])
                corners = numbered_corners(rows, first, len(numbers), base, len(points))
                if corners is None:
                    return None
                ordered = np.sort(corners, axis=1)
                if bool(np.any(ordered[:, 1:] == ordered[:, :-1])):
                    return None
                chunk = list(zip(*(corners[:, k].tolist() for k in range(4)), strict=True))
                # the certified filter on all of them at once, orient3d on the undecided
                signs = orient3d_signs(*doubles, *corners.T)
                for row in np.flatnonzero(signs == 0).tolist():
                    a, b, c, d = chunk[row]
                    signs[row] = int(orient3d(points[a], points[b], points[c], points[d]))
                if bool(np.any(signs == 0)):
                    return None
                positive = positive or bool(np.any(signs > 0))
                negative = negative or bool(np.any(signs < 0))
                if positive and negative:
                    return None
                tetrahedra.extend(chunk)
                numbers.extend(rows_lines)
            if not lines.at_end():
                return None
    except NotPlain:
        return None
    if negative:
        tetrahedra = [(b, a, c, d) for a, b, c, d in tetrahedra]
        notes.append(negative_note(len(tetrahedra)))
    if attributes:
        notes.append(f"dropped the {counted(attributes, 'attribute')} of each tetrahedron")
    return tetrahedra, numbers


@plain_first(_bulk_tetrahedra)
def _read_tetrahedra(
    path: Path, points: list[Point3], base: int, notes: list[str]
) -> tuple[list[tuple[int, int, int, int]], list[int]]:
    """The tetrahedra of an ``.ele`` file (0-based), all positive, and their lines; a
    plain file's tokens in bulk (:func:`_bulk_tetrahedra`)."""
    name = str(path)
    lines, header = _ELE_HEADER.read(path)
    count, attributes = header.count, header.attributes
    fields = 5 + attributes
    tetrahedra: list[tuple[int, int, int, int]] = []
    numbers: list[int] = []
    positive: str | None = None  # the first tetrahedron of each orientation, described
    negative: str | None = None
    first = 0
    for index in range(count):
        number, tokens = lines.next_item(
            index, count, f"tetrahedron {index + first} (of {count})", "tetrahedra"
        )
        expect_exact_fields(
            name, number, tokens, fields,
            "a tetrahedron line 'number a b c d" + " attributes" * bool(attributes) + "'",
        )
        label = parse_int(name, number, tokens[0], "tetrahedron number")
        first = check_numbering(name, number, label, index, first, "tetrahedron")
        a, b, c, d = (
            check_index(
                name, number, parse_int(name, number, token, f"corner of tetrahedron {label}"),
                len(points), base, f"tetrahedron {label}: vertex",
            )
            for token in tokens[1:5]
        )
        for token in tokens[5:]:
            parse_number(name, number, token, f"attribute of tetrahedron {label}")
        if len({a, b, c, d}) < 4:
            raise FormatError(name, number, f"tetrahedron {label} repeats a vertex")
        shown = ", ".join(str(vertex + base) for vertex in (a, b, c, d))
        described = f"tetrahedron {label} ({shown}) on line {number}"
        orientation = orient3d(points[a], points[b], points[c], points[d])
        if orientation == Orientation.COLLINEAR:
            raise FormatError(name, number, flat_problem(described))
        if orientation == Orientation.COUNTERCLOCKWISE:
            positive = described if positive is None else positive
        else:
            negative = described if negative is None else negative
        if positive is not None and negative is not None:
            raise FormatError(name, number, mixed_problem(negative, positive))
        tetrahedra.append((a, b, c, d))
        numbers.append(number)
    lines.expect_end(f"the {counted(count, 'tetrahedron', 'tetrahedra')}")
    if negative is not None:
        tetrahedra = [(b, a, c, d) for a, b, c, d in tetrahedra]
        notes.append(negative_note(count))
    if attributes:
        notes.append(f"dropped the {counted(attributes, 'attribute')} of each tetrahedron")
    return tetrahedra, numbers


def _check_faces(path: Path, mesh: Mesh3, base: int) -> None:
    """FormatError unless the ``.face`` file lists exactly the boundary faces."""
    name = str(path)
    lines, number, tokens = read_header(path, "the .face header", "count markers")
    count = parse_count(name, number, tokens[0], "face count")
    markers = parse_marker_flag(name, number, tokens, 1, "face marker count")
    boundary = {frozenset(face) for face in mesh.boundary_faces()}
    if count != len(boundary):
        raise FormatError(
            name, number,
            f"lists {count} faces, but the mesh has {len(boundary)} boundary faces",
        )
    seen: set[frozenset[int]] = set()
    first = 0
    for index in range(count):
        number, tokens = lines.next_item(index, count, f"face {index + first}", "faces")
        expect_exact_fields(
            name, number, tokens, 4 + markers,
            "a face line 'number a b c" + " marker" * markers + "'",
        )
        label = parse_int(name, number, tokens[0], "face number")
        first = check_numbering(name, number, label, index, first, "face")
        face = frozenset(
            check_index(
                name, number, parse_int(name, number, token, f"corner of face {label}"),
                mesh.vertex_count, base, f"face {label}: vertex",
            )
            for token in tokens[1:4]
        )
        if markers:
            parse_int(name, number, tokens[4], f"marker of face {label}")
        if face not in boundary:
            raise FormatError(name, number, f"face {label} is not a boundary face of the mesh")
        if face in seen:
            raise FormatError(name, number, f"face {label} is listed twice")
        seen.add(face)
    lines.expect_end(f"the {counted(count, 'face')}")


def _build(
    name: str,
    points: list[Point3],
    tetrahedra: list[tuple[int, int, int, int]],
    numbers: list[int],
    base: int,
) -> Mesh3:
    """The mesh of positive ``tetrahedra``; two on the same side of a face (an overlap) is
    a FormatError at the later one's line naming the earlier one's."""
    try:  # in bulk; an overlap is then found again one tetrahedron at a time, to name it
        return mesh3_from_positive_arrays(points, np.array(tetrahedra, dtype=np.int64))
    except PreconditionError:
        pass
    transient = Transient3(empty_mesh3())
    for point in points:
        transient.add_vertex(point)
    owner: dict[tuple[int, int, int], int] = {}  # oriented face -> line of its tetrahedron
    for tetrahedron, number in zip(tetrahedra, numbers, strict=True):
        for face, _ in tetrahedron_faces(*tetrahedron):
            if face in owner:
                shown = tuple(vertex + base for vertex in face)
                raise FormatError(
                    name, number,
                    f"the tetrahedra overlap: face {shown} of this tetrahedron is on the "
                    f"same side as the tetrahedron on line {owner[face]}",
                )
        for face, _ in tetrahedron_faces(*tetrahedron):
            owner[face] = number
        transient.add_tetrahedron(*tetrahedron)
    return transient.seal()


def read_tetgen(path: Path) -> tuple[Value, list[str]]:
    """A TetGen mesh named by its ``.ele`` file (or its stem) as a :class:`Mesh3`."""
    stem = mesh_stem(path)
    ele_path, node_path, face_path = (with_extension(stem, e) for e in (ELE, NODE, FACE))
    if not ele_path.exists():
        raise FormatError(str(ele_path), None, "no such file")
    if not node_path.exists():
        raise FormatError(
            str(ele_path), None,
            f"a TetGen mesh needs its vertices in {node_path.name}, which does not exist",
        )
    check_file_set((node_path, ele_path, face_path))
    notes: list[str] = []
    points, base = _read_nodes(node_path, notes)
    tetrahedra, numbers = _read_tetrahedra(ele_path, points, base, notes)
    mesh = _build(str(ele_path), points, tetrahedra, numbers, base)
    if face_path.exists():
        _check_faces(face_path, mesh, base)
        notes.append(f"{face_path.name} agrees with the boundary")
    return mesh, notes


def tetgen_output_paths(path: Path) -> tuple[Path, ...]:
    """The files :func:`write_tetgen` writes for ``path``."""
    stem = mesh_stem(path)
    return tuple(with_extension(stem, extension) for extension in (NODE, ELE, FACE))


def tetgen_texts(mesh: Mesh3, number: NumberText) -> tuple[str, str, str]:
    """The ``.node``, ``.ele`` and ``.face`` texts of ``mesh`` in the orientations TetGen
    itself writes (``specs/formats/tetgen.md``): 0-based; tetrahedra canonical, each
    positive in our orient3d (``det[b - a, c - a, d - a] > 0``); boundary faces inward
    (counter-clockwise seen from inside the mesh: each outward face reversed), marker 1."""
    points = mesh.point_list()
    count = len(points)
    coordinates = number.texts(
        coordinate for point in points for coordinate in point[:3]
    )
    node = f"{count} 3 0 0\n" + rows_text(
        "%s %s %s %s\n", count, numbered(coordinates, 3)
    )
    tetrahedra = mesh.tetrahedron_array()
    ele = f"{len(tetrahedra)} 4 0\n" + rows_text(
        "%s %s %s %s %s\n", len(tetrahedra), numbered(tetrahedra.ravel().tolist(), 4)
    )
    faces = mesh.boundary_faces()
    inward = [vertex for a, b, c in faces for vertex in (a, c, b)]
    face = f"{len(faces)} 1\n" + rows_text(
        "%s %s %s %s 1\n", len(faces), numbered(inward, 3)
    )
    return node, ele, face


def write_tetgen(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A :class:`Mesh3` as ``stem.node``, ``stem.ele`` and ``stem.face``."""
    mesh = written_value(value, Mesh3, "tetgen")
    number = NumberText(numbers)
    texts = tetgen_texts(mesh, number)
    outputs = tetgen_output_paths(path)
    return write_files(list(zip(outputs, texts, strict=True)), overwrite=overwrite,
                       numbers=number, members=outputs)
