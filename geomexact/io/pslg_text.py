"""The line-tagged PSLG text format (``.pslg``): one record per line, tagged by its first
token.  Spec: ``specs/formats/pslg.md``.

::

    # comment
    v x y [marker [attribute ...]]      vertex; ids 0, 1, 2, ... in order of appearance
    s a b [marker]                      segment between two vertex ids
    h x y                               hole seed
    r x y attribute [max_area]          region seed (max_area <= 0 or absent: none)
    t a b c [attribute ...]             triangle (vertex ids, 0-based)
    n n0 n1 n2                          neighbours of the k-th triangle (k-th n line):
                                        the triangle across the edge opposite a, b, c;
                                        -1 for none

A file with ``t`` records reads as a :class:`Mesh2` (its ``s`` records become constrained
segments, ``n`` records are checked against the adjacency); without, as a :class:`PSLG`.
Records may come in any order; ids refer to vertices anywhere in the file.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from pathlib import Path

import attrs

from geomexact.errors import FormatError, UnsupportedValueError
from geomexact.io import registry
from geomexact.io.files import read_lines
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.pslg import PSLG, RegionSeed
from geomexact.mesh2d.snapshot import Attributes, Mesh2

_TAGS = "v, s, h, r, t or n"


@attrs.define
class _Records:
    points: list[Point2] = attrs.Factory(list)
    point_lines: list[int | None] = attrs.Factory(list)
    markers: list[int | None] = attrs.Factory(list)
    vertex_attributes: list[tuple[int, Attributes]] = attrs.Factory(list)
    segments: list[tuple[int, int, int, int]] = attrs.Factory(list)  # a, b, marker, line
    holes: list[Point2] = attrs.Factory(list)
    regions: list[RegionSeed] = attrs.Factory(list)
    region_lines: list[int] = attrs.Factory(list)
    hole_lines: list[int] = attrs.Factory(list)
    triangles: list[tuple[int, int, int, int]] = attrs.Factory(list)  # a, b, c, line
    triangle_attributes: list[tuple[int, Attributes]] = attrs.Factory(list)
    neighbours: list[tuple[int, int, int, int]] = attrs.Factory(list)  # n0, n1, n2, line


def _attributes(
    name: str, number: int, tokens: Sequence[str], owner: str
) -> tuple[Rational, ...]:
    """The exact attribute values ``tokens`` of ``owner`` (a vertex or a triangle)."""
    return tuple(registry.parse_number(name, number, token, f"attribute of {owner}")
                 for token in tokens)


def _parse(name: str, lines: Iterable[registry.NumberedLine]) -> _Records:
    records = _Records()
    for number, tokens in lines:
        tag = tokens[0]
        if tag == "v":
            registry.expect_fields(name, number, tokens, 3,
                                   "a vertex record 'v x y [marker [attributes]]'")
            index = len(records.points)
            x = registry.parse_number(name, number, tokens[1], f"x of vertex {index}")
            y = registry.parse_number(name, number, tokens[2], f"y of vertex {index}")
            records.points.append(point2(x, y))
            records.point_lines.append(number)
            records.markers.append(
                registry.parse_int(name, number, tokens[3], f"marker of vertex {index}")
                if len(tokens) > 3
                else None
            )
            records.vertex_attributes.append(
                (number, _attributes(name, number, tokens[4:], f"vertex {index}"))
            )
        elif tag == "s":
            registry.expect_field_range(name, number, tokens, 3, 4,
                                        "a segment record 's a b [marker]'")
            a = registry.parse_int(name, number, tokens[1], "segment endpoint")
            b = registry.parse_int(name, number, tokens[2], "segment endpoint")
            marker = (registry.parse_int(name, number, tokens[3], "segment marker")
                      if len(tokens) > 3 else 0)
            records.segments.append((a, b, marker, number))
        elif tag == "h":
            registry.expect_exact_fields(name, number, tokens, 3, "a hole record 'h x y'")
            records.holes.append(
                point2(
                    registry.parse_number(name, number, tokens[1], "x of hole"),
                    registry.parse_number(name, number, tokens[2], "y of hole"),
                )
            )
            records.hole_lines.append(number)
        elif tag == "r":
            if not 4 <= len(tokens) <= 5:
                raise FormatError(
                    name,
                    number,
                    "a region record is 'r x y attribute [max_area]', found "
                    f"{registry.quoted_tokens(tokens)}",
                )
            point = point2(
                registry.parse_number(name, number, tokens[1], "x of region"),
                registry.parse_number(name, number, tokens[2], "y of region"),
            )
            attribute = registry.parse_number(name, number, tokens[3], "attribute of region")
            area: Rational | None = None
            if len(tokens) == 5:
                area = registry.parse_number(name, number, tokens[4], "maximum area of region")
                if area <= 0:
                    area = None
            records.regions.append(RegionSeed(point, attribute, area))
            records.region_lines.append(number)
        elif tag == "t":
            registry.expect_fields(name, number, tokens, 4,
                                   "a triangle record 't a b c [attributes]'")
            index = len(records.triangles)
            a, b, c = (
                registry.parse_int(name, number, token, f"vertex of triangle {index}")
                for token in tokens[1:4]
            )
            records.triangles.append((a, b, c, number))
            records.triangle_attributes.append(
                (number, _attributes(name, number, tokens[4:], f"triangle {index}"))
            )
        elif tag == "n":
            registry.expect_exact_fields(name, number, tokens, 4, "a neighbour record 'n n0 n1 n2'")
            n0, n1, n2 = (
                registry.parse_int(name, number, token, "neighbour") for token in tokens[1:4]
            )
            records.neighbours.append((n0, n1, n2, number))
        else:
            raise FormatError(name, number,
                              f"unknown record {registry.quoted(tag)}; expected {_TAGS}")
    return records


def _uniform(
    name: str, rows: list[tuple[int, Attributes]], what: str
) -> list[Attributes] | None:
    """The attribute rows when every record has the same number (None when all have
    none); FormatError naming the first record that differs."""
    if not rows or all(not values for _, values in rows):
        return None
    size = len(rows[0][1])
    for number, values in rows:
        if len(values) != size:
            raise FormatError(
                name,
                number,
                f"this {what} has {len(values)} attributes, but the first {what} has {size}",
            )
    return [values for _, values in rows]


def read_pslg_text(path: Path) -> tuple[registry.Value, list[str]]:
    """A ``.pslg`` file as a Mesh2 (with ``t`` records) or a PSLG
    (:func:`pslg_text_reading` without the lines)."""
    reading = pslg_text_reading(path)
    return reading.value, reading.notes


def pslg_text_reading(path: Path) -> registry.Reading:
    """A ``.pslg`` file as a Mesh2 (with ``t`` records) or a PSLG, with the line of each
    vertex, segment, hole and region; streamed."""
    name = str(path)
    notes: list[str] = []
    records = _parse(name, registry.token_lines(read_lines(path)))
    count = len(records.points)
    vertex_markers = (
        [marker or 0 for marker in records.markers]
        if any(marker is not None for marker in records.markers)
        else None
    )
    vertex_attributes = _uniform(name, records.vertex_attributes, "vertex")
    segments = []
    segment_lines: list[int | None] = []
    for a, b, marker, number in records.segments:
        u = registry.check_index(name, number, a, count, 0, "segment endpoint: vertex")
        v = registry.check_index(name, number, b, count, 0, "segment endpoint: vertex")
        if u == v:
            raise FormatError(name, number, f"segment ({a}, {b}) has equal ends")
        segments.append((u, v, marker))
        segment_lines.append(number)
    if not records.triangles:
        if records.neighbours:
            raise FormatError(
                name, records.neighbours[0][3], "neighbour records need triangle records"
            )
        registry.note_duplicate_points(records.points, records.point_lines, notes)
        pslg = PSLG(
            vertices=records.points,
            segments=segments,
            holes=records.holes,
            regions=records.regions,
            vertex_markers=tuple(vertex_markers) if vertex_markers is not None else (),
            vertex_attributes=tuple(vertex_attributes) if vertex_attributes is not None else (),
        )
        sources = registry.SourceLines(
            name, tuple(records.point_lines), name, tuple(segment_lines),
            tuple(records.hole_lines), tuple(records.region_lines),
        )
        return registry.Reading(pslg, notes, sources)
    if records.holes or records.regions:
        line = (records.hole_lines + records.region_lines)[0]
        raise FormatError(
            name, line, "hole and region records belong to a PSLG, not to a file of triangles"
        )
    triangles: list[tuple[int, int, int]] = []
    for a, b, c, number in records.triangles:
        corners = [
            registry.check_index(name, number, vertex, count, 0, "triangle corner: vertex")
            for vertex in (a, b, c)
        ]
        triangles.append((corners[0], corners[1], corners[2]))
    table = registry.TriangleTable(
        path=name,
        triangles=triangles,
        lines=[number for *_, number in records.triangles],
        attributes=_uniform(name, records.triangle_attributes, "triangle"),
    )
    mesh = registry.build_mesh(
        records.points,
        records.point_lines,
        table,
        point_path=name,
        notes=notes,
        vertex_markers=vertex_markers,
        vertex_attributes=vertex_attributes,
        segments=segments,
        segment_lines=segment_lines,
    )
    if records.neighbours:
        _check_neighbours(name, table, records.neighbours)
        notes.append("the neighbour records agree with the adjacency")
    sources = registry.SourceLines(name, tuple(records.point_lines), name, tuple(segment_lines))
    return registry.Reading(mesh, notes, sources)


def _check_neighbours(
    name: str, table: registry.TriangleTable, neighbours: list[tuple[int, int, int, int]]
) -> None:
    count = len(table.triangles)
    if len(neighbours) != count:
        line = neighbours[min(count, len(neighbours) - 1)][3]
        raise FormatError(
            name, line, f"{len(neighbours)} neighbour records for {count} triangles"
        )
    expected = registry.expected_neighbours(table.triangles)
    for index, (*listed, number) in enumerate(neighbours):
        for corner, neighbour in enumerate(listed):
            if neighbour != -1:
                registry.check_index(name, number, neighbour, count, 0, "neighbour: triangle")
            want = expected[index][corner]
            if neighbour != want:
                vertex = table.triangles[index][corner]
                raise FormatError(
                    name,
                    number,
                    f"triangle {index}: the neighbour opposite its vertex {vertex} is listed "
                    f"as {neighbour}, but in the mesh it is {want} (-1: none)",
                )


def write_pslg_text(
    path: Path, value: registry.Value, /, *, overwrite: bool, numbers: registry.NumberStyle
) -> registry.WriteReport:
    """A PSLG (v, s, h, r records) or a Mesh2 (v, t, n, s records) as a ``.pslg`` file
    (nothing dropped)."""
    number = registry.NumberText(numbers)
    out: list[str] = []
    if isinstance(value, PSLG):
        markers = value.vertex_markers or (0,) * len(value.vertices)
        show_markers = bool(value.vertex_markers or value.vertex_attributes)
        attributes = value.vertex_attributes or ((),) * len(value.vertices)
        for index, point in enumerate(value.vertices):
            fields = ["v", number(point.x), number(point.y)]
            if show_markers:
                fields.append(str(markers[index]))
                fields.extend(map(number, attributes[index]))
            out.append(" ".join(fields))
        out.extend(f"s {a} {b} {marker}" for a, b, marker in value.segments)
        out.extend(f"h {number(point.x)} {number(point.y)}" for point in value.holes)
        for region in value.regions:
            area = "" if region.max_area is None else f" {number(region.max_area)}"
            out.append(
                f"r {number(region.point.x)} {number(region.point.y)} "
                f"{number(region.attribute)}{area}"
            )
    elif isinstance(value, Mesh2):
        _mesh_records(value, number, out)
    else:
        raise UnsupportedValueError(
            f"the pslg format writes a PSLG or a Mesh2, not a {type(value).__name__}"
        )
    return registry.write_files(
        [(path, "".join(line + "\n" for line in out))], overwrite=overwrite, numbers=number
    )


def _mesh_records(mesh: Mesh2, number: Callable[[Rational], str], out: list[str]) -> None:
    count = mesh.vertex_count
    vertex_count, vertex_rows = registry.uniform_attributes(
        [mesh.vertex_attributes.get(index) for index in range(count)], "vertex"
    )
    show_markers = bool(mesh.vertex_markers) or vertex_count > 0
    for index, point in enumerate(mesh.point_list()):
        fields = ["v", number(point.x), number(point.y)]
        if show_markers:
            fields.append(str(mesh.vertex_markers.get(index, 0)))
            fields.extend(number(value) for value in vertex_rows[index])
        out.append(" ".join(fields))
    triangles = mesh.triangles()
    _, rows = registry.uniform_attributes(
        [mesh.triangle_attributes.get(triangle) for triangle in triangles], "triangle"
    )
    for index, (a, b, c) in enumerate(triangles):
        out.append(" ".join(["t", str(a), str(b), str(c), *(number(v) for v in rows[index])]))
    out.extend(f"n {n0} {n1} {n2}" for n0, n1, n2 in registry.expected_neighbours(triangles))
    out.extend(f"s {u} {v} {marker}" for u, v, marker in mesh.segment_list())
