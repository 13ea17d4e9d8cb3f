"""Mellado's text format (the Lepp-Delaunay / quasi-Delaunay study, 2023): sections
``Vertices``, ``Triangles`` and ``Neighbors``, with lines ``v x y``, ``t a b c`` and
``n …``.  Spec: ``specs/formats/mellado.md``.

Indices are 0-based (−1: no neighbour); a file whose triangles use the indices 1…N of N
vertices, and never 0, is read as 1-based (and noted).  The paper describes ``n`` lines in
two ways, so both are accepted, decided by count and arity: one ``n`` line per triangle
with three entries (the triangles across the edges opposite its first, second and third
vertex, −1 on the boundary), or one per vertex listing its neighbouring vertices.  Either
is checked against the triangles, and a mismatch is a ``FormatError`` naming the ``n``
line.  Writing uses the triangle form, 0-based.
"""

from __future__ import annotations

from pathlib import Path

from geomexact.errors import FormatError
from geomexact.io import registry
from geomexact.io.files import read_lines
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.snapshot import Mesh2, canonical_triangle

_SECTIONS = {"vertices": "v", "triangles": "t", "neighbors": "n", "neighbours": "n"}
_ARITY = {"v": 2, "t": 3}


def _index(path: str, line: int, token: str, what: str) -> int:
    try:
        return int(token)
    except ValueError:
        raise FormatError(path, line, f"{what} must be an integer, not {token!r}") from None


def looks_like_mellado(path: Path) -> bool:
    """True when the first data line of ``path`` is a section header of this format
    (``Vertices``, ``Triangles``, ``Neighbors``): Mellado's programs write ``.txt`` files,
    which otherwise name the triangle list.  Reads no further than that line; a file that
    cannot be read is left to the reader to report."""
    try:
        for _, tokens in registry.token_lines(read_lines(path)):
            return tokens[0].lower() in _SECTIONS
    except (OSError, FormatError):
        return False
    return False


def read_mellado(path: Path) -> tuple[registry.Value, list[str]]:
    """A Mellado text file as a :class:`Mesh2` (module docstring)."""
    name = str(path)
    notes: list[str] = []
    section: str | None = None
    declared: dict[str, tuple[int, int]] = {}  # record -> (count, line of the header)
    points: list[Point2] = []
    point_lines: list[int | None] = []
    corners: list[tuple[int, int, int]] = []
    corner_lines: list[int | None] = []
    neighbours: list[tuple[int, list[int]]] = []  # (line, entries)
    for number, tokens in registry.token_lines(read_lines(path)):
        head = tokens[0].lower()
        if head in _SECTIONS:
            section = _SECTIONS[head]
            if len(tokens) > 2:
                raise FormatError(name, number, f"a section header is '{tokens[0]}' with an "
                                  f"optional count, found {registry.quoted_tokens(tokens)}")
            if len(tokens) == 2:
                declared[section] = (_index(name, number, tokens[1], "the count"), number)
            continue
        if section is None:
            raise FormatError(name, number, "data before the first section (Vertices, "
                              f"Triangles or Neighbors): {registry.quoted_tokens(tokens)}")
        if head != section:
            raise FormatError(name, number, f"a line of this section starts with "
                              f"'{section}', found {registry.quoted_tokens(tokens)}")
        values = tokens[1:]
        if section in _ARITY and len(values) != _ARITY[section]:
            shape = "v x y" if section == "v" else "t a b c"
            raise FormatError(name, number, f"a line of this section is '{shape}', found "
                              f"{registry.quoted_tokens(tokens)}")
        if section == "v":
            x, y = (registry.parse_number(name, number, token, field)
                    for token, field in zip(values, ("x", "y"), strict=True))
            points.append(point2(x, y))
            point_lines.append(number)
        elif section == "t":
            a, b, c = (_index(name, number, token, "a vertex index") for token in values)
            corners.append((a, b, c))
            corner_lines.append(number)
        else:
            neighbours.append(
                (number, [_index(name, number, token, "a neighbour") for token in values])
            )
    for record, found in (("v", len(points)), ("t", len(corners)), ("n", len(neighbours))):
        if record in declared and declared[record][0] != found:
            count, line = declared[record]
            raise FormatError(name, line, f"the header announces {count} lines, the "
                              f"section has {found}")
    if not corners:
        raise FormatError(name, None, "the file has no Triangles section lines")
    used = [vertex for triangle in corners for vertex in triangle]
    base = 1 if min(used) == 1 and max(used) == len(points) else 0
    if base:
        notes.append("vertex indices are 1-based (0 is never used and N is)")
    triangles: list[tuple[int, int, int]] = []
    for (a, b, c), where in zip(corners, corner_lines, strict=True):
        shifted = (a - base, b - base, c - base)
        for vertex in shifted:
            if not 0 <= vertex < len(points):
                raise FormatError(name, where, f"vertex index {vertex + base} is out of range "
                                  f"({base}…{len(points) - 1 + base})")
        triangles.append(shifted)
    if neighbours:
        _check_neighbours(name, triangles, len(points), neighbours, base, notes)
    table = registry.TriangleTable(path=name, triangles=triangles, lines=corner_lines,
                                   vertex_base=base)
    mesh = registry.build_mesh(points, point_lines, table, point_path=name, notes=notes)
    return mesh, notes


def _check_neighbours(
    name: str, triangles: list[tuple[int, int, int]], vertex_count: int,
    neighbours: list[tuple[int, list[int]]], base: int, notes: list[str],
) -> None:
    """Check the ``n`` lines against the triangles, in the form their count and arity
    select (module docstring)."""
    across: dict[tuple[int, int], int] = {}
    for index, (a, b, c) in enumerate(triangles):
        for u, v in ((a, b), (b, c), (c, a)):
            across[(u, v)] = index
    triangle_form = len(neighbours) == len(triangles) and all(
        len(entries) == 3 for _, entries in neighbours
    )
    if triangle_form:
        for index, (line, entries) in enumerate(neighbours):
            a, b, c = triangles[index]
            for (u, v), given in zip(((b, c), (c, a), (a, b)), entries, strict=True):
                actual = across.get((v, u))  # a consistent orientation: the other way
                expected = -1 if actual is None else actual + base
                if given != expected:
                    raise FormatError(
                        name, line, f"triangle {index + base}: the neighbour across the "
                        f"edge {u + base}-{v + base} is {expected}, the file says {given}"
                    )
        notes.append("Neighbors: one line per triangle")
        return
    if len(neighbours) != vertex_count:
        line = neighbours[0][0]
        raise FormatError(name, line, f"the Neighbors section has {len(neighbours)} lines: "
                          f"neither one per triangle ({len(triangles)}, three entries each) "
                          f"nor one per vertex ({vertex_count})")
    adjacent: list[set[int]] = [set() for _ in range(vertex_count)]
    for u, v in across:
        adjacent[u].add(v)
        adjacent[v].add(u)
    for vertex, (line, entries) in enumerate(neighbours):
        listed = {entry - base for entry in entries}
        if listed != adjacent[vertex]:
            around = " ".join(str(w + base) for w in sorted(adjacent[vertex]))
            raise FormatError(name, line, f"vertex {vertex + base}: its neighbours are "
                              f"{around or 'none'}, the file says "
                              f"{' '.join(map(str, entries)) or 'none'}")
    notes.append("Neighbors: one line per vertex")


def write_mellado(
    path: Path, value: registry.Value, /, *, overwrite: bool, numbers: registry.NumberStyle
) -> registry.WriteReport:
    """A Mesh2 in Mellado's text format: its vertices, its triangles (canonical order,
    counter-clockwise) and one ``n`` line per triangle, 0-based; markers, attributes and
    segments are dropped (and reported)."""
    mesh = registry.written_value(value, Mesh2, "mellado")
    number = registry.NumberText(numbers)
    ids = {vertex: index for index, vertex in enumerate(sorted(mesh.vertices.keys()))}
    triangles = mesh.triangles()
    position = {triangle: index for index, triangle in enumerate(triangles)}
    out = [f"Vertices {len(ids)}"]
    out += [f"v {number(mesh.point(v).x)} {number(mesh.point(v).y)}" for v in ids]
    out.append(f"Triangles {len(triangles)}")
    out += [f"t {ids[a]} {ids[b]} {ids[c]}" for a, b, c in triangles]
    out.append(f"Neighbors {len(triangles)}")
    for a, b, c in triangles:
        entries = []
        for u, v in ((b, c), (c, a), (a, b)):
            apex = mesh.apex(v, u)
            entries.append(-1 if apex is None else position[canonical_triangle(v, u, apex)])
        out.append("n " + " ".join(map(str, entries)))
    return registry.write_files(
        [(path, "".join(line + "\n" for line in out))],
        overwrite=overwrite,
        numbers=number,
        dropped=registry.dropped_parts(mesh, ()),
    )
