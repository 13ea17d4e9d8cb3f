"""Jonathan Shewchuk's Triangle files: ``.node``, ``.ele``, ``.neigh`` and ``.poly``.

Three registry formats live here (``specs/formats/triangle.md``, ``node.md``, ``poly.md``):

- ``triangle``: a mesh named by its ``.ele`` file, with the ``.node`` beside it (required),
  the ``.neigh`` (read when present and checked against the adjacency) and a ``.poly``
  whose vertex count is 0 (its segments become the mesh's constrained segments);
- ``node``: a ``.node`` alone, read as a point set (a PSLG without segments);
- ``poly``: a PSLG with segments, holes and regions; a vertex count of 0 in its first line
  means "the vertices are in the ``.node`` beside it".

Indices are 0- or 1-based as the first vertex number says; vertices and triangles must be
numbered consecutively from there.  Boundary markers and attributes are kept.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator, Sequence
from pathlib import Path

import attrs
import numpy as np

from geomexact.errors import FormatError
from geomexact.io.bulk import (
    IntArray,
    NotPlain,
    OrientedChunks,
    PlainLines,
    integer_column,
    neighbour_array,
    number_column,
    numbered_corners,
    plain_first,
    row_chunks,
    rows_text,
    triangle_array,
    triangle_tuples,
)
from geomexact.io.registry import (
    BulkOrientation,
    CountHeader,
    FixedField,
    HeaderCounts,
    Lines,
    NumberStyle,
    NumberText,
    Orienter,
    Reading,
    SourceLines,
    TriangleTable,
    Value,
    WriteReport,
    build_mesh,
    check_file_set,
    check_index,
    check_numbering,
    counted,
    dropped_parts,
    expect_exact_fields,
    expect_fields,
    expect_header_fields,
    expected_neighbours,
    file_set_stem,
    file_stem,
    is_count_line,
    note_duplicate_points,
    parse_count,
    parse_int,
    parse_marker_flag,
    parse_number,
    quoted_tokens,
    read_header,
    section_too_short,
    uniform_attributes,
    with_extension,
    write_files,
    written_value,
)
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.pslg import PSLG, RegionSeed
from geomexact.mesh2d.snapshot import Attributes, Mesh2

NODE, ELE, NEIGH, POLY = ".node", ".ele", ".neigh", ".poly"


# -----------------------------------------------------------------------------------------
# vertex tables (.node, and the first section of .poly)
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class VertexTable:
    """The vertex section of a ``.node`` or ``.poly`` file."""

    path: str
    points: list[Point2]
    lines: list[int | None]
    base: int
    attribute_count: int
    has_markers: bool
    markers: list[int]
    attributes: list[Attributes]


_VERTEX_HEADER = CountHeader(
    "the vertex header", "count dimension attributes markers", "vertex count",
    FixedField("dimension", 2, default=2,
               problem=lambda dimension: f"dimension is {dimension}; only 2D files are "
                                         "supported"),
)
"""The header of a vertex section (a ``.node``, the start of a ``.poly``): only 2D files
are read."""


def _read_vertices(
    path: str, lines: Lines, header: HeaderCounts, *, followed: bool = False
) -> VertexTable:
    """The vertex lines after the vertex header ``header``; ``followed``: a segment
    header comes next (a ``.poly``), so a line of that shape ends the section."""
    count, attribute_count = header.count, header.attributes
    has_markers = bool(header.markers)
    fields = 3 + attribute_count + header.markers
    points: list[Point2] = []
    point_lines: list[int | None] = []
    markers: list[int] = []
    attributes: list[Attributes] = []
    base = 0
    shape = (
        "a vertex line 'number x y"
        + " attributes" * bool(attribute_count)
        + " marker" * has_markers
        + "'"
    )
    for index in range(count):
        number, tokens = lines.next_item(
            index, count, f"vertex {index + base} (of {count})", "vertices"
        )
        if len(tokens) != fields and followed and index and is_count_line(tokens, 2):
            raise section_too_short(
                path, number, count, index, "vertices", header.line,
                f"{quoted_tokens(tokens)} is the segment header 'count markers'",
            )
        expect_exact_fields(path, number, tokens, fields, shape)
        label = parse_int(path, number, tokens[0], "vertex number")
        base = check_numbering(path, number, label, index, base, "vertex")
        x = parse_number(path, number, tokens[1], f"x of vertex {label}")
        y = parse_number(path, number, tokens[2], f"y of vertex {label}")
        points.append(point2(x, y))
        point_lines.append(number)
        if attribute_count:
            attributes.append(
                tuple(
                    parse_number(path, number, token, f"attribute of vertex {label}")
                    for token in tokens[3 : 3 + attribute_count]
                )
            )
        if has_markers:
            markers.append(parse_int(path, number, tokens[-1], f"marker of vertex {label}"))
    return VertexTable(
        path, points, point_lines, base, attribute_count, has_markers, markers, attributes
    )


def _bulk_node_table(path: Path) -> VertexTable | None:
    """:func:`read_node_table` of a plain ``.node`` file (:mod:`geomexact.io.bulk`):
    regular lines, vertices numbered 0, 1, … or 1, 2, … as written by Triangle, plain
    numbers; None for anything else (the line reader then reads it, or names the error)."""
    name = str(path)
    points: list[Point2] = []
    point_lines: list[int | None] = []
    markers: list[int] = []
    attributes: list[Attributes] = []
    cache: dict[str, tuple[Rational, float]] = {}
    try:
        with PlainLines(path) as lines:
            tokens, number = lines.next_line()
            try:
                header = _VERTEX_HEADER.parse(name, number, tokens)
            except FormatError:
                return None
            count, attribute_count, has_markers = header.count, header.attributes, header.markers
            fields = 3 + attribute_count + has_markers
            base = 0
            for tokens, numbers in lines.chunks(count, fields):
                if not points:
                    base = 1 if tokens[0] == "1" else 0
                part = _bulk_vertices(tokens, fields, base + len(points), attribute_count,
                                      bool(has_markers), cache)
                if part is None:
                    return None
                points.extend(part[0])
                markers.extend(part[1])
                attributes.extend(part[2])
                point_lines.extend(numbers)
            if not lines.at_end():
                return None
    except NotPlain:
        return None
    return VertexTable(
        name, points, point_lines, base, attribute_count, bool(has_markers), markers,
        attributes,
    )


@plain_first(_bulk_node_table)
def read_node_table(path: Path) -> VertexTable:
    """The vertices of a ``.node`` file (nothing may follow them), streamed; a plain
    file in bulk (:func:`_bulk_node_table`)."""
    name = str(path)
    lines, header = _VERTEX_HEADER.read(path)
    table = _read_vertices(name, lines, header)
    lines.expect_end(f"the {counted(header.count, 'vertex', 'vertices')}")
    return table


def _bulk_vertices(
    tokens: list[str],
    fields: int,
    first: int,
    attribute_count: int,
    has_markers: bool,
    cache: dict[str, tuple[Rational, float]],
) -> tuple[list[Point2], list[int], list[Attributes]] | None:
    """Points, markers and attributes of vertex lines of ``fields`` tokens each, or None
    unless every token is plain and the lines are numbered ``first``, ``first + 1``, …"""
    count = len(tokens) // fields
    if tokens[0::fields] != [str(label) for label in range(first, first + count)]:
        return None
    xs = number_column(tokens[1::fields], cache)
    ys = number_column(tokens[2::fields], cache)
    if xs is None or ys is None:
        return None
    points = list(map(Point2, xs[0], ys[0], xs[1], ys[1]))
    attributes: list[Attributes] = []
    if attribute_count:
        columns = []
        for column in range(3, 3 + attribute_count):
            values = number_column(tokens[column::fields], cache)
            if values is None:
                return None
            columns.append(values[0])
        attributes = list(zip(*columns, strict=True))
    markers: list[int] = []
    if has_markers:
        marker_column = integer_column(tokens[fields - 1 :: fields])
        if marker_column is None:
            return None
        markers = marker_column.tolist()
    return points, markers, attributes


def _pslg_vertex_tables(
    table: VertexTable,
) -> tuple[tuple[int, ...], tuple[Attributes, ...]]:
    markers = tuple(table.markers) if table.has_markers else ()
    attributes = tuple(table.attributes) if table.attribute_count else ()
    return markers, attributes


def _note_duplicate_vertices(table: VertexTable, notes: list[str]) -> None:
    note_duplicate_points(table.points, table.lines, notes, table.base)


# -----------------------------------------------------------------------------------------
# format "node": a point set
# -----------------------------------------------------------------------------------------
def node_reading(path: Path) -> Reading:
    """A ``.node`` file as a PSLG without segments (markers and attributes kept), with the
    line of each vertex."""
    table = read_node_table(path)
    notes: list[str] = []
    _note_duplicate_vertices(table, notes)
    markers, attributes = _pslg_vertex_tables(table)
    pslg = PSLG(vertices=table.points, vertex_markers=markers, vertex_attributes=attributes)
    return Reading(pslg, notes, SourceLines(str(path), tuple(table.lines), base=table.base))


def read_node(path: Path) -> tuple[Value, list[str]]:
    """A ``.node`` file as a PSLG (:func:`node_reading` without the lines)."""
    reading = node_reading(path)
    return reading.value, reading.notes


def _node_text(
    points: Sequence[Point2],
    markers: Sequence[int] | None,
    attributes: Sequence[Attributes | None],
    number: NumberText,
) -> str:
    count, rows = uniform_attributes(attributes, "vertex")
    header = f"{len(points)} 2 {count} {1 if markers is not None else 0}\n"
    columns: list[Sequence[object]] = [
        range(len(points)),
        number.texts(point.x for point in points),
        number.texts(point.y for point in points),
    ]
    if count:
        values = number.texts(value for row in rows for value in row)
        columns.extend(values[column::count] for column in range(count))
    if markers is not None:
        columns.append(markers)
    template = " ".join(["%s"] * len(columns)) + "\n"
    return header + rows_text(
        template, len(points), list(itertools.chain.from_iterable(zip(*columns, strict=True)))
    )


def _pslg_node_text(pslg: PSLG, number: NumberText) -> str:
    attributes: Sequence[Attributes | None] = (
        pslg.vertex_attributes if pslg.vertex_attributes else [None] * len(pslg.vertices)
    )
    markers = pslg.vertex_markers if pslg.vertex_markers else None
    return _node_text(pslg.vertices, markers, attributes, number)


def write_node(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """The vertices of a PSLG (markers, attributes) as a ``.node`` file; its segments,
    holes and regions are not part of a ``.node`` (write a ``.poly`` for them): they are
    dropped and reported."""
    pslg = written_value(value, PSLG, "node")
    number = NumberText(numbers)
    return write_files(
        [(path, _pslg_node_text(pslg, number))],
        overwrite=overwrite,
        numbers=number,
        dropped=dropped_parts(pslg, ("vertex markers", "vertex attributes")),
    )


# -----------------------------------------------------------------------------------------
# format "poly": a PSLG
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class PolySections:
    """What follows the vertices of a ``.poly`` file."""

    segments: list[tuple[int, int, int]]
    segment_lines: list[int | None]
    holes: list[Point2]
    regions: list[RegionSeed]
    hole_lines: list[int | None] = attrs.Factory(list)
    region_lines: list[int | None] = attrs.Factory(list)


def _read_poly_sections(
    path: str, lines: Lines, vertex_count: int, base: int, notes: list[str] | None = None
) -> PolySections:
    """Segments, then the optional holes and regions.  As Triangle does, a hole or region
    header is read by its first number and a hole or region line by its first 3 or 5
    fields: what follows them is ignored (and noted in ``notes``)."""
    ignored: list[int] = []  # lines whose extra fields were ignored
    number, tokens = lines.next("the segment header 'count markers'")
    expect_header_fields(path, number, tokens, "the segment header", "count markers")
    count = parse_count(path, number, tokens[0], "segment count")
    markers = parse_marker_flag(path, number, tokens, 1, "segment marker count")
    header_line = number
    segments: list[tuple[int, int, int]] = []
    segment_lines: list[int | None] = []
    fields = 3 + markers
    for index in range(count):
        number, tokens = lines.next_item(
            index, count, f"segment {index + base} (of {count})", "segments"
        )
        if len(tokens) != fields and is_count_line(tokens, 1):
            raise section_too_short(
                path, number, count, index, "segments", header_line,
                f"{quoted_tokens(tokens)} is the hole header 'count'",
            )
        expect_exact_fields(
            path, number, tokens, fields,
            "a segment line 'number endpoint endpoint" + " marker" * markers + "'",
        )
        label = parse_int(path, number, tokens[0], "segment number")
        ends = []
        for token in tokens[1:3]:
            vertex = parse_int(path, number, token, f"endpoint of segment {label}")
            ends.append(
                check_index(path, number, vertex, vertex_count, base, f"segment {label}: vertex")
            )
        marker = parse_int(path, number, tokens[3], f"marker of segment {label}") if markers else 0
        if ends[0] == ends[1]:
            raise FormatError(
                path, number, f"segment {label} ({tokens[1]}, {tokens[2]}) has equal ends"
            )
        segments.append((ends[0], ends[1], marker))
        segment_lines.append(number)
    holes: list[Point2] = []
    hole_lines: list[int | None] = []
    regions: list[RegionSeed] = []
    region_lines: list[int | None] = []
    if not lines.at_end():
        number, tokens = lines.next("the hole count")
        if len(tokens) > 1:
            ignored.append(number)
        count = parse_count(path, number, tokens[0], "hole count")
        header_line = number
        for index in range(count):
            number, tokens = lines.next_item(index, count, f"hole {index + 1} (of {count})",
                                             "holes")
            if len(tokens) < 3 and is_count_line(tokens, 1):
                raise section_too_short(
                    path, number, count, index, "holes", header_line,
                    f"{quoted_tokens(tokens)} is the region header 'count'",
                )
            expect_fields(path, number, tokens, 3, "a hole line 'number x y'")
            if len(tokens) > 3:
                ignored.append(number)
            label = parse_int(path, number, tokens[0], "hole number")
            holes.append(
                point2(
                    parse_number(path, number, tokens[1], f"x of hole {label}"),
                    parse_number(path, number, tokens[2], f"y of hole {label}"),
                )
            )
            hole_lines.append(number)
    if not lines.at_end():
        number, tokens = lines.next("the region count")
        if len(tokens) > 1:
            ignored.append(number)
        count = parse_count(path, number, tokens[0], "region count")
        for index in range(count):
            number, tokens = lines.next_item(
                index, count, f"region {index + 1} (of {count})", "regions"
            )
            expect_fields(path, number, tokens, 4, "a region line 'number x y attribute [area]'")
            if len(tokens) > 5:
                ignored.append(number)
            label = parse_int(path, number, tokens[0], "region number")
            x = parse_number(path, number, tokens[1], f"x of region {label}")
            y = parse_number(path, number, tokens[2], f"y of region {label}")
            attribute = parse_number(path, number, tokens[3], f"attribute of region {label}")
            area: Rational | None = None
            if len(tokens) >= 5:
                area = parse_number(path, number, tokens[4], f"maximum area of region {label}")
                if area <= 0:
                    area = None  # Triangle: a non-positive area means "no constraint"
            regions.append(RegionSeed(point2(x, y), attribute, area))
            region_lines.append(number)
    lines.expect_end("the last section (holes, then regions)")
    if ignored and notes is not None:
        shown = ", ".join(map(str, ignored[:5])) + (", …" if len(ignored) > 5 else "")
        notes.append(
            f"ignored the fields after the ones Triangle reads on "
            f"{counted(len(ignored), 'line')} of the holes and regions (line {shown})"
        )
    return PolySections(
        segments, segment_lines, holes, regions, hole_lines, region_lines
    )


def poly_reading(path: Path) -> Reading:
    """A ``.poly`` file as a PSLG (vertices from the ``.node`` beside it when its vertex
    count is 0), with the line of each item; streamed."""
    name = str(path)
    notes: list[str] = []
    lines, header = _VERTEX_HEADER.read(path)
    vertex_file = name
    if header.count == 0:
        node_path = with_extension(file_stem(path, POLY), NODE)
        if not node_path.exists():
            raise FormatError(
                name,
                header.line,
                f"the vertex count is 0, meaning 'vertices in {node_path.name}', but there "
                "is no such file",
            )
        table = read_node_table(node_path)
        vertex_file = str(node_path)
        notes.append(f"vertices read from {node_path}")
    else:
        table = _read_vertices(name, lines, header, followed=True)
    sections = _read_poly_sections(name, lines, len(table.points), table.base, notes)
    _note_duplicate_vertices(table, notes)
    vertex_markers, vertex_attributes = _pslg_vertex_tables(table)
    pslg = PSLG(
        vertices=table.points,
        segments=sections.segments,
        holes=sections.holes,
        regions=sections.regions,
        vertex_markers=vertex_markers,
        vertex_attributes=vertex_attributes,
    )
    sources = SourceLines(
        vertex_file, tuple(table.lines), name, tuple(sections.segment_lines),
        tuple(sections.hole_lines), tuple(sections.region_lines), table.base,
    )
    return Reading(pslg, notes, sources)


def read_poly(path: Path) -> tuple[Value, list[str]]:
    """A ``.poly`` file as a PSLG (:func:`poly_reading` without the lines)."""
    reading = poly_reading(path)
    return reading.value, reading.notes


def _poly_sections_text(
    segments: Sequence[tuple[int, int, int]],
    holes: Sequence[Point2],
    regions: Sequence[RegionSeed],
    number: NumberText,
) -> list[str]:
    out = [f"{len(segments)} 1"]
    out.extend(f"{index} {u} {v} {marker}" for index, (u, v, marker) in enumerate(segments))
    out.append(str(len(holes)))
    out.extend(
        f"{index} {number(point.x)} {number(point.y)}" for index, point in enumerate(holes)
    )
    out.append(str(len(regions)))
    for index, region in enumerate(regions):
        area = "-1" if region.max_area is None else number(region.max_area)
        out.append(
            f"{index} {number(region.point.x)} {number(region.point.y)} "
            f"{number(region.attribute)} {area}"
        )
    return out


def write_poly(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A PSLG as one self-contained ``.poly`` file (vertices inline, 0-based)."""
    pslg = written_value(value, PSLG, "poly")
    number = NumberText(numbers)
    text = _pslg_node_text(pslg, number) + "\n".join(
        _poly_sections_text(pslg.segments, pslg.holes, pslg.regions, number)
    ) + "\n"
    return write_files([(path, text)], overwrite=overwrite, numbers=number)


# -----------------------------------------------------------------------------------------
# format "triangle": a mesh (.node + .ele [+ .neigh] [+ .poly])
# -----------------------------------------------------------------------------------------
@attrs.frozen(slots=True)
class ElementTable:
    """The triangles of an ``.ele`` file, 0-based vertex ids in file order."""

    table: TriangleTable
    first_number: int
    orienter: Orienter | BulkOrientation | None = None  # each triangle oriented as read


_ELE_HEADER = CountHeader(
    "the .ele header", "count corners attributes", "triangle count",
    FixedField("corners per triangle", 3, default=3,
               problem=lambda corners: f"triangles have {corners} nodes; only 3-node "
                                       "triangles are supported"),
)
"""The header of an ``.ele``: only 3-node triangles are read."""


def _bulk_ele(path: Path, nodes: VertexTable) -> ElementTable | None:
    """:func:`_read_ele` of a plain file without attributes (:mod:`geomexact.io.bulk`):
    regular lines of integers, triangles numbered 0, 1, … or 1, 2, …, indices in range,
    one orientation; None for anything else (the line reader then reads it, or names the
    error, having read no further than its line)."""
    base = nodes.base
    triangles = OrientedChunks(nodes.points)
    first = 0

    def numbered(rows: IntArray) -> IntArray | None:
        nonlocal first
        if triangles.empty:
            first = int(rows[0, 0])
        return numbered_corners(rows, first, len(triangles.lines), base, len(nodes.points))

    try:
        with PlainLines(path) as lines:
            tokens, _ = lines.next_line()
            if len(tokens) > 3 or tokens[1:] not in ([], ["3"], ["3", "0"]):
                return None
            header = integer_column(tokens[:1])
            if header is None or header[0] < 0:
                return None
            if not triangles.read_last_section(lines, int(header[0]), numbered):
                return None
    except NotPlain:
        return None
    corners, rows = triangles.tables()
    element_table = TriangleTable(
        path=str(path), triangles=triangle_tuples(corners), lines=triangles.lines,
        first_number=first, vertex_base=base,
    )
    return ElementTable(element_table, first, BulkOrientation(rows, triangles.reversed_count))


@plain_first(_bulk_ele)
def _read_ele(path: Path, nodes: VertexTable) -> ElementTable:
    """The triangles of an ``.ele`` file, streamed, each oriented as it is read (a
    degenerate or mixed triangle stops the reading at its line); a plain file in bulk
    (:func:`_bulk_ele`)."""
    name = str(path)
    lines, header = _ELE_HEADER.read(path)
    count, attribute_count = header.count, header.attributes
    fields = 4 + attribute_count
    vertex_count = len(nodes.points)
    base = nodes.base
    limit = vertex_count + base
    triangles: list[tuple[int, int, int]] = []
    triangle_lines: list[int | None] = []
    attributes: list[Attributes] = []
    first = 0
    orienter: Orienter | None = None
    for index in range(count):
        number, tokens = lines.next_item(
            index, count, f"triangle {index + first} (of {count})", "triangles"
        )
        if len(tokens) != fields:
            expect_exact_fields(
                name, number, tokens, fields,
                "a triangle line 'number a b c" + " attributes" * bool(attribute_count) + "'",
            )
        try:
            label, a, b, c = int(tokens[0]), int(tokens[1]), int(tokens[2]), int(tokens[3])
        except ValueError:
            label = parse_int(name, number, tokens[0], "triangle number")
            for token in tokens[1:4]:
                parse_int(name, number, token, f"corner of triangle {label}")
            raise  # pragma: no cover - one of the calls above raised
        first = check_numbering(name, number, label, index, first, "triangle")
        if not (base <= a < limit and base <= b < limit and base <= c < limit):
            for vertex in (a, b, c):
                check_index(
                    name, number, vertex, vertex_count, base, f"triangle {label}: vertex"
                )
        triangles.append((a - base, b - base, c - base))
        triangle_lines.append(number)
        if attribute_count:
            attributes.append(
                tuple(
                    parse_number(name, number, token, f"attribute of triangle {label}")
                    for token in tokens[4:]
                )
            )
        if orienter is None:  # the first line sets the numbering the messages use
            orienter = Orienter(
                TriangleTable(name, triangles, triangle_lines, first_number=first,
                              vertex_base=base),
                nodes.points, individually=False, vertices=(nodes.path, nodes.lines),
            )
        orienter.add(index)
    lines.expect_end(f"the {counted(count, 'triangle')}")
    table = TriangleTable(
        path=name,
        triangles=triangles,
        lines=triangle_lines,
        attributes=attributes if attribute_count else None,
        first_number=first,
        vertex_base=base,
    )
    return ElementTable(table, first, orienter)


def _check_neigh(path: Path, elements: ElementTable) -> None:
    name = str(path)
    if _bulk_neigh_agrees(path, elements):
        return
    triangles = elements.table.triangles
    count = len(triangles)
    first = elements.first_number
    lines, number, tokens = read_header(path, "the .neigh header", "count 3")
    listed = parse_count(name, number, tokens[0], "triangle count")
    if listed != count:
        raise FormatError(
            name, number, f"lists {listed} triangles, but the .ele file has {count}"
        )
    if len(tokens) > 1 and parse_int(name, number, tokens[1], "neighbours per triangle") != 3:
        raise FormatError(name, number, f"neighbours per triangle is {tokens[1]}, not 3")
    expected = expected_neighbours(triangles)
    for index in range(count):
        number, tokens = lines.next_item(
            index, count, f"the neighbours of triangle {index + first}", "neighbour lines"
        )
        if len(tokens) == 4:
            try:
                label, n0, n1, n2 = (
                    int(tokens[0]), int(tokens[1]), int(tokens[2]), int(tokens[3])
                )
            except ValueError:
                pass
            else:
                want = expected[index]
                if label == index + first and (
                    n0 - first if n0 != -1 else -1,
                    n1 - first if n1 != -1 else -1,
                    n2 - first if n2 != -1 else -1,
                ) == want:
                    continue
        _neigh_problem(name, number, tokens, index, elements, expected[index])
    lines.expect_end(f"the {counted(count, 'neighbour line')}")


def _bulk_neigh_agrees(path: Path, elements: ElementTable) -> bool:
    """True when a plain ``.neigh`` file lists exactly the neighbours of the mesh, checked
    in bulk (:mod:`geomexact.io.bulk`); False leaves it to the line reader (which then
    finds it right, or names the wrong line)."""
    triangles = elements.table.triangles
    count = len(triangles)
    first = elements.first_number
    expected = neighbour_array(np.array(triangles, dtype=np.int64).reshape(-1, 3))
    done = 0
    try:
        with PlainLines(path) as lines:
            if lines.next_line()[0] not in ([str(count)], [str(count), "3"]):
                return False
            for tokens, _ in lines.chunks(count, 4):
                values = integer_column(tokens)
                if values is None:
                    return False
                rows = values.reshape(-1, 4)
                listed = np.where(rows[:, 1:] == -1, -1, rows[:, 1:] - first)
                if not (
                    np.array_equal(rows[:, 0], np.arange(first + done, first + done + len(rows)))
                    and np.array_equal(listed, expected[done : done + len(rows)])
                ):
                    return False
                done += len(rows)
            return lines.at_end()
    except NotPlain:
        return False


def _neigh_problem(
    name: str,
    number: int,
    tokens: list[str],
    index: int,
    elements: ElementTable,
    want: tuple[int, int, int],
) -> None:
    """Raise the FormatError describing why a neighbour line is wrong."""
    first = elements.first_number
    count = len(elements.table.triangles)
    expect_exact_fields(name, number, tokens, 4, "a neighbour line 'number n0 n1 n2'")
    label = parse_int(name, number, tokens[0], "triangle number")
    if label != index + first:
        raise FormatError(name, number, f"triangle numbered {label}, expected {index + first}")
    for corner, token in enumerate(tokens[1:]):
        neighbour = parse_int(name, number, token, f"neighbour of triangle {label}")
        if neighbour != -1:
            neighbour = check_index(
                name, number, neighbour, count, first, f"triangle {label}: neighbour"
            )
        if neighbour != want[corner]:
            vertex = elements.table.triangles[index][corner] + elements.table.vertex_base
            raise FormatError(
                name,
                number,
                f"triangle {label}: the neighbour opposite its vertex {vertex} is listed "
                f"as {_show_triangle(neighbour, first)}, but in the mesh it is "
                f"{_show_triangle(want[corner], first)}",
            )
    raise AssertionError("unreachable: the line was found wrong")  # pragma: no cover


def _show_triangle(index: int, first: int) -> str:
    return "none (-1)" if index == -1 else f"triangle {index + first}"


def _read_mesh_segments(
    path: Path, nodes: VertexTable, notes: list[str]
) -> tuple[list[tuple[int, int, int]], list[int | None]]:
    name = str(path)
    lines, header = _VERTEX_HEADER.read(path)
    if header.count != 0:
        notes.append(f"{path} lists its own vertices; did not use its segments for the mesh")
        return [], []
    sections = _read_poly_sections(name, lines, len(nodes.points), nodes.base, notes)
    notes.append(f"read {counted(len(sections.segments), 'segment')} from {path}")
    if sections.holes or sections.regions:
        notes.append(f"ignored the holes and regions of {path} (a mesh has no use for them)")
    return sections.segments, sections.segment_lines


def _mesh_stem(path: Path) -> Path:
    """The stem of a Triangle mesh named by any of its files (``x.1.ele``, ``x.1.node``,
    ``x.1.neigh``) or by the stem itself (``x.1``)."""
    return file_set_stem(path, (ELE, NODE, NEIGH))


def read_triangle(path: Path) -> tuple[Value, list[str]]:
    """A Triangle mesh named by its ``.ele`` file (or its stem)."""
    stem = _mesh_stem(path)
    ele_path, node_path = with_extension(stem, ELE), with_extension(stem, NODE)
    neigh_path, poly_path = with_extension(stem, NEIGH), with_extension(stem, POLY)
    if not ele_path.exists():
        raise FormatError(str(ele_path), None, "no such file")
    if not node_path.exists():
        raise FormatError(
            str(ele_path),
            None,
            f"a Triangle mesh needs its vertices in {node_path.name}, which does not exist",
        )
    check_file_set((node_path, ele_path, neigh_path, poly_path))
    notes: list[str] = []
    nodes = read_node_table(node_path)
    elements = _read_ele(ele_path, nodes)
    segments: list[tuple[int, int, int]] = []
    segment_lines: list[int | None] = []
    if poly_path.exists():
        segments, segment_lines = _read_mesh_segments(poly_path, nodes, notes)
    mesh = build_mesh(
        nodes.points,
        nodes.lines,
        elements.table,
        point_path=str(node_path),
        notes=notes,
        vertex_markers=nodes.markers if nodes.has_markers else None,
        vertex_attributes=nodes.attributes if nodes.attribute_count else None,
        segments=segments,
        segment_lines=segment_lines,
        segment_path=str(poly_path),
        orienter=elements.orienter,
    )
    if neigh_path.exists():
        _check_neigh(neigh_path, elements)
        notes.append(f"{neigh_path.name} agrees with the adjacency")
    return mesh, notes


def triangle_output_paths(path: Path) -> tuple[Path, ...]:
    """The files :func:`write_triangle` may write for ``path``."""
    stem = _mesh_stem(path)
    return tuple(with_extension(stem, extension) for extension in (NODE, ELE, NEIGH, POLY))


def write_triangle(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A mesh as ``stem.node``, ``stem.ele`` and ``stem.neigh`` (0-based, triangles in
    canonical order), plus ``stem.poly`` (vertex count 0) when it has segments."""
    mesh = written_value(value, Mesh2, "triangle")
    stem = _mesh_stem(path)
    number = NumberText(numbers)
    vertex_markers = mesh.vertex_markers
    points = mesh.point_list()
    markers = [vertex_markers.get(index, 0) for index in range(mesh.vertex_count)]
    vertex_attributes = [mesh.vertex_attributes.get(index) for index in range(len(points))]
    node_text = _node_text(points, markers, vertex_attributes, number)
    triangles = triangle_array(mesh)
    total = len(triangles)
    ele: str | Iterator[str] = itertools.chain(
        [f"{total} 3 0\n"], row_chunks("%s %s %s %s\n", triangles, numbered=True)
    )
    if len(mesh.triangle_attributes):
        flat = triangles.ravel().tolist()
        keys = list(zip(flat[0::3], flat[1::3], flat[2::3], strict=True))
        count, rows = uniform_attributes(
            [mesh.triangle_attributes.get(triangle) for triangle in keys], "triangle"
        )
        lines = [f"{total} 3 {count}"]
        for index, (a, b, c) in enumerate(keys):
            lines.append(" ".join([str(index), str(a), str(b), str(c),
                                   *map(number, rows[index])]))
        ele = "\n".join(lines) + "\n"
    neigh = itertools.chain(
        [f"{total} 3\n"],
        row_chunks("%s %s %s %s\n", neighbour_array(triangles), numbered=True),
    )
    files: list[tuple[Path, str | Iterator[str]]] = [
        (with_extension(stem, NODE), node_text),
        (with_extension(stem, ELE), ele),
        (with_extension(stem, NEIGH), neigh),
    ]
    segments = mesh.segment_list()
    if segments:
        poly = ["0 2 0 1", *_poly_sections_text(segments, (), (), number)]
        files.append((with_extension(stem, POLY), "\n".join(poly) + "\n"))
    return write_files(files, overwrite=overwrite, numbers=number,
                       members=triangle_output_paths(path))

