"""Object File Format (OFF), including the old Geomview ``{ appearance {…} LIST … }``
wrapper, for planar meshes (every z = 0).  Spec: ``specs/formats/off.md``.

Reading gives a :class:`Mesh2` when every face is a triangle (one orientation for the whole
file: all clockwise is reversed and noted, mixed is an error), else a
:class:`PolygonMesh` (the same orientation rule, by exact signed area).  Writing takes
either; markers, attributes and segments of a mesh have no place in OFF and are dropped.
"""

from __future__ import annotations

from pathlib import Path

from geomexact.errors import FormatError, UnsupportedValueError
from geomexact.io.files import read_text
from geomexact.io.registry import (
    Lines,
    NumberedLine,
    NumberStyle,
    NumberText,
    TriangleTable,
    Value,
    WriteReport,
    all_clockwise_note,
    build_mesh,
    counted,
    dropped_parts,
    expect_field_range,
    expect_fields,
    note_duplicate_points,
    parse_count,
    parse_int,
    parse_number,
    write_files,
)
from geomexact.kernel.numbers import ZERO, Rational
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.snapshot import Mesh2

_BRACES = "{}"


# -----------------------------------------------------------------------------------------
# the Geomview wrapper
# -----------------------------------------------------------------------------------------
class _Unwrapper:
    """Blanks the ``{ [appearance {…}] [LIST] [{] … }`` wrapper around an OFF object in
    comment-free rows, keeping every other character (and so every line number)."""

    def __init__(self, path: str, rows: list[str]) -> None:
        self.path = path
        self.rows = rows
        self.row = 0
        self.col = 0

    def skip_space(self) -> bool:
        """Move to the next non-blank character; False at the end of the text."""
        while self.row < len(self.rows):
            text = self.rows[self.row]
            while self.col < len(text) and text[self.col].isspace():
                self.col += 1
            if self.col < len(text):
                return True
            self.row += 1
            self.col = 0
        return False

    def _blank(self, start: int, end: int) -> None:
        text = self.rows[self.row]
        self.rows[self.row] = text[:start] + " " * (end - start) + text[end:]

    def _word(self) -> str:
        text = self.rows[self.row]
        end = self.col
        while end < len(text) and not text[end].isspace() and text[end] not in _BRACES:
            end += 1
        return text[self.col : end]

    def _blank_block(self) -> None:
        """Blank a balanced ``{ … }`` starting at the cursor."""
        start_line = self.row + 1
        depth = 0
        while self.skip_space():
            text = self.rows[self.row]
            char = text[self.col]
            self._blank(self.col, self.col + 1)
            self.col += 1
            if char == "{":
                depth += 1
            elif char == "}":
                depth -= 1
                if depth == 0:
                    return
        raise FormatError(self.path, start_line, "the '{' of this block is never closed")

    def unwrap(self) -> int:
        """Blank the opening part of the wrapper; return how many '}' must close it."""
        opened = 0
        while self.skip_space():
            text = self.rows[self.row]
            if text[self.col] == "{":
                self._blank(self.col, self.col + 1)
                self.col += 1
                opened += 1
                continue
            if not opened:
                return 0
            word = self._word()
            if word.lower() == "appearance":
                self._blank(self.col, self.col + len(word))
                self.col += len(word)
                if not self.skip_space() or self.rows[self.row][self.col] != "{":
                    raise FormatError(
                        self.path, self.row + 1, "'appearance' must be followed by '{ … }'"
                    )
                self._blank_block()
            elif word == "LIST":
                self._blank(self.col, self.col + len(word))
                self.col += len(word)
            else:
                break
        return opened

    def close(self, opened: int, opening_line: int) -> None:
        """Blank the ``opened`` closing braces at the end of the text."""
        row = len(self.rows) - 1
        while opened and row >= 0:
            text = self.rows[row]
            col = len(text) - 1
            while col >= 0 and opened:
                char = text[col]
                if char == "}":
                    text = text[:col] + " " + text[col + 1 :]
                    opened -= 1
                elif not char.isspace():
                    raise FormatError(
                        self.path,
                        row + 1,
                        f"expected '}}' closing the Geomview block opened on line "
                        f"{opening_line}, found {char!r}",
                    )
                col -= 1
            self.rows[row] = text
            row -= 1
        if opened:  # pragma: no cover - the opening braces are in the text too
            raise FormatError(self.path, opening_line, "the Geomview block is never closed")


def _off_lines(path: str, text: str, notes: list[str]) -> list[NumberedLine]:
    text = text.removeprefix("\ufeff")  # a byte-order mark is not data
    rows = [line[: line.index("#")] if "#" in line else line for line in text.split("\n")]
    unwrapper = _Unwrapper(path, rows)
    if unwrapper.skip_space():
        opening_line = unwrapper.row + 1
        opened = unwrapper.unwrap()
        if opened:
            unwrapper.close(opened, opening_line)
            notes.append("read the OFF object inside a Geomview '{ … }' wrapper")
    result: list[NumberedLine] = []
    for number, row in enumerate(rows, start=1):
        tokens = row.split()
        if tokens:
            result.append((number, tokens))
    return result


# -----------------------------------------------------------------------------------------
# reading
# -----------------------------------------------------------------------------------------
def _keyword(path: str, number: int, token: str) -> bool:
    """True when ``token`` is an OFF keyword (``OFF``, ``COFF``, ``NOFF``, ``STOFF``, …);
    FormatError for the variants geomexact cannot read (``4OFF``, ``nOFF``)."""
    if not token.upper().endswith("OFF"):
        return False
    prefix = token[:-3]
    if "4" in prefix or "n" in prefix:
        raise FormatError(
            path, number, f"{token}: 4D and n-dimensional OFF variants are not supported"
        )
    rest = prefix.upper()
    for part in ("ST", "C", "N"):
        rest = rest.replace(part, "", 1)
    if rest:
        raise FormatError(path, number, f"unknown OFF keyword {token!r}")
    return True


def read_off(path: Path) -> tuple[Value, list[str]]:
    """An OFF file as a Mesh2 (all faces triangles) or a PolygonMesh."""
    name = str(path)
    notes: list[str] = []
    lines = Lines(name, _off_lines(name, read_text(path), notes))
    number, tokens = lines.next("the OFF header")
    if _keyword(name, number, tokens[0]):
        tokens = tokens[1:]
        if tokens and tokens[0].upper() == "BINARY":
            raise FormatError(name, number, "binary OFF is not supported")
        if not tokens:
            number, tokens = lines.next("the counts 'vertices faces edges'")
    expect_field_range(name, number, tokens, 2, 3, "the counts 'vertices faces edges'")
    vertex_count = parse_count(name, number, tokens[0], "vertex count")
    face_count = parse_count(name, number, tokens[1], "face count")
    if len(tokens) == 3:
        parse_count(name, number, tokens[2], "edge count")
    points: list[Point2] = []
    point_lines: list[int | None] = []
    for index in range(vertex_count):
        number, tokens = lines.next(f"vertex {index} (of {vertex_count})")
        expect_fields(name, number, tokens, 3, f"vertex {index} 'x y z'")
        x = parse_number(name, number, tokens[0], f"x of vertex {index}")
        y = parse_number(name, number, tokens[1], f"y of vertex {index}")
        z = parse_number(name, number, tokens[2], f"z of vertex {index}")
        if z != 0:
            raise FormatError(
                name,
                number,
                f"vertex {index} has z = {tokens[2]}; only planar meshes (z = 0 for every "
                "vertex) are supported",
            )
        points.append(point2(x, y))
        point_lines.append(number)
    faces: list[tuple[int, ...]] = []
    face_lines: list[int | None] = []
    for index in range(face_count):
        number, tokens = lines.next(f"face {index} (of {face_count})")
        size = parse_int(name, number, tokens[0], f"vertex count of face {index}")
        if size < 3:
            raise FormatError(
                name, number, f"face {index} has {size} vertices; a polygon needs at least 3"
            )
        expect_fields(name, number, tokens, size + 1, f"face {index} with {size} vertices")
        face = []
        for token in tokens[1 : size + 1]:
            vertex = parse_int(name, number, token, f"vertex of face {index}")
            if not 0 <= vertex < vertex_count:
                raise FormatError(
                    name,
                    number,
                    f"face {index}: vertex {vertex} is out of range (expected 0.."
                    f"{vertex_count - 1})",
                )
            face.append(vertex)
        faces.append(tuple(face))
        face_lines.append(number)
    lines.expect_end(f"the {counted(face_count, 'face')}")
    if all(len(face) == 3 for face in faces):
        table = TriangleTable(
            path=name,
            triangles=[(face[0], face[1], face[2]) for face in faces],
            lines=face_lines,
        )
        mesh = build_mesh(points, point_lines, table, point_path=name, notes=notes)
        return mesh, notes
    polygons = _orient_polygons(name, points, faces, face_lines, notes)
    note_duplicate_points(points, point_lines, notes)
    return PolygonMesh(vertices=points, polygons=polygons), notes


def _twice_area(points: list[Point2], polygon: tuple[int, ...]) -> Rational:
    total = ZERO
    previous = points[polygon[-1]]
    for vertex in polygon:
        point = points[vertex]
        total += previous.x * point.y - point.x * previous.y
        previous = point
    return total


def _orient_polygons(
    path: str,
    points: list[Point2],
    faces: list[tuple[int, ...]],
    lines: list[int | None],
    notes: list[str],
) -> list[tuple[int, ...]]:
    def describe(index: int) -> str:
        return f"face {index} ({' '.join(map(str, faces[index]))}) on line {lines[index]}"

    first_cw: int | None = None
    first_ccw: int | None = None
    for index, face in enumerate(faces):
        area = _twice_area(points, face)
        if area == 0:
            raise FormatError(path, lines[index], f"{describe(index)} has zero area")
        if area < 0:
            first_cw = index if first_cw is None else first_cw
        else:
            first_ccw = index if first_ccw is None else first_ccw
        if first_cw is not None and first_ccw is not None:
            raise FormatError(
                path,
                lines[max(first_cw, first_ccw)],
                f"faces have mixed orientations: {describe(first_cw)} is clockwise but "
                f"{describe(first_ccw)} is counter-clockwise",
            )
    if first_cw is None:
        return faces
    notes.append(all_clockwise_note(len(faces), "face"))
    return [(face[0], *reversed(face[1:])) for face in faces]


# -----------------------------------------------------------------------------------------
# writing
# -----------------------------------------------------------------------------------------
def write_off(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A Mesh2 (triangles in canonical order) or a PolygonMesh as an OFF file, z = 0; a
    mesh's markers, attributes and segments are dropped (and reported)."""
    number = NumberText(numbers)
    if isinstance(value, Mesh2):
        points = [value.vertices[index] for index in range(value.vertex_count)]
        faces: list[tuple[int, ...]] = list(value.triangles())
    elif isinstance(value, PolygonMesh):
        points = list(value.vertices)
        faces = list(value.polygons)
    else:
        raise UnsupportedValueError(
            f"the off format writes a Mesh2 or a PolygonMesh, not a {type(value).__name__}"
        )
    out = ["OFF", f"{len(points)} {len(faces)} 0"]
    out.extend(f"{number(point.x)} {number(point.y)} 0" for point in points)
    out.extend(f"{len(face)} {' '.join(map(str, face))}" for face in faces)
    return write_files(
        [(path, "\n".join(out) + "\n")],
        overwrite=overwrite,
        numbers=number,
        dropped=dropped_parts(value, ()),
    )
