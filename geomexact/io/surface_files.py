"""Closed triangulated surfaces from files: Wavefront OBJ, STL (ASCII and binary), PLY
(ASCII and binary) and 3D OFF, read exactly into a
:class:`~geomexact.mesh3d.surface.value.TriangleSurface`.  Spec:
``specs/formats/surfaces.md``.

Every decimal in a text file is read as the rational it writes (``0.1`` is 1/10); every
float of a binary file is its exact binary value.  Polygons (OBJ, PLY, OFF) are
fan-triangulated from their first vertex: ``(v0, v1, v2), (v0, v2, v3), …``.  STL has no
shared vertices: identical points are welded into one vertex, exactly (by value), in
order of first appearance.  Every problem of a file is a :class:`FormatError` naming the
file, the 1-based line (None in a binary part, where the message names the record) and
the problem.  Files are streamed: text line by line, triangles kept in an int64 buffer.
The checks of the surface itself (closed, manifold, …) are
:mod:`geomexact.mesh3d.surface.checks`'; a reader only reads.
"""

from __future__ import annotations

import os
import re
from array import array
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import gmpy2
import numpy as np

from geomexact.errors import FormatError
from geomexact.io.files import open_regular, read_lines
from geomexact.io.registry import (
    Lines,
    clipped,
    counted,
    expect_exact_fields,
    expect_field_range,
    parse_count,
    parse_int,
    parse_number,
    quoted,
    quoted_tokens,
    token_lines,
)
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point3, nearest_double
from geomexact.mesh3d.surface.value import TriangleSurface

__all__ = ["SURFACE_FORMATS", "read_surface", "surface_format"]

SURFACE_FORMATS = {".obj": "obj", ".stl": "stl", ".ply": "ply", ".off": "off"}
"""The extension (lower case) -> surface format name that :func:`read_surface` reads."""


def surface_format(path: str | Path) -> str:
    """The surface format that ``path``'s extension names; FormatError for another."""
    suffix = Path(path).suffix.lower()
    name = SURFACE_FORMATS.get(suffix)
    if name is None:
        shown = f"extension {suffix!r}" if suffix else "no extension"
        raise FormatError(str(path), None, f"{shown} names no surface format (known: "
                          f"{', '.join(SURFACE_FORMATS)}); pass format= to name one")
    return name


def read_surface(path: str | Path, *, format: str | None = None) -> TriangleSurface:
    """The triangulated surface in ``path`` (format from the extension unless ``format``
    is ``"obj"``, ``"stl"``, ``"ply"`` or ``"off"``), read exactly; its name is the
    file's name.  :class:`FormatError` (file, line, problem) for anything malformed and
    for a file without triangles.  Time and memory linear in the file."""
    name = format if format is not None else surface_format(path)
    reader = _READERS.get(name)
    if reader is None:
        raise FormatError(str(path), None, f"unknown surface format {name!r} (known: "
                          f"{', '.join(_READERS)})")
    return reader(Path(path))


# -----------------------------------------------------------------------------------------
# shared pieces
# -----------------------------------------------------------------------------------------
# what gmpy2's own parser reads exactly as parse_rational does (it refuses "+3", "-.5")
_PLAIN_NUMBER = re.compile(r"-?[0-9]+(?:\.[0-9]*)?(?:[eE][-+]?[0-9]{1,6})?")
_PLAIN_LENGTH = 4000


def _exact(path: str, line: int, token: str, what: str) -> Rational:
    """``token`` as an exact rational (gmpy2's parser for a plain decimal, the common
    case; :func:`parse_number` with its error message otherwise)."""
    if len(token) < _PLAIN_LENGTH and _PLAIN_NUMBER.fullmatch(token):
        return gmpy2.mpq(token)
    return parse_number(path, line, token, what)


def _point(x: Rational, y: Rational, z: Rational) -> Point3:
    return Point3(x, y, z, nearest_double(x), nearest_double(y), nearest_double(z))


def _text_point(path: str, line: int, tokens: Sequence[str], what: str) -> Point3:
    return _point(*(_exact(path, line, token, f"{what}, {axis}")
                    for token, axis in zip(tokens, "xyz", strict=False)))


def _fan(corners: array[int], ids: Sequence[int]) -> None:
    """Append the fan triangulation of the polygon ``ids`` to ``corners``."""
    first = ids[0]
    for index in range(1, len(ids) - 1):
        corners.extend((first, ids[index], ids[index + 1]))


def _surface(path: Path, points: Sequence[Point3], corners: array[int],
             line: int | None) -> TriangleSurface:
    """The surface read, or FormatError (at ``line``) when the file has no triangle."""
    if not corners:
        raise FormatError(str(path), line, "the file has no face: a surface needs at least "
                          "one triangle")
    triangles = np.array(corners, dtype=np.int64).reshape(-1, 3)
    triangles.setflags(write=False)
    return TriangleSurface(tuple(points), triangles, path.name)


# -----------------------------------------------------------------------------------------
# Wavefront OBJ
# -----------------------------------------------------------------------------------------
_OBJ_IGNORED = frozenset({"vt", "vn", "vp", "g", "o", "s", "usemtl", "mtllib", "l", "p"})


def _read_obj(path: Path) -> TriangleSurface:
    """OBJ: ``v x y z [w]`` (or ``v x y z r g b``, colours ignored) and ``f`` of 1-based or
    negative (relative) vertex references ``v``, ``v/vt``, ``v//vn``, ``v/vt/vn``, each
    defined before it is used; texture and normal data, groups, objects, smoothing
    groups, materials, lines and points are ignored; other statements are refused."""
    name = str(path)
    points: list[Point3] = []
    corners: array[int] = array("q")
    number = 0
    for number, line in read_lines(path):
        if "#" in line:
            line = line[: line.index("#")]
        tokens = line.split()
        if not tokens:
            continue
        keyword = tokens[0]
        if keyword == "v":
            points.append(_obj_vertex(name, number, tokens, len(points) + 1))
        elif keyword == "f":
            _fan(corners, _obj_face(name, number, tokens, len(points)))
        elif keyword not in _OBJ_IGNORED:
            raise FormatError(name, number, f"unknown OBJ statement {quoted(keyword, 40)} "
                              "(read: v, f; ignored: " + ", ".join(sorted(_OBJ_IGNORED))
                              + ")")
    return _surface(path, points, corners, number or None)


def _obj_vertex(path: str, line: int, tokens: list[str], label: int) -> Point3:
    what = f"vertex {label}"
    if len(tokens) not in (4, 5, 7, 8):
        raise FormatError(path, line, f"{what}: expected 'v x y z', 'v x y z w' or 'v x y "
                          f"z r g b', found {quoted_tokens(tokens)}")
    for index, token in enumerate(tokens[4:], start=4):  # w or colours: still numbers
        _exact(path, line, token, f"{what}, field {index}")
    point = _text_point(path, line, tokens[1:4], what)
    if len(tokens) == 5:
        weight = _exact(path, line, tokens[4], f"{what}, w")
        if weight == 0:
            raise FormatError(path, line, f"{what}: the weight w is 0")
        if weight != 1:
            point = _point(point.x / weight, point.y / weight, point.z / weight)
    return point


def _obj_face(path: str, line: int, tokens: list[str], defined: int) -> list[int]:
    """The 0-based vertex ids of an ``f`` line, given ``defined`` vertices so far."""
    if len(tokens) < 4:
        raise FormatError(path, line, f"a face needs at least 3 vertices, found "
                          f"{len(tokens) - 1}: {quoted_tokens(tokens)}")
    ids = []
    for reference in tokens[1:]:
        text = reference.split("/", 1)[0]
        index = parse_int(path, line, text, f"face vertex {quoted(reference, 40)}")
        resolved = index - 1 if index > 0 else defined + index
        if index == 0 or not 0 <= resolved < defined:
            so_far = "no vertex is" if not defined else (
                f"{counted(defined, 'vertex', 'vertices')}: 1..{defined} or -{defined}..-1")
            raise FormatError(path, line, f"face vertex {clipped(text, 40)} is not defined "
                              f"before this line ({so_far} defined)")
        ids.append(resolved)
    return ids


# -----------------------------------------------------------------------------------------
# STL
# -----------------------------------------------------------------------------------------
_STL_HEADER = 84
_STL_RECORD = np.dtype([("normal", "<f4", (3,)), ("corners", "<f4", (9,)),
                        ("attribute", "<u2")])


def _read_stl(path: Path) -> TriangleSurface:
    """STL: binary when the size is exactly ``84 + 50 n`` bytes for the ``n`` of its
    header, else ASCII when it starts with ``solid``, else a truncated binary file."""
    name = str(path)
    with open_regular(path) as handle:
        size = os.fstat(handle.fileno()).st_size
        start = handle.read(_STL_HEADER)
        announced = int.from_bytes(start[80:84], "little") if len(start) == 84 else None
        if announced is not None and size == _STL_HEADER + _STL_RECORD.itemsize * announced:
            return _binary_stl(path, handle.read(), announced)
    if start.lstrip().startswith(b"solid"):
        return _ascii_stl(path)
    if announced is None:
        raise FormatError(name, None, f"a binary STL needs an 84-byte header, the file has "
                          f"{size} bytes (and an ASCII STL starts with 'solid')")
    expected = _STL_HEADER + _STL_RECORD.itemsize * announced
    raise FormatError(name, None, f"binary STL: the header announces {announced:,} "
                      f"triangles ({expected:,} bytes) but the file has {size:,} bytes "
                      "(truncated or not an STL file; an ASCII STL starts with 'solid')")


def _binary_stl(path: Path, data: bytes, count: int) -> TriangleSurface:
    records = np.frombuffer(data, dtype=_STL_RECORD, count=count)
    coordinates = records["corners"].reshape(-1, 3).astype(np.float64)
    finite = np.isfinite(coordinates).all(axis=1)
    if not finite.all():
        bad = int(np.argmin(finite))
        triangle = bad // 3
        raise FormatError(str(path), None, f"triangle {triangle} (bytes "
                          f"{_STL_HEADER + _STL_RECORD.itemsize * triangle:,}..): corner "
                          f"{bad % 3} is not a finite number "
                          f"{tuple(coordinates[bad].tolist())}")
    coordinates += 0.0  # -0.0 becomes 0.0: one value, one vertex
    return _welded(path, coordinates)


def _welded(path: Path, coordinates: np.ndarray) -> TriangleSurface:
    """The surface of triangles given by their corners' doubles (3 rows each), identical
    points welded into one vertex, ids in order of first appearance."""
    if not len(coordinates):
        raise FormatError(str(path), None, "the file has no face: a surface needs at least "
                          "one triangle")
    keys = np.ascontiguousarray(coordinates).view(np.dtype((np.void, 24))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    triangles = rank[inverse.ravel()].astype(np.int64).reshape(-1, 3)
    triangles.setflags(write=False)
    points = tuple(_point(gmpy2.mpq(x), gmpy2.mpq(y), gmpy2.mpq(z))
                   for x, y, z in coordinates[first[order]].tolist())
    return TriangleSurface(points, triangles, path.name)


def _ascii_stl(path: Path) -> TriangleSurface:
    name = str(path)
    lines = Lines(name, token_lines(read_lines(path)))
    ids: dict[tuple[Rational, Rational, Rational], int] = {}
    points: list[Point3] = []
    corners: array[int] = array("q")
    number, tokens = lines.next("'solid'")
    if tokens[0] != "solid":
        raise FormatError(name, number, f"an ASCII STL starts with 'solid', found "
                          f"{quoted_tokens(tokens)}")
    facet = 0
    while not lines.at_end():
        number, tokens = lines.next("'endsolid'")
        keyword = tokens[0]
        if keyword == "endsolid":
            if lines.at_end():
                break
            number, tokens = lines.next("'solid'")
            if tokens[0] != "solid":
                raise FormatError(name, number, f"expected 'solid' or the end of the file "
                                  f"after 'endsolid', found {quoted_tokens(tokens)}")
            continue
        if keyword != "facet":
            raise FormatError(name, number, f"expected 'facet normal nx ny nz' or "
                              f"'endsolid', found {quoted_tokens(tokens)}")
        facet += 1
        _stl_keywords(lines, f"facet {facet}", ("outer", "loop"))
        for corner in range(3):
            number, tokens = lines.next(f"vertex {corner + 1} of facet {facet}")
            if tokens[0] != "vertex" or len(tokens) != 4:
                raise FormatError(name, number, f"facet {facet}: expected 'vertex x y z', "
                                  f"found {quoted_tokens(tokens)}")
            point = _text_point(name, number, tokens[1:], f"facet {facet}, vertex "
                                f"{corner + 1}")
            key = (point.x, point.y, point.z)
            vertex = ids.get(key)
            if vertex is None:
                vertex = ids[key] = len(points)
                points.append(point)
            corners.append(vertex)
        _stl_keywords(lines, f"facet {facet}", ("endloop",))
        _stl_keywords(lines, f"facet {facet}", ("endfacet",))
    else:
        raise FormatError(name, lines.last_line, "the file ends before 'endsolid'")
    return _surface(path, points, corners, lines.last_line)


def _stl_keywords(lines: Lines, what: str, expected: tuple[str, ...]) -> None:
    text = " ".join(expected)
    number, tokens = lines.next(f"'{text}' of {what}")
    if tuple(tokens) != expected:
        hint = " (a facet has 3 vertices)" if tokens[0] == "vertex" else ""
        raise FormatError(lines.path, number, f"{what}: expected '{text}', found "
                          f"{quoted_tokens(tokens)}{hint}")


# -----------------------------------------------------------------------------------------
# 3D OFF
# -----------------------------------------------------------------------------------------
_OFF_KEYWORDS = {"OFF": 0, "COFF": 4, "NOFF": 3, "CNOFF": 7}
"""OFF header keywords of 3D files -> how many extra numbers a vertex line may carry
(colour, normal; ignored)."""


def _read_off(path: Path) -> TriangleSurface:
    """3D OFF: ``OFF`` (or ``COFF``, ``NOFF``, ``CNOFF``), the counts ``vertices faces
    [edges]`` (on the header line or the next), the vertices ``x y z [extras]``, the
    faces ``k i1 … ik [colour]`` of 0-based ids."""
    name = str(path)
    lines = Lines(name, token_lines(read_lines(path)))
    number, tokens = lines.next("the 'OFF' header")
    extras = _OFF_KEYWORDS.get(tokens[0])
    if extras is None:
        raise FormatError(name, number, f"a 3D OFF file starts with OFF, COFF, NOFF or "
                          f"CNOFF, found {quoted_tokens(tokens)}")
    counts = tokens[1:]
    if not counts:
        number, counts = lines.next("the counts 'vertices faces edges'")
    expect_field_range(name, number, counts, 2, 3, "the counts 'vertices faces [edges]'")
    vertex_count = parse_count(name, number, counts[0], "the vertex count")
    face_count = parse_count(name, number, counts[1], "the face count")
    points: list[Point3] = []
    for index in range(vertex_count):
        number, tokens = lines.next_item(index, vertex_count, f"vertex {index}", "vertices")
        expect_field_range(name, number, tokens, 3, 3 + extras,
                           f"vertex {index} as 'x y z'" + (f" and up to {extras} more "
                                                           "numbers" if extras else ""))
        points.append(_text_point(name, number, tokens[:3], f"vertex {index}"))
    corners: array[int] = array("q")
    for index in range(face_count):
        number, tokens = lines.next_item(index, face_count, f"face {index}", "faces")
        size = parse_count(name, number, tokens[0], f"face {index}: the vertex count")
        if size < 3:
            raise FormatError(name, number, f"face {index} has {size} vertices; a face "
                              "needs at least 3")
        expect_field_range(name, number, tokens, 1 + size, 5 + size,
                           f"face {index} as '{size}' and {size} vertex ids (and at most "
                           "4 colour numbers)")
        ids = []
        for token in tokens[1 : 1 + size]:
            vertex = parse_int(name, number, token, f"face {index}: vertex id")
            if not 0 <= vertex < vertex_count:
                raise FormatError(name, number, f"face {index}: vertex {vertex} is out of "
                                  f"range (expected 0..{vertex_count - 1})")
            ids.append(vertex)
        _fan(corners, ids)
    lines.expect_end(f"the {counted(face_count, 'face')}")
    return _surface(path, points, corners, lines.last_line)


# -----------------------------------------------------------------------------------------
# PLY
# -----------------------------------------------------------------------------------------
_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
    "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4",
    "uint32": "u4", "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}
_PLY_FORMATS = {"ascii": "", "binary_little_endian": "<", "binary_big_endian": ">"}
_PLY_HEADER_LIMIT = 1 << 16


class _PlyProperty:
    __slots__ = ("count_type", "kind", "name")

    def __init__(self, name: str, kind: str, count_type: str | None) -> None:
        self.name = name
        self.kind = kind  # numpy kind code without byte order, e.g. "f4"
        self.count_type = count_type  # the list's count type, None for a scalar


class _PlyElement:
    __slots__ = ("count", "line", "name", "properties")

    def __init__(self, name: str, count: int, line: int) -> None:
        self.name = name
        self.count = count
        self.line = line
        self.properties: list[_PlyProperty] = []


def _read_ply(path: Path) -> TriangleSurface:
    """PLY 1.0, ASCII or binary (either byte order): the ``vertex`` element's ``x y z``
    and the ``face`` element's ``vertex_indices`` (or ``vertex_index``) list; other
    properties and elements are read past and ignored."""
    name = str(path)
    with open_regular(path) as handle:
        header, encoding, elements = _ply_header(name, handle)
        if encoding:
            return _binary_ply(path, handle.read(), encoding, elements)
    return _ascii_ply(path, header, elements)


def _ply_header(path: str, handle: object) -> tuple[int, str, list[_PlyElement]]:
    """(header lines, byte order ('' for ASCII), elements) of a PLY header."""
    read_line = handle.readline  # type: ignore[attr-defined]
    elements: list[_PlyElement] = []
    encoding: str | None = None
    number = 0
    while True:
        raw: bytes = read_line(_PLY_HEADER_LIMIT)
        number += 1
        if not raw:
            raise FormatError(path, number - 1 or None, "the file ends before 'end_header'")
        text = raw.decode("ascii", "replace")
        tokens = text.split()
        if number == 1:
            if tokens != ["ply"]:
                raise FormatError(path, 1, f"a PLY file starts with 'ply', found "
                                  f"{quoted(text.strip())}")
            continue
        if not tokens or tokens[0] in ("comment", "obj_info"):
            continue
        keyword = tokens[0]
        if keyword == "end_header":
            break
        if keyword == "format":
            if len(tokens) != 3 or tokens[1] not in _PLY_FORMATS or tokens[2] != "1.0":
                raise FormatError(path, number, "expected 'format ascii|binary_little_endian"
                                  f"|binary_big_endian 1.0', found {quoted_tokens(tokens)}")
            encoding = _PLY_FORMATS[tokens[1]]
        elif keyword == "element":
            expect_exact_fields(path, number, tokens, 3, "'element name count'")
            count = parse_count(path, number, tokens[2], f"the count of element "
                                f"{quoted(tokens[1], 40)}")
            elements.append(_PlyElement(tokens[1], count, number))
        elif keyword == "property":
            if not elements:
                raise FormatError(path, number, "a property before any element")
            elements[-1].properties.append(_ply_property(path, number, tokens))
        else:
            raise FormatError(path, number, f"unknown PLY header line {quoted_tokens(tokens)}")
    if encoding is None:
        raise FormatError(path, number, "the header has no 'format' line")
    return number, encoding, elements


def _ply_property(path: str, line: int, tokens: list[str]) -> _PlyProperty:
    def kind(token: str) -> str:
        found = _PLY_TYPES.get(token)
        if found is None:
            raise FormatError(path, line, f"unknown property type {quoted(token, 40)}")
        return found

    if len(tokens) >= 2 and tokens[1] == "list":
        expect_exact_fields(path, line, tokens, 5, "'property list count_type item_type "
                            "name'")
        count_type = kind(tokens[2])
        if count_type[0] == "f":
            raise FormatError(path, line, "a list's count type must be an integer type")
        return _PlyProperty(tokens[4], kind(tokens[3]), count_type)
    expect_exact_fields(path, line, tokens, 3, "'property type name'")
    return _PlyProperty(tokens[2], kind(tokens[1]), None)


def _ply_roles(path: str, elements: list[_PlyElement]) -> tuple[tuple[int, ...], int]:
    """(the indices of x, y, z among the vertex element's properties, the index of the
    face element's vertex list); FormatError naming what is missing."""
    by_name = {element.name: element for element in elements}
    vertex, face = by_name.get("vertex"), by_name.get("face")
    if vertex is None or face is None:
        missing = "vertex" if vertex is None else "face"
        raise FormatError(path, None, f"the header has no '{missing}' element")
    names = [prop.name for prop in vertex.properties]
    axes = []
    for axis in "xyz":
        if axis not in names or vertex.properties[names.index(axis)].count_type:
            raise FormatError(path, vertex.line, f"the vertex element has no scalar "
                              f"property {axis!r}")
        axes.append(names.index(axis))
    lists = [index for index, prop in enumerate(face.properties) if prop.count_type
             and prop.name in ("vertex_indices", "vertex_index")]
    if not lists:
        raise FormatError(path, face.line, "the face element has no list property "
                          "'vertex_indices'")
    if face.properties[lists[0]].kind[0] == "f":
        raise FormatError(path, face.line, "vertex_indices must be of an integer type")
    return tuple(axes), lists[0]


def _face_ids(path: str, line: int | None, where: str, ids: Sequence[int],
              vertex_count: int) -> Sequence[int]:
    if len(ids) < 3:
        raise FormatError(path, line, f"{where} has {len(ids)} vertices; a face needs at "
                          "least 3")
    for vertex in ids:
        if not 0 <= vertex < vertex_count:
            raise FormatError(path, line, f"{where}: vertex {vertex} is out of range "
                              f"(expected 0..{vertex_count - 1})")
    return ids


def _ascii_ply(path: Path, header_lines: int, elements: list[_PlyElement]) -> TriangleSurface:
    name = str(path)
    axes, face_list = _ply_roles(name, elements)
    rows = (row for row in read_lines(path) if row[0] > header_lines)
    lines = Lines(name, token_lines(rows))
    points: list[Point3] = []
    corners: array[int] = array("q")
    vertex_count = next(e.count for e in elements if e.name == "vertex")
    for element in elements:
        for index in range(element.count):
            number, tokens = lines.next_item(index, element.count, f"{element.name} {index}",
                                             f"'{element.name}' lines")
            values = _ascii_record(name, number, tokens, element, index)
            if element.name == "vertex":
                coordinates = [values[axis] for axis in axes]
                points.append(_text_point(name, number, [c for c in coordinates
                                                         if isinstance(c, str)],
                                          f"vertex {index}"))
            elif element.name == "face":
                ids = [parse_int(name, number, token, f"face {index}: vertex id")
                       for token in values[face_list]]
                _fan(corners, _face_ids(name, number, f"face {index}", ids, vertex_count))
    lines.expect_end("the last element")
    return _surface(path, points, corners, lines.last_line)


def _ascii_record(path: str, line: int, tokens: list[str], element: _PlyElement,
                  index: int) -> list[str | list[str]]:
    """The tokens of one ASCII PLY record, by property (a list property: its items)."""
    values: list[str | list[str]] = []
    at = 0
    for prop in element.properties:
        if at >= len(tokens):
            raise FormatError(path, line, f"{element.name} {index}: the line ends before "
                              f"property {quoted(prop.name, 40)}: {quoted_tokens(tokens)}")
        if prop.count_type is None:
            values.append(tokens[at])
            at += 1
            continue
        size = parse_count(path, line, tokens[at], f"{element.name} {index}: the length "
                           f"of {quoted(prop.name, 40)}")
        if at + 1 + size > len(tokens):
            raise FormatError(path, line, f"{element.name} {index}: {quoted(prop.name, 40)} "
                              f"announces {size} items, the line has {len(tokens) - at - 1}")
        values.append(tokens[at + 1 : at + 1 + size])
        at += 1 + size
    if at != len(tokens):
        raise FormatError(path, line, f"{element.name} {index}: {len(tokens) - at} fields "
                          f"more than its properties: {quoted_tokens(tokens)}")
    return values


def _binary_ply(path: Path, data: bytes, order: str,
                elements: list[_PlyElement]) -> TriangleSurface:
    name = str(path)
    axes, face_list = _ply_roles(name, elements)
    offset = 0
    points: tuple[Point3, ...] = ()
    triangles = np.zeros((0, 3), dtype=np.int64)
    vertex_count = next(e.count for e in elements if e.name == "vertex")
    for element in elements:
        if all(prop.count_type is None for prop in element.properties):
            layout = np.dtype([(f"p{i}", order + prop.kind)
                               for i, prop in enumerate(element.properties)])
            end = offset + layout.itemsize * element.count
            if end > len(data):
                raise _ply_truncated(name, element, (len(data) - offset) // layout.itemsize)
            table = np.frombuffer(data, dtype=layout, count=element.count, offset=offset)
            offset = end
            if element.name == "vertex":
                points = _binary_points(name, [table[f"p{a}"] for a in axes])
            elif element.name == "face":
                raise FormatError(name, element.line, "the face element has no list")
            continue
        offset, lists = _binary_lists(name, data, offset, order, element)
        if element.name == "face":
            triangles = _binary_triangles(name, lists[face_list], vertex_count)
    if offset != len(data):
        raise FormatError(name, None, f"{len(data) - offset:,} bytes after the last element")
    if not len(triangles):
        raise FormatError(name, None, "the file has no face: a surface needs at least one "
                          "triangle")
    triangles.setflags(write=False)
    return TriangleSurface(points, triangles, path.name)


def _ply_truncated(path: str, element: _PlyElement, found: int) -> FormatError:
    return FormatError(path, None, f"the file ends inside the '{element.name}' element: "
                       f"expected {element.count:,} records, found {found:,} (truncated)")


def _binary_points(path: str, columns: list[np.ndarray]) -> tuple[Point3, ...]:
    for axis, column in zip("xyz", columns, strict=True):
        if column.dtype.kind == "f" and not np.isfinite(column).all():
            bad = int(np.argmin(np.isfinite(column)))
            raise FormatError(path, None, f"vertex {bad}: {axis} is not a finite number "
                              f"({column[bad]})")
    exact = [[gmpy2.mpq(value) for value in column.tolist()] for column in columns]
    return tuple(_point(x, y, z) for x, y, z in zip(*exact, strict=True))


def _binary_lists(path: str, data: bytes, offset: int, order: str,
                  element: _PlyElement) -> tuple[int, dict[int, list[list[int]] | np.ndarray]]:
    """Read past a binary element with list properties; return the end offset and the
    face list (as an (n, k) array when every face has k items, else lists)."""
    uniform = _uniform_lists(data, offset, order, element)
    if uniform is not None:
        return uniform
    lists: dict[int, list[list[int]] | np.ndarray] = {}
    collected: list[list[int]] = []
    for index in range(element.count):
        for position, prop in enumerate(element.properties):
            if prop.count_type is None:
                offset += np.dtype(prop.kind).itemsize
                if offset > len(data):
                    raise _ply_truncated(path, element, index)
                continue
            count_type = np.dtype(order + prop.count_type)
            if offset + count_type.itemsize > len(data):
                raise _ply_truncated(path, element, index)
            size = int(np.frombuffer(data, dtype=count_type, count=1, offset=offset)[0])
            offset += count_type.itemsize
            item = np.dtype(order + prop.kind)
            if size < 0 or offset + item.itemsize * size > len(data):
                raise _ply_truncated(path, element, index)
            if prop.name in ("vertex_indices", "vertex_index") and element.name == "face":
                collected.append(np.frombuffer(data, dtype=item, count=size,
                                               offset=offset).tolist())
                lists[position] = collected
            offset += item.itemsize * size
    return offset, lists


def _uniform_lists(data: bytes, offset: int, order: str,
                   element: _PlyElement) -> tuple[int, dict[int, list[list[int]] | np.ndarray]]\
        | None:
    """The fast path of :func:`_binary_lists`: every list of the element has the length
    of its first record (triangles, say), so the records have one layout; None when they
    do not."""
    fields: list[tuple[Any, ...]] = []
    at = offset
    for position, prop in enumerate(element.properties):
        if prop.count_type is None:
            fields.append((f"p{position}", order + prop.kind))
            at += np.dtype(prop.kind).itemsize
            continue
        count_type = np.dtype(order + prop.count_type)
        if at + count_type.itemsize > len(data):
            return None
        size = int(np.frombuffer(data, dtype=count_type, count=1, offset=at)[0])
        if size <= 0:
            return None
        fields.append((f"n{position}", count_type.str))
        fields.append((f"p{position}", order + prop.kind, (size,)))
        at += count_type.itemsize + np.dtype(prop.kind).itemsize * size
    layout = np.dtype(fields)
    end = offset + layout.itemsize * element.count
    if element.count == 0 or end > len(data):
        return None
    table = np.frombuffer(data, dtype=layout, count=element.count, offset=offset)
    lists: dict[int, list[list[int]] | np.ndarray] = {}
    for position, prop in enumerate(element.properties):
        if prop.count_type is None:
            continue
        shape = layout[f"p{position}"].shape
        if not (table[f"n{position}"] == shape[0]).all():
            return None
        lists[position] = table[f"p{position}"].reshape(element.count, shape[0])
    return end, lists


def _binary_triangles(path: str, faces: list[list[int]] | np.ndarray,
                      vertex_count: int) -> np.ndarray:
    if isinstance(faces, np.ndarray):
        ids = faces.astype(np.int64)
        if ids.shape[1] < 3:
            raise FormatError(path, None, f"face 0 has {ids.shape[1]} vertices; a face "
                              "needs at least 3")
        bad = (ids < 0) | (ids >= vertex_count)
        if bad.any():
            first = int(np.argmax(bad.any(axis=1)))
            _face_ids(path, None, f"face {first}", ids[first].tolist(), vertex_count)
        fan = [ids[:, [0, k, k + 1]] for k in range(1, ids.shape[1] - 1)]
        return np.stack(fan, axis=1).reshape(-1, 3)
    corners: array[int] = array("q")
    for index, face in enumerate(faces):
        _fan(corners, _face_ids(path, None, f"face {index}", face, vertex_count))
    return np.array(corners, dtype=np.int64).reshape(-1, 3)


_READERS = {"obj": _read_obj, "stl": _read_stl, "ply": _read_ply, "off": _read_off}
