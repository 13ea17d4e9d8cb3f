"""Triangle lists: one triangle per line, ``x1 y1 x2 y2 x3 y3`` (the format of the
LeppDelaunay course files).  Spec: ``specs/formats/trilist.md``.

Vertices are the distinct exact points in order of first appearance; each triangle is
oriented on its own (a clockwise one is reversed, and the count is noted).  Writing lists a
mesh's triangles in canonical order, each counter-clockwise from its smallest vertex id;
vertices in no triangle, markers, attributes and segments are not representable.
"""

from __future__ import annotations

from pathlib import Path

from geomexact.errors import FormatError
from geomexact.io import registry
from geomexact.io.files import read_lines
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.snapshot import Mesh2

_NAMES = ("x1", "y1", "x2", "y2", "x3", "y3")


def read_triangle_list(path: Path) -> tuple[registry.Value, list[str]]:
    """A triangle-list file as a Mesh2 (vertices merged by exact coordinates)."""
    name = str(path)
    notes: list[str] = []
    ids: dict[tuple[Rational, Rational], int] = {}
    points: list[Point2] = []
    point_lines: list[int | None] = []
    triangles: list[tuple[int, int, int]] = []
    triangle_lines: list[int | None] = []
    table = registry.TriangleTable(path=name, triangles=triangles, lines=triangle_lines)
    orienter = registry.Orienter(table, points, individually=True)
    for number, tokens in registry.token_lines(read_lines(path)):  # streamed
        if len(tokens) != 6:
            raise FormatError(
                name,
                number,
                f"a triangle line is 'x1 y1 x2 y2 x3 y3', found {len(tokens)} fields: "
                f"{registry.quoted_tokens(tokens)}",
            )
        values = [
            registry.parse_number(name, number, token, field)
            for token, field in zip(tokens, _NAMES, strict=True)
        ]
        corners = []
        for x, y in ((values[0], values[1]), (values[2], values[3]), (values[4], values[5])):
            vertex = ids.get((x, y))
            if vertex is None:
                vertex = ids[(x, y)] = len(points)
                points.append(point2(x, y))
                point_lines.append(number)
            corners.append(vertex)
        triangles.append((corners[0], corners[1], corners[2]))
        triangle_lines.append(number)
        orienter.add(len(triangles) - 1)  # a degenerate triangle stops the reading here
    if not triangles:
        notes.append("the file lists no triangles")
    mesh = registry.build_mesh(
        points, point_lines, table, point_path=name, notes=notes, orient_individually=True,
        orienter=orienter,
    )
    return mesh, notes


def write_triangle_list(
    path: Path, value: registry.Value, /, *, overwrite: bool, numbers: registry.NumberStyle
) -> registry.WriteReport:
    """A Mesh2's triangles, one ``x1 y1 x2 y2 x3 y3`` line each (canonical order); its
    markers, attributes, segments and unused vertices are dropped (and reported)."""
    mesh = registry.written_value(value, Mesh2, "trilist")
    number = registry.NumberText(numbers)
    text = {index: f"{number(p.x)} {number(p.y)}" for index, p in mesh.vertices.items()}
    triangles = mesh.triangles()
    out = [f"{text[a]} {text[b]} {text[c]}" for a, b, c in triangles]
    dropped = registry.dropped_parts(mesh, ())
    unused = mesh.vertex_count - len({vertex for triangle in triangles for vertex in triangle})
    if unused:
        dropped += (f"{unused} vertex in no triangle" if unused == 1
                    else f"{unused} vertices in no triangle",)
    return registry.write_files(
        [(path, "".join(line + "\n" for line in out))],
        overwrite=overwrite,
        numbers=number,
        dropped=dropped,
    )
