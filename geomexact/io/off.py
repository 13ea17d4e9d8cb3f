"""Object File Format (OFF), including the old Geomview ``{ appearance {…} LIST … }``
wrapper, for planar meshes (every z = 0).  Spec: ``specs/formats/off.md``.

Reading gives a :class:`Mesh2` when every face is a triangle (one orientation for the whole
file: all clockwise is reversed and noted, mixed is an error), else a
:class:`PolygonMesh` (the same orientation rule, by exact signed area).  Writing takes
either; markers, attributes and segments of a mesh have no place in OFF and are dropped.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterator
from pathlib import Path

from geomexact.errors import FormatError, RationalParseError, UnsupportedValueError
from geomexact.io.files import read_lines
from geomexact.io.registry import (
    BulkOrientation,
    Lines,
    NumberedLine,
    NumberStyle,
    NumberText,
    Orienter,
    TriangleTable,
    Value,
    WriteReport,
    all_clockwise_note,
    build_mesh,
    clipped,
    counted,
    dropped_parts,
    expect_field_range,
    expect_fields,
    note_duplicate_points,
    parse_count,
    parse_int,
    parse_number,
    quoted,
    quoted_tokens,
    section_too_short,
    token_lines,
    write_files,
)
from geomexact.kernel.numbers import Rational, parse_rational
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh, polygon_twice_area
from geomexact.mesh2d.snapshot import Mesh2

BULK_MIN_BYTES = 1 << 16
"""Files from this size are read by the bulk reader (NumPy); smaller ones line by line,
which does not pay NumPy's import (``geomexact info`` on a small file)."""

_BRACES = "{}"


# -----------------------------------------------------------------------------------------
# the Geomview wrapper
# -----------------------------------------------------------------------------------------
class _Unwrapper:
    """Blanks the opening ``{ [appearance {…}] [LIST] [{]`` of the wrapper around an OFF
    object in comment-free rows, keeping every other character (and so every line number).
    Rows are pulled from the file only as far as the opening goes."""

    def __init__(self, path: str, source: Iterator[tuple[int, str]]) -> None:
        self.path = path
        self.source = source
        self.rows: list[str] = []
        self.row = 0
        self.col = 0

    def _has_row(self) -> bool:
        """True when row ``self.row`` exists (pulling it from the file if needed)."""
        while self.row >= len(self.rows):
            pulled = next(self.source, None)
            if pulled is None:
                return False
            line = pulled[1]
            self.rows.append(line[: line.index("#")] if "#" in line else line)
        return True

    def skip_space(self) -> bool:
        """Move to the next non-blank character; False at the end of the text."""
        while self._has_row():
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
        """Blank a balanced ``{ … }`` starting at the cursor (each row blanked at once:
        blanking character by character was quadratic in a long row)."""
        start_line = self.row + 1
        depth = 0
        while self.skip_space():
            text = self.rows[self.row]
            end = self.col
            while end < len(text):
                char = text[end]
                end += 1
                if char == "{":
                    depth += 1
                elif char == "}":
                    depth -= 1
                    if depth == 0:
                        break
            self._blank(self.col, end)
            self.col = end
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
                line = self.row + 1
                self._blank(self.col, self.col + len(word))
                self.col += len(word)
                if not self.skip_space():
                    raise FormatError(
                        self.path, line, "'appearance' must be followed by '{ … }', but the "
                        "file ends"
                    )
                if self.rows[self.row][self.col] != "{":
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


def _closed(
    path: str, lines: Iterator[NumberedLine], opened: int, opening_line: int
) -> Iterator[NumberedLine]:
    """``lines`` without the ``opened`` braces that close the Geomview block: the last
    ``}`` characters of the text (only blanks and comments after them).  Earlier braces
    are data (the reader reports them); too few closing braces are an error naming the
    last other character."""
    trailing: list[tuple[int, int]] = []  # (line, braces) of the text's trailing braces
    last: tuple[int, str] | None = None  # the last data line and its last character
    for number, tokens in lines:
        text = " ".join(tokens)
        data = text.rstrip("} ")
        if not data:
            trailing.append((number, text.count("}")))
            continue
        for brace_line, braces in trailing:  # data follows them: they close nothing
            yield brace_line, ["}"] * braces
        trailing = []
        yield number, data.split()
        last = (number, data[-1])
        braces = text.count("}", len(data))
        if braces:
            trailing.append((number, braces))
    count = sum(braces for _, braces in trailing)
    if count < opened:
        line, char = last if last is not None else (opening_line, "")
        raise FormatError(
            path,
            line,
            f"expected '}}' closing the Geomview block opened on line {opening_line}, "
            f"found {char!r}" if char else "the Geomview block is never closed",
        )
    extra = count - opened  # the first braces beyond the closing ones are data
    for number, braces in trailing:
        if extra <= 0:
            break
        yield number, ["}"] * min(extra, braces)
        extra -= braces


def _off_lines(path: Path, notes: list[str]) -> Iterator[NumberedLine]:
    """The data lines of an OFF file, streamed, through any Geomview wrapper."""
    name = str(path)
    source = read_lines(path)
    unwrapper = _Unwrapper(name, source)
    opened = 0
    opening_line = 0
    if unwrapper.skip_space():
        opening_line = unwrapper.row + 1
        opened = unwrapper.unwrap()
        if opened:
            notes.append("read the OFF object inside a Geomview '{ … }' wrapper")
    head = ((number, row) for number, row in enumerate(unwrapper.rows, start=1))
    lines = token_lines(itertools.chain(head, source))
    if opened:
        return _closed(name, lines, opened, opening_line)
    return lines


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
        raise FormatError(path, number, f"unknown OFF keyword {quoted(token)}")
    return True


def _face_shaped(tokens: list[str]) -> bool:
    """True when a line has the shape of a face, ``k v1 … vk [colour]`` of integers with
    k >= 3 (which a vertex line ``x y 0`` does not have)."""
    if not all(token.isdigit() for token in tokens):
        return False
    size = int(tokens[0]) if len(tokens[0]) < 10 else 0
    return size >= 3 and len(tokens) >= size + 1


def _vertex_shaped(tokens: list[str]) -> bool:
    """True when a line reads as a planar vertex ``x y 0`` whose x is no integer (which a
    face line ``k v1 … vk`` cannot be)."""
    if len(tokens) < 3 or tokens[0].lstrip("+-").isdigit():
        return False
    try:
        return all(parse_rational(token) is not None for token in tokens[:2]) and (
            parse_rational(tokens[2]) == 0
        )
    except RationalParseError:
        return False


def read_off(path: Path) -> tuple[Value, list[str]]:
    """An OFF file as a Mesh2 (all faces triangles) or a PolygonMesh.  The file is
    streamed: a bad line stops the reading there."""
    bulk = _bulk_off(path) if _size(path) >= BULK_MIN_BYTES else None
    if bulk is not None:
        return bulk
    name = str(path)
    notes: list[str] = []
    lines = Lines(name, _off_lines(path, notes))
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
    counts_line = number
    points: list[Point2] = []
    point_lines: list[int | None] = []
    for index in range(vertex_count):
        number, tokens = lines.next_item(
            index, vertex_count, f"vertex {index}", "vertices"
        )
        try:
            expect_fields(name, number, tokens, 3, f"vertex {index} 'x y z'")
            x = parse_number(name, number, tokens[0], f"x of vertex {index}")
            y = parse_number(name, number, tokens[1], f"y of vertex {index}")
            z = parse_number(name, number, tokens[2], f"z of vertex {index}")
        except FormatError as error:
            if index and _face_shaped(tokens):
                raise section_too_short(
                    name, number, vertex_count, index, "vertices", counts_line,
                    f"{quoted_tokens(tokens)} is a face"
                ) from error
            raise
        if z != 0:
            if index and _face_shaped(tokens):
                raise section_too_short(
                    name, number, vertex_count, index, "vertices", counts_line,
                    f"{quoted_tokens(tokens)} is a face"
                )
            raise FormatError(
                name,
                number,
                f"vertex {index} has z = {clipped(tokens[2])}; only planar meshes (z = 0 "
                "for every vertex) are supported",
            )
        points.append(point2(x, y))
        point_lines.append(number)
    faces: list[tuple[int, ...]] = []
    face_lines: list[int | None] = []
    triangles: list[tuple[int, int, int]] = []
    table = TriangleTable(path=name, triangles=triangles, lines=face_lines)
    orienter = Orienter(table, points, individually=False, vertices=(name, point_lines))
    all_triangles = True
    for index in range(face_count):
        number, tokens = lines.next_item(index, face_count, f"face {index}", "faces")
        if _vertex_shaped(tokens):
            raise FormatError(
                name,
                number,
                f"face {index}: {quoted_tokens(tokens)} is a vertex, but the header (line "
                f"{counts_line}) announces {counted(vertex_count, 'vertex', 'vertices')}; "
                "is the vertex count right?",
            )
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
        if size != 3:
            all_triangles = False
        elif all_triangles:  # a degenerate or mixed triangle stops the reading here
            triangles.append((face[0], face[1], face[2]))
            orienter.add(index)
    lines.expect_end(f"the {counted(face_count, 'face')}")
    if all_triangles:
        mesh = build_mesh(
            points, point_lines, table, point_path=name, notes=notes, orienter=orienter
        )
        return mesh, notes
    polygons = _orient_polygons(name, points, faces, face_lines, notes)
    note_duplicate_points(points, point_lines, notes)
    return PolygonMesh(vertices=points, polygons=polygons), notes


def _size(path: Path) -> int:
    """The file's size in bytes (0 when it cannot be read: the line reader names why)."""
    try:
        return path.stat().st_size
    except OSError:
        return 0


def _bulk_off(path: Path) -> tuple[Mesh2, list[str]] | None:
    """:func:`read_off` of a plain triangle OFF file (:mod:`geomexact.io.bulk`): the
    keyword ``OFF``, regular lines ``x y 0`` and ``3 a b c`` of plain numbers, indices in
    range, one orientation; None for anything else (the line reader then reads it, or
    names the error, having read no further than its line)."""
    import numpy as np

    from geomexact.io.bulk import (
        IntArray,
        NotPlain,
        OrientedChunks,
        PlainLines,
        integer_column,
        number_column,
        triangle_tuples,
    )

    def triangle_corners(rows: IntArray) -> IntArray | None:
        corners = rows[:, 1:]  # of the rows "3 a b c" with every id a vertex's
        if (not bool(np.all(rows[:, 0] == 3)) or int(corners.min()) < 0
                or int(corners.max()) >= vertex_count):
            return None
        return corners

    points: list[Point2] = []
    point_lines: list[int | None] = []
    faces = OrientedChunks(points)
    vertex_count = 0
    cache: dict[str, tuple[Rational, float]] = {}
    try:
        with PlainLines(path) as lines:
            tokens, _ = lines.next_line()
            if tokens[0] != "OFF":
                return None
            counts = tokens[1:] or lines.next_line()[0]
            numbers = integer_column(counts) if len(counts) in (2, 3) else None
            if numbers is None or int(numbers.min()) < 0:
                return None
            vertex_count, face_count = int(numbers[0]), int(numbers[1])
            for tokens, rows_lines in lines.chunks(vertex_count, 3):
                xs = number_column(tokens[0::3], cache)
                ys = number_column(tokens[1::3], cache)
                zs = number_column(tokens[2::3], cache)
                if xs is None or ys is None or zs is None or any(zs[0]):
                    return None
                points.extend(map(Point2, xs[0], ys[0], xs[1], ys[1]))
                point_lines.extend(rows_lines)
            if not faces.read_last_section(lines, face_count, triangle_corners):
                return None
    except NotPlain:
        return None
    corners, rows = faces.tables()
    name = str(path)
    notes: list[str] = []
    table = TriangleTable(path=name, triangles=triangle_tuples(corners), lines=faces.lines)
    mesh = build_mesh(
        points, point_lines, table, point_path=name, notes=notes,
        orienter=BulkOrientation(rows, faces.reversed_count),
    )
    return mesh, notes


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
        area = polygon_twice_area(points, face)
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
    text: str | Iterator[str]
    if isinstance(value, Mesh2):
        text = _mesh_off_text(value, number)
    elif isinstance(value, PolygonMesh):
        points = list(value.vertices)
        faces = list(value.polygons)
        out = ["OFF", f"{len(points)} {len(faces)} 0"]
        out.extend(f"{number(point.x)} {number(point.y)} 0" for point in points)
        out.extend(f"{len(face)} {' '.join(map(str, face))}" for face in faces)
        text = "\n".join(out) + "\n"
    else:
        raise UnsupportedValueError(
            f"the off format writes a Mesh2 or a PolygonMesh, not a {type(value).__name__}"
        )
    return write_files(
        [(path, text)],
        overwrite=overwrite,
        numbers=number,
        dropped=dropped_parts(value, ()),
    )


def _mesh_off_text(mesh: Mesh2, number: NumberText) -> Iterator[str]:
    """The OFF text of a mesh in chunks: vertices in id order, triangles canonical and
    sorted, in bulk (:mod:`geomexact.io.bulk`)."""
    from geomexact.io.bulk import row_chunks, rows_text, triangle_array

    count = mesh.vertex_count
    coordinates = number.texts(
        coordinate for point in mesh.point_list() for coordinate in point[:2]
    )
    triangles = triangle_array(mesh)
    yield (f"OFF\n{count} {len(triangles)} 0\n"
           + rows_text("%s %s 0\n", count, coordinates))
    del coordinates
    yield from row_chunks("3 %d %d %d\n", triangles)
