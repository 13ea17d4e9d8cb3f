"""The bridge to meshio (VTK, VTU, XDMF, Gmsh, Medit, …) for 2D triangle meshes,
tetrahedral meshes and mixed-cell meshes.  Spec: ``specs/formats/meshio.md``.

A file with ``tetra`` cells is read as a :class:`Mesh3` (exact binary values of its 3D
points; its boundary's cells (triangles, quads, lines, vertices) ignored with a note,
higher-order solids refused; all negative tetrahedra reversed with a note, a mix or a
flat one refused, as in :mod:`geomexact.io.tetrahedron_orientation`); a :class:`Mesh3` is
written as its points (doubles, rounding counted) and ``tetra`` cells.  A file whose solids
include hexahedra, wedges, pyramids or polyhedra is read as a :class:`MixedMesh3`, checked
exactly (:mod:`geomexact.io.mixed_meshio`); a :class:`MixedMesh3` (or
:class:`MixedMeshData`, with integer cell arrays) is written to ``.vtu``, ``.vtk`` or
``.msh`` (polyhedra to VTK files only, by :mod:`geomexact.io.vtk_polyhedra`).

Reading takes the ``triangle`` cells (``line`` and ``vertex`` cells are ignored, with a
note; any other cell type is an error), requires z = 0, and converts each float to its
exact binary value.  Writing stores the nearest doubles (``exact`` cannot apply: these
formats hold floats) with z = 0, triangles in canonical order; markers, attributes and
segments are not written.  meshio is imported only when the bridge is used.
"""

from __future__ import annotations

import contextlib
import importlib
import operator
import sys
import tempfile
from collections.abc import Iterator, Sequence
from io import StringIO
from pathlib import Path
from typing import Any

import gmpy2

from geomexact.errors import (
    FormatError,
    MissingDependencyError,
    OverwriteError,
    PreconditionError,
    RationalParseError,
    UnsupportedValueError,
)
from geomexact.io.files import check_regular, write_bytes_atomic
from geomexact.io.mixed_meshio import (
    cell_arrays,
    cell_entries,
    is_mixed_file,
    meshio_blocks,
    mixed_of_meshio,
    parts_of,
)
from geomexact.io.registry import (
    MESHIO_EXTENSIONS,
    NumberStyle,
    TriangleTable,
    Value,
    WriteReport,
    build_mesh,
    clipped,
    dropped_parts,
)
from geomexact.io.tetrahedron_orientation import orient_tetrahedra
from geomexact.io.vtk_polyhedra import legacy_vtk_text, polyhedra_readable, vtu_text
from geomexact.io.vtu_grid import TETRAHEDRON, binary_vtu
from geomexact.kernel.numbers import Rational, to_float, to_rational
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.cells import CellKind
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3, tetrahedron_faces
from geomexact.mesh3d.transient import mesh3_from_positive_arrays, mesh3_from_tetrahedra

EXTENSIONS = MESHIO_EXTENSIONS
# extension -> meshio's formats (modules) to read it with, first one also to write it
# (meshio's own guess for .msh is the ANSYS format; geomexact means Gmsh)
_MESHIO_FORMATS: dict[str, tuple[str, ...]] = {
    ".vtk": ("vtk",),
    ".vtu": ("vtu",),
    ".xdmf": ("xdmf",),
    ".xmf": ("xdmf",),
    ".msh": ("gmsh", "ansys"),
    ".mesh": ("medit",),
    ".obj": ("obj",),
    ".ply": ("ply",),
}
IGNORED_CELLS = ("vertex", "line", "line3")
BOUNDARY_CELLS = ("vertex", "line", "line3", "triangle", "triangle6", "quad", "quad8",
                   "quad9", "polygon")
"""Cells of a tetrahedral file that are not solids (its boundary's faces, edges and
points): ignored with a note; any other cell but a tetrahedron is refused."""
# meshio's XDMF writer puts the arrays in an HDF5 file beside the .xdmf by default; XML
# keeps the output one self-contained file.
_WRITE_OPTIONS: dict[str, dict[str, Any]] = {
    ".xdmf": {"data_format": "XML"},
    ".xmf": {"data_format": "XML"},
    ".msh": {"binary": False},  # Gmsh text, doubles in full ("%.16e")
}


def meshio_module() -> Any:
    """The meshio module (heavy: imported only when the bridge is used; the "meshio"
    extra installs it)."""
    try:
        import meshio
    except ImportError as error:
        raise MissingDependencyError("meshio", "VTK, XDMF, Gmsh … files", "meshio") from error
    return meshio


def _missing(error: ImportError) -> str:
    return f"meshio needs the {error.name or 'missing'} package for this format ({error})"


@contextlib.contextmanager
def _meshio_messages(messages: list[str]) -> Iterator[None]:
    """Collect the warnings meshio's readers would print (into ``messages``, clipped).
    meshio prints them through rich, whose highlighting regex takes minutes on a long
    line: a mutated Gmsh header of 200,000 characters hung a read (fuzz suite).  The
    readers import ``warn`` and ``info`` by name, so each loaded meshio module's binding
    is replaced for the call, and restored."""
    common = sys.modules.get("meshio._common")

    def collect(text: object, highlight: bool = True) -> None:
        del highlight
        messages.append(clipped(str(text), 200))

    replaced: list[tuple[Any, str, Any]] = []
    if common is not None:
        originals = {getattr(common, name, None) for name in ("warn", "info")} - {None}
        for name, module in list(sys.modules.items()):
            if not name.startswith("meshio") or module is None:
                continue
            for attribute in ("warn", "info"):
                value = getattr(module, attribute, None)
                if value is not None and value in originals:
                    replaced.append((module, attribute, value))
                    setattr(module, attribute, collect)
    try:
        with contextlib.redirect_stdout(StringIO()), contextlib.redirect_stderr(StringIO()):
            yield
    finally:
        for module, attribute, value in replaced:
            setattr(module, attribute, value)


def _gmsh22_cell_data(cells: Any, cell_data_raw: Any) -> dict[str, Any]:
    """meshio's ``cell_data_from_raw`` for the Gmsh 2.2 reader, split by each block's
    length (meshio 5.3 takes ``len`` of its (type, cells) pairs: 2, so a file of two or
    more blocks with ElementData does not read)."""
    import numpy

    ends = numpy.cumsum([len(block[1]) for block in cells])[:-1]
    return {name: numpy.split(values, ends) for name, values in cell_data_raw.items()}


@contextlib.contextmanager
def meshio_fixed() -> Iterator[None]:
    """While active, meshio's readers read polyhedra beside other cells
    (:func:`~geomexact.io.vtk_polyhedra.polyhedra_readable`) and Gmsh 2.2 ElementData of
    several blocks (:func:`_gmsh22_cell_data`); restored afterwards."""
    import meshio.gmsh._gmsh22 as gmsh22

    original = gmsh22.cell_data_from_raw
    gmsh22.cell_data_from_raw = _gmsh22_cell_data
    try:
        with polyhedra_readable():
            yield
    finally:
        gmsh22.cell_data_from_raw = original


MEMORY_MARGIN = 2 << 30
"""The address space a meshio read may add beyond :data:`MEMORY_PER_BYTE` times the
file's size (bytes)."""

MEMORY_PER_BYTE = 64


@contextlib.contextmanager
def _memory_budget(size: int) -> Iterator[None]:
    """Cap the process's address space while meshio reads a file of ``size`` bytes (Linux;
    elsewhere nothing).  meshio sizes arrays by numbers in the file: a Gmsh node tag of
    2^31 made it fill a 16 GiB array (fuzz suite); under the cap the allocation fails
    with ``MemoryError``, reported as the file's problem.  The previous limit is
    restored afterwards."""
    try:
        import resource

        pages = int(Path("/proc/self/statm").read_text().split()[0])
        used = pages * resource.getpagesize()
        soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, OSError, ValueError, IndexError):
        yield
        return
    cap = used + MEMORY_MARGIN + MEMORY_PER_BYTE * size
    if hard != resource.RLIM_INFINITY:
        cap = min(cap, hard)
    if soft != resource.RLIM_INFINITY and soft <= cap:
        yield  # already as tight
        return
    resource.setrlimit(resource.RLIMIT_AS, (cap, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


_GMSH_DATA_BLOCKS = (b"$NodeData", b"$ElementData", b"$ElementNodeData")
_GMSH_TAG_KINDS = ("string", "real", "integer")


def _check_gmsh_tag_counts(path: Path) -> None:
    """Refuse a Gmsh file whose data block (``$NodeData``, ``$ElementData``,
    ``$ElementNodeData``) announces more string, real or integer tags than the file has
    lines: meshio reads that many lines one by one, so a count of 10^9 in a small file
    would keep it reading for hours.  Other faults are meshio's to report."""
    data = path.read_bytes()
    lines = data.count(b"\n") + 1
    for block in _GMSH_DATA_BLOCKS:
        start = data.find(block)
        while start >= 0:
            position = data.find(b"\n", start) + 1  # after the block's line (LF or CRLF)
            if position <= 0:
                break
            for kind in _GMSH_TAG_KINDS:
                end = data.find(b"\n", position)
                try:
                    count = int(data[position:end if end >= 0 else len(data)])
                except ValueError:
                    break
                if count > lines:
                    line = data.count(b"\n", 0, position) + 1
                    raise FormatError(str(path), line, f"the {block.decode()} block "
                                      f"announces {count} {kind} tags; the file has "
                                      f"{lines} lines")
                position = end + 1
                for _ in range(max(count, 0)):  # the tags themselves, a line each
                    position = data.find(b"\n", position) + 1
                    if position <= 0:
                        break
                if end < 0 or position <= 0:
                    break
            start = data.find(block, start + 1)


def _meshio_read(path: Path, notes: list[str]) -> Any:
    """meshio's reader of ``path``'s format, its warnings collected into ``notes``.
    ``meshio.read`` itself prints and calls ``sys.exit`` when a file does not parse, so
    the format's own reader is called; only an extension outside :data:`EXTENSIONS` goes
    through ``meshio.read``."""
    meshio = meshio_module()

    name = str(path)
    modules = _MESHIO_FORMATS.get(path.suffix.lower())
    if path.suffix.lower() == ".msh":
        _check_gmsh_tag_counts(path)
    messages: list[str] = []
    try:
        readers = [importlib.import_module(f"meshio.{module}") for module in modules or ()]
        with _meshio_messages(messages), _memory_budget(path.stat().st_size), \
                meshio_fixed():
            if not readers:
                return meshio.read(path)
            for reader in readers[:-1]:
                try:
                    return reader.read(name)
                except meshio.ReadError:
                    continue
            return readers[-1].read(name)
    except ImportError as error:
        raise FormatError(name, None, _missing(error)) from error
    except MemoryError as error:
        raise FormatError(
            name, None, "meshio cannot read it: it needs more memory than a file of this "
            "size can (a count or an index in the file is far too large)"
        ) from error
    except (Exception, SystemExit) as error:  # meshio raises many kinds, or exits
        problem = clipped(str(error) or type(error).__name__, 300)
        raise FormatError(name, None, f"meshio cannot read it: {problem}") from error
    finally:
        notes.extend(f"meshio: {message}" for message in messages[:5])


def read_meshio(path: Path) -> tuple[Value, list[str]]:
    """A file meshio can read, as a Mesh2 of its triangle cells."""
    name = str(path)
    check_regular(path)  # before meshio opens it: a FIFO would block, /dev/zero not end
    notes: list[str] = []
    data = _meshio_read(path, notes)
    if is_mixed_file(data.cells):
        return mixed_of_meshio(name, points3(name, data), data.cells, BOUNDARY_CELLS,
                               notes), notes
    if any(block.type == "tetra" for block in data.cells):
        return tetrahedral_of_meshio(name, data, notes), notes
    return mesh2_of_meshio(name, data, notes), notes


SEGMENT_MARKER_DATA = ("marker", "gmsh:physical")
"""Cell data of ``line`` blocks read as segment markers, the first present (an all-zero
``gmsh:physical`` is meshio's filler for a file without physical groups: not read)."""


def _block_values(name: str, data: Any, keys: Sequence[str], index: int, count: int
                  ) -> Any | None:
    """The first of the cell data ``keys`` on block ``index`` (``count`` rows), as an
    array, skipping an all-zero ``gmsh:physical``; None when there is none."""
    import numpy

    for key in keys:
        blocks = data.cell_data.get(key)
        if blocks is None or index >= len(blocks):
            continue
        values = numpy.asarray(blocks[index])
        if key == "gmsh:physical" and not values.any():
            continue
        if len(values) != count:
            raise FormatError(name, None, f"cell data {key!r} of block {index} has "
                              f"{len(values)} values for {count} cells")
        return values
    return None


def _numbered(arrays: Any, prefix: str) -> list[str]:
    """The keys ``prefix0``, ``prefix1``, … of ``arrays``, in order, as far as they go."""
    keys: list[str] = []
    while f"{prefix}{len(keys)}" in arrays:
        keys.append(f"{prefix}{len(keys)}")
    return keys


def _stacked(columns: Sequence[Any]) -> Any:
    import numpy

    return numpy.column_stack([numpy.asarray(column).reshape(-1) for column in columns])


def _attribute_columns(name: str, data: Any, index: int, count: int) -> Any | None:
    """The triangle attributes of block ``index``: the cell data ``triangle_attribute_k``
    (k = 0, 1, …), else a nonzero ``gmsh:physical`` (Gmsh's physical surface: one
    attribute); None when there are none."""
    columns = _numbered(data.cell_data, TRIANGLE_ATTRIBUTE)
    if columns:
        return _stacked([_block_values(name, data, (key,), index, count) for key in columns])
    return _block_values(name, data, ("gmsh:physical",), index, count)


def _exact_rows(name: str, what: str, values: Any) -> list[tuple[Rational, ...]]:
    """Rows of doubles (or integers) as tuples of their exact rationals."""
    rows = []
    for index, row in enumerate(values.reshape(len(values), -1).tolist()):
        try:
            rows.append(tuple(to_rational(value) for value in row))
        except RationalParseError as error:
            raise FormatError(name, None, f"{what} {index}: {error}") from error
    return rows


def mesh2_of_meshio(name: str, data: Any, notes: list[str]) -> Mesh2:
    """A planar meshio mesh as a :class:`Mesh2`, nothing dropped: its ``triangle``
    blocks, ``line`` blocks as segments (markers: :data:`SEGMENT_MARKER_DATA`, else 1),
    ``vertex`` blocks with physical tags as vertex markers, the cell data
    ``triangle_attribute_k`` (else a nonzero ``gmsh:physical``) of the triangles as their
    attributes and the point data ``vertex_markers``/``vertex_attribute_k``; each double
    exactly the rational it is.  Problems are FormatErrors on ``name``."""
    raw_points = data.points
    if raw_points.ndim != 2 or raw_points.shape[1] not in (2, 3):
        raise FormatError(name, None, f"points have shape {raw_points.shape}; expected n x 2|3")
    points: list[Point2] = []
    for index, row in enumerate(raw_points.tolist()):
        try:
            x, y = to_rational(row[0]), to_rational(row[1])
            z = to_rational(row[2]) if len(row) == 3 else 0
        except RationalParseError as error:
            raise FormatError(name, None, f"point {index}: {error}") from error
        if z != 0:
            raise FormatError(
                name,
                None,
                f"point {index} has z = {row[2]!r}; only planar meshes (z = 0) are supported",
            )
        points.append(point2(x, y))
    count = len(points)
    triangles: list[tuple[int, int, int]] = []
    attributes: list[tuple[Rational, ...]] = []
    attributed_blocks = triangle_blocks = 0
    segments: list[tuple[int, int, int]] = []
    vertex_markers: dict[int, int] = {}
    for index, block in enumerate(data.cells):
        shape: tuple[int, ...] = tuple(getattr(block.data, "shape", ()))
        if block.type == "triangle":
            if len(shape) != 2 or (shape[0] and shape[1] != 3):
                raise FormatError(
                    name, None, f"its triangle cells have shape {shape}; expected n x 3"
                )
            triangles.extend(
                (int(a), int(b), int(c)) for a, b, c in block.data.tolist()
            )
            triangle_blocks += 1
            values = _attribute_columns(name, data, index, len(block.data))
            if values is not None:
                attributed_blocks += 1
                attributes.extend(_exact_rows(name, "triangle attribute", values))
        elif block.type == "line":
            if len(shape) != 2 or (shape[0] and shape[1] != 2):
                raise FormatError(name, None, f"its line cells have shape {shape}; "
                                  "expected n x 2")
            values = _block_values(name, data, SEGMENT_MARKER_DATA, index, len(block.data))
            markers = [1] * len(block.data) if values is None else [
                _integer(name, "segment marker", value) for value in values.tolist()]
            for (u, v), marker in zip(block.data.tolist(), markers, strict=True):
                _in_range(name, "line", (int(u), int(v)), count)
                segments.append((int(u), int(v), marker))
        elif block.type == "vertex":
            values = _block_values(name, data, ("gmsh:physical",), index, len(block.data))
            if values is None:
                notes.append(f"ignored {len(block.data)} vertex cells (no physical tags)")
                continue
            for (vertex,), marker in zip(block.data.tolist(), values.tolist(), strict=True):
                _in_range(name, "vertex cell", (int(vertex),), count)
                vertex_markers[int(vertex)] = _integer(name, "vertex marker", marker)
        elif block.type in IGNORED_CELLS:
            notes.append(f"ignored {len(block.data)} {block.type} cells")
        else:
            raise FormatError(
                name,
                None,
                f"has {block.type} cells; only triangle meshes are supported",
            )
    for index, triangle in enumerate(triangles):
        for vertex in triangle:
            if not 0 <= vertex < count:
                raise FormatError(
                    name,
                    None,
                    f"triangle {index} {triangle}: vertex {vertex} is out of range "
                    f"(there are {count} points)",
                )
    if not triangles and (segments or vertex_markers):
        raise FormatError(name, None, "has line or vertex cells but no triangles: a "
                          "PSLG is read from a .poly or .pslg file")
    if attributed_blocks and attributed_blocks != triangle_blocks:
        raise FormatError(name, None, "only some triangle blocks have attributes (cell "
                          "data triangle_attributes or gmsh:physical)")
    marker_rows = data.point_data.get("vertex_markers")
    if marker_rows is not None:
        vertex_markers.update(
            (vertex, _integer(name, "vertex marker", value))
            for vertex, value in enumerate(marker_rows.reshape(-1).tolist()) if value)
    columns = _numbered(data.point_data, VERTEX_ATTRIBUTE)
    vertex_attributes = (None if not columns else _exact_rows(
        name, "vertex attribute", _stacked([data.point_data[key] for key in columns])))
    table = TriangleTable(path=name, triangles=triangles, lines=[None] * len(triangles),
                          attributes=attributes if attributed_blocks else None)
    return build_mesh(
        points, [None] * count, table, point_path=name, notes=notes,
        vertex_markers=[vertex_markers.get(v, 0) for v in range(count)]
        if vertex_markers else None,
        vertex_attributes=vertex_attributes, segments=segments,
        segment_lines=[None] * len(segments), segment_path=name)


def _integer(name: str, what: str, value: Any) -> int:
    """A marker read as a number: an integer (a double that is one), else a FormatError."""
    if isinstance(value, float) and not value.is_integer():
        raise FormatError(name, None, f"a {what} is {value!r}, not an integer")
    return int(value)


def _in_range(name: str, what: str, ids: tuple[int, ...], count: int) -> None:
    for vertex in ids:
        if not 0 <= vertex < count:
            raise FormatError(name, None, f"{what} {ids}: vertex {vertex} is out of range "
                              f"(there are {count} points)")


def points3(name: str, data: Any) -> list[Point3]:
    """The ``n x 3`` points of a meshio mesh, each double as its exact binary value."""
    raw_points = data.points
    if raw_points.ndim != 2 or raw_points.shape[1] != 3:
        raise FormatError(name, None, f"points have shape {raw_points.shape}; expected n x 3")
    points: list[Point3] = []
    for index, row in enumerate(raw_points.tolist()):
        try:
            points.append(point3(*(to_rational(value) for value in row)))
        except RationalParseError as error:
            raise FormatError(name, None, f"point {index}: {error}") from error
    return points


def tetrahedral_of_meshio(name: str, data: Any, notes: list[str]) -> Mesh3:
    """The ``tetra`` cells of a meshio mesh as a :class:`Mesh3` (exact 3D points), oriented
    by :func:`~geomexact.io.tetrahedron_orientation.orient_tetrahedra`; FormatErrors name
    the tetrahedron and its cell (its index among all the file's cells, from 0)."""
    points = points3(name, data)
    tetrahedra: list[tuple[int, int, int, int]] = []
    cells: list[int] = []  # the cell of each tetrahedron
    first_cell = 0
    for block in data.cells:
        if block.type == "tetra":
            shape: tuple[int, ...] = tuple(getattr(block.data, "shape", ()))
            if len(shape) != 2 or (shape[0] and shape[1] != 4):
                raise FormatError(
                    name, None, f"its tetra cells have shape {shape}; expected n x 4"
                )
            tetrahedra.extend(
                (int(a), int(b), int(c), int(d)) for a, b, c, d in block.data.tolist()
            )
            cells.extend(range(first_cell, first_cell + len(block.data)))
        elif block.type in BOUNDARY_CELLS:
            notes.append(f"ignored {len(block.data)} {block.type} cells")
        else:  # a solid cell that is not a tetrahedron: dropping it would lose volume
            raise FormatError(
                name, None,
                f"has {len(block.data)} {block.type} cell(s) (from cell {first_cell}); only "
                "tetrahedral meshes are read (lower-dimensional cells, a boundary's, are "
                "ignored): nothing was read rather than drop them")
        first_cell += len(block.data)

    def describe(index: int) -> str:
        corners = ", ".join(map(str, tetrahedra[index]))
        return f"tetrahedron ({corners}) in cell {cells[index]}"

    count = len(points)
    for index, tetrahedron in enumerate(tetrahedra):
        outside = [vertex for vertex in tetrahedron if not 0 <= vertex < count]
        if outside:
            raise FormatError(name, None, f"{describe(index)}: vertex {outside[0]} is out of "
                              f"range (there are {count} points)")
        if len(set(tetrahedron)) < 4:
            raise FormatError(name, None, f"{describe(index)} repeats a vertex")
    rows = orient_tetrahedra(name, points, tetrahedra, describe, notes)
    try:  # in bulk; an overlap is then found again one tetrahedron at a time, to name it
        return mesh3_from_positive_arrays(points, rows)
    except PreconditionError:
        pass
    owner: dict[tuple[int, int, int], int] = {}  # oriented face -> its tetrahedron
    for index, tetrahedron in enumerate(rows.tolist()):
        faces = [face for face, _ in tetrahedron_faces(*tetrahedron)]
        for face in faces:
            if face in owner:
                raise FormatError(
                    name, None, f"the tetrahedra overlap: face {face} of {describe(index)} is "
                    f"on the same side as {describe(owner[face])}")
        owner.update((face, index) for face in faces)
    try:
        return mesh3_from_tetrahedra(points, rows.tolist())
    except PreconditionError as error:
        raise FormatError(name, None, str(error)) from error


def _doubles3(path: Path, points: Sequence[Point3]) -> tuple[Any, int]:
    """3D ``points`` as doubles (V x 3 array) and how many coordinates that rounds; a
    FormatError naming the first vertex beyond the range of a double."""
    return _double_rows(path, points, 3, ".ele")


def _doubles(path: Path, mesh: Mesh2) -> tuple[Any, int]:
    """The vertices as doubles (V x 3 array, z = 0) and how many coordinates that rounds;
    a FormatError naming the first vertex beyond the range of a double."""
    return _double_rows(path, mesh.point_list(), 2, ".off, .ele, .pslg")


def _double_rows(path: Path, points: Sequence[Point2] | Sequence[Point3], dimension: int,
                 exact_formats: str) -> tuple[Any, int]:
    import numpy

    count = len(points)
    rows = numpy.zeros((count, 3))
    for axis in range(dimension):  # the points' own nearest doubles (NaN beyond the range)
        rows[:, axis] = numpy.fromiter((p[dimension + axis] for p in points),
                                       dtype=numpy.float64, count=count)
    beyond = numpy.isnan(rows).any(axis=1)
    if beyond.any():
        raise FormatError(
            str(path), None,
            f"vertex {int(beyond.argmax())} has a coordinate beyond the range of a double, "
            f"which these formats store; write an exact text format ({exact_formats}) "
            "instead")
    # (gmpy2 compares an mpq with a float exactly)
    exact = (value for point in points for value in point[:dimension])
    rounded = sum(map(operator.ne, exact, rows[:, :dimension].ravel().tolist()))
    return rows, rounded


_MIXED_EXTENSIONS = (".vtu", ".vtk", ".msh")
"""Where a mixed-cell mesh is written."""
_GMSH_DOUBLE_INTEGERS = 1 << 53
"""Gmsh stores cell data as doubles: integers below this in magnitude are exact."""


def write_meshio(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A Mesh2, Mesh3 or mixed-cell mesh through meshio as doubles (the format is chosen by
    the extension); every coordinate that is not a double is rounded and counted,
    markers, attributes and segments are dropped and reported; numbers ``"exact"`` is
    refused (FormatError).  A mixed mesh (:func:`_write_mixed`) goes to .vtu, .vtk or
    .msh only; a Mesh3's .vtu is written by geomexact (:func:`_write_mesh3`)."""
    if not isinstance(value, (Mesh2, Mesh3, MixedMesh3, MixedMeshData)):
        raise UnsupportedValueError(
            f"the meshio format writes a Mesh2, Mesh3 or MixedMesh3, not a "
            f"{type(value).__name__}"
        )
    if numbers == "exact":
        raise FormatError(
            str(path), None,
            "the meshio formats store doubles and cannot hold exact numbers; write an exact "
            "text format (.off, .ele, .pslg) for exact output",
        )
    if isinstance(value, (MixedMesh3, MixedMeshData)):
        return _write_mixed(path, value, overwrite=overwrite)
    if isinstance(value, Mesh3):
        return _write_mesh3(path, value, overwrite=overwrite)
    meshio = meshio_module()
    import numpy

    if path.exists() and not overwrite:
        raise OverwriteError(str(path))
    # 32-bit indices where they fit: some writers (PLY) warn on 64-bit ones
    index_type = numpy.int32 if value.vertex_count < 2**31 else numpy.int64
    rows, rounded = _doubles(path, value)
    suffix = path.suffix.lower()
    if suffix not in KEEPS_EVERYTHING:
        cells = ("triangle", numpy.array(value.triangles(), dtype=index_type).reshape(-1, 3))
        _write_through_meshio(path, meshio.Mesh(rows, [cells]), overwrite=overwrite)
        return WriteReport((path,), rounded, dropped_parts(value, ()))
    converted, more, dropped = mesh2_meshio(str(path), value, gmsh=suffix == ".msh")
    converted.points = rows
    _write_through_meshio(path, converted, overwrite=overwrite,
                          file_format="gmsh22" if suffix == ".msh" else None)
    return WriteReport((path,), rounded + more, dropped)


def _write_mesh3(path: Path, mesh: Mesh3, *, overwrite: bool) -> WriteReport:
    """:func:`write_meshio` of a tetrahedral mesh: .vtu by geomexact's binary writer
    (:func:`~geomexact.io.vtu_grid.binary_vtu`), the other formats by meshio; the files
    that keep everything get each tetrahedron's smallest dihedral angle."""
    import numpy

    if path.exists() and not overwrite:
        raise OverwriteError(str(path))
    suffix = path.suffix.lower()
    points, rounded = _doubles3(path, mesh.point_list())
    # 32-bit indices where they fit: some writers (PLY) warn on 64-bit ones
    index_type = numpy.int32 if mesh.vertex_count < 2**31 else numpy.int64
    tetrahedra = mesh.tetrahedron_array().astype(index_type)
    cell_data: dict[str, Any] = {}
    if suffix in KEEPS_EVERYTHING and len(tetrahedra):
        from geomexact.mesh3d.quality import dihedral_angles

        cell_data[QUALITY_3D] = dihedral_angles(points, tetrahedra).min(axis=1)
    if suffix == ".vtu":
        count = len(tetrahedra)
        write_bytes_atomic(path, binary_vtu(
            points, numpy.full(count, TETRAHEDRON, dtype=numpy.uint8), tetrahedra.ravel(),
            numpy.arange(4, 4 * count + 1, 4, dtype=numpy.int64), cell_data),
            overwrite=overwrite)
        return WriteReport((path,), rounded, ())
    meshio_data = {name: [values] for name, values in cell_data.items()}
    if suffix == ".msh":
        # Python floats: meshio's Gmsh text writer prints each value's repr
        meshio_data = {name: [numpy.array(values.tolist(), dtype=object)]
                       for name, values in cell_data.items()}
        if len(tetrahedra):
            meshio_data["gmsh:physical"] = [numpy.zeros(len(tetrahedra), dtype=numpy.int32)]
            meshio_data["gmsh:geometrical"] = [numpy.zeros(len(tetrahedra),
                                                           dtype=numpy.int32)]
    _write_through_meshio(path, meshio_module().Mesh(points, [("tetra", tetrahedra)],
                                                     cell_data=meshio_data),
                          overwrite=overwrite,
                          file_format="gmsh22" if suffix == ".msh" else None)
    return WriteReport((path,), rounded, ())


KEEPS_EVERYTHING = (".vtu", ".vtk", ".msh", ".xdmf", ".xmf")
QUALITY_2D = "min_angle"
QUALITY_3D = "min_dihedral"
"""The cell data of a triangle's smallest angle and a tetrahedron's smallest dihedral
angle (degrees, doubles) in the files that keep everything: derived, never read back."""
TRIANGLE_ATTRIBUTE = "triangle_attribute_"
VERTEX_ATTRIBUTE = "vertex_attribute_"
"""Prefixes of the data arrays of attribute k (one scalar array per attribute: VTK
files pad arrays of two or three components as vectors)."""
"""The meshio formats a triangle mesh is written to with its segments (a ``line``
block), markers and attributes (cell and point data): :func:`mesh2_meshio`.  The others
(Medit, OBJ, PLY) get the triangles, and the report names what they dropped."""

_INT32 = range(-(1 << 31), 1 << 31)


def _uniform(rows: Sequence[tuple[Any, ...]]) -> bool:
    return len({len(row) for row in rows}) <= 1


def mesh2_meshio(name: str, mesh: Mesh2, *, gmsh: bool = False,
                 numbers: str = "nearest") -> tuple[Any, int, tuple[str, ...]]:
    """``mesh`` as a ``meshio.Mesh`` keeping everything (read back by
    :func:`mesh2_of_meshio`): points ``n x 2`` (``numbers``: ``"nearest"`` doubles or
    ``"exact"`` rationals), a ``triangle`` block (``triangles()`` order) and a ``line``
    block of the segments (sorted); cell data ``marker`` (0 on triangles, each segment's
    marker on lines) and ``triangle_attribute_k`` (NaN on lines), point data
    ``vertex_markers`` and ``vertex_attribute_k``; with ``gmsh`` also the tags
    ``gmsh:physical`` (segment markers, and a single integral triangle attribute, where
    they fit Gmsh's 32 bits) and ``gmsh:geometrical``.  Returns (the object, how many
    attribute values were rounded to doubles, the parts it could not hold: attributes of
    varying length).  Markers beyond 2^53 are refused for Gmsh, which stores data as
    doubles (FormatError on ``name``)."""
    meshio = meshio_module()
    import numpy

    vertex_count = mesh.vertex_count
    triangles = numpy.array(mesh.triangles(), dtype=numpy.int64).reshape(-1, 3)
    edges = sorted(mesh.segments.items())
    dropped: list[str] = []
    rounded = 0

    def doubles(rows: Sequence[tuple[Any, ...]], what: str) -> Any | None:
        nonlocal rounded
        if not _uniform(rows):
            dropped.append(f"{what} (of varying length)")
            return None
        if numbers == "exact":
            array = numpy.empty((len(rows), len(rows[0]) if rows else 0), dtype=object)
            for i, row in enumerate(rows):
                array[i, :] = [gmpy2.mpq(value) for value in row]
            return array
        array = numpy.array([[to_float(value) for value in row] for row in rows],
                            dtype=float).reshape(len(rows), -1)
        rounded += sum(gmpy2.mpq(double) != value for row, doubles_row in
                       zip(rows, array.tolist(), strict=True)
                       for value, double in zip(row, doubles_row, strict=True))
        return array

    def exact_integers(what: str, values: Sequence[int]) -> None:
        big = [value for value in values if abs(value) >= _GMSH_DOUBLE_INTEGERS]
        if gmsh and big:
            raise FormatError(name, None, f"{what} {big[0]} is beyond what Gmsh's double "
                              "values hold exactly; nothing was written")

    if numbers == "exact":
        points: Any = numpy.empty((vertex_count, 2), dtype=object)
        for vertex, point in enumerate(mesh.point_list()):
            points[vertex, :] = [point.x, point.y]
    else:
        points = numpy.array([[point.fx, point.fy] for point in mesh.point_list()],
                             dtype=float).reshape(-1, 2)
    cells: list[tuple[str, Any]] = [("triangle", triangles)]
    cell_data: dict[str, list[Any]] = {}
    point_data: dict[str, Any] = {}
    markers = [marker for _, marker in edges]
    exact_integers("a segment marker", markers)
    if edges:
        cells.append(("line", numpy.array([edge for edge, _ in edges], dtype=numpy.int64)))
        cell_data["marker"] = [numpy.zeros(len(triangles), dtype=numpy.int64),
                               numpy.array(markers, dtype=numpy.int64)]
    # the quality of each triangle, for ParaView (read back by nothing: derived)
    from geomexact.mesh2d.quality import min_angles

    xy = numpy.array([[point.fx, point.fy] for point in mesh.point_list()],
                     dtype=float).reshape(-1, 2)
    cell_data[QUALITY_2D] = [min_angles(xy, triangles)] + (
        [numpy.full(len(edges), numpy.nan)] if edges else [])
    if len(mesh.triangle_attributes):
        rows = [tuple(mesh.triangle_attributes.get((a, b, c), ()))
                for a, b, c in mesh.triangles()]
        array = doubles(rows, "triangle attributes")
        if array is not None:
            for column in range(array.shape[1]):  # scalars: VTK pads 2-vectors to 3
                cell_data[f"{TRIANGLE_ATTRIBUTE}{column}"] = [array[:, column]] + (
                    [numpy.full(len(edges), numpy.nan)] if edges else [])
    if gmsh:
        physical = [numpy.zeros(len(triangles), dtype=numpy.int32)]
        single = cell_data.get(f"{TRIANGLE_ATTRIBUTE}0", [None])[0]
        if single is not None and f"{TRIANGLE_ATTRIBUTE}1" not in cell_data:
            whole = [int(value) for value in single.tolist()
                     if float(value).is_integer() and int(value) in _INT32]
            if len(whole) == len(single):
                physical[0] = numpy.array(whole, dtype=numpy.int32)
        if edges:
            physical.append(numpy.array([m if m in _INT32 else 0 for m in markers],
                                        dtype=numpy.int32))
        cell_data["gmsh:physical"] = physical
        cell_data["gmsh:geometrical"] = [numpy.zeros(len(block), dtype=numpy.int32)
                                         for _, block in cells]
    if any(mesh.vertex_markers.values()):
        values = [mesh.vertex_markers.get(v, 0) for v in range(vertex_count)]
        exact_integers("a vertex marker", values)
        point_data["vertex_markers"] = numpy.array(values, dtype=numpy.int64)
    if len(mesh.vertex_attributes):
        array = doubles([tuple(mesh.vertex_attributes.get(v, ())) for v in range(vertex_count)],
                        "vertex attributes")
        if array is not None:
            for column in range(array.shape[1]):
                point_data[f"{VERTEX_ATTRIBUTE}{column}"] = array[:, column]
    if gmsh:  # Python numbers: meshio's Gmsh text writer prints each value's repr
        point_data = {key: numpy.array(values.tolist(), dtype=object)
                      for key, values in point_data.items()}
        cell_data = {key: blocks if key.startswith("gmsh:") else
                     [numpy.array(block.tolist(), dtype=object) for block in blocks]
                     for key, blocks in cell_data.items()}
    converted = meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data)
    return converted, rounded, tuple(dropped)


def _write_through_meshio(path: Path, mesh: Any, *, overwrite: bool,
                          file_format: str | None = None) -> None:
    """meshio writes ``mesh`` into a scratch directory beside ``path`` (in
    ``file_format``, else the one the extension names), then the bytes are moved into
    place atomically; any meshio failure is a FormatError naming ``path``."""
    meshio = meshio_module()
    suffix = path.suffix.lower()
    options = dict(_WRITE_OPTIONS.get(suffix, {}))
    if file_format is not None:
        options["file_format"] = file_format
    elif suffix in _MESHIO_FORMATS:
        options["file_format"] = _MESHIO_FORMATS[suffix][0]
    directory = path.parent if str(path.parent) else Path(".")
    with tempfile.TemporaryDirectory(prefix=".geomexact-", dir=directory) as scratch:
        temporary = Path(scratch) / path.name
        try:
            with contextlib.redirect_stdout(StringIO()):  # meshio prints warnings
                meshio.write(temporary, mesh, **options)
        except ImportError as error:
            raise FormatError(str(path), None, _missing(error)) from error
        except Exception as error:  # meshio raises many kinds
            raise FormatError(str(path), None, f"meshio cannot write it: {error}") from error
        data = temporary.read_bytes()
    write_bytes_atomic(path, data, overwrite=overwrite)


def _write_mixed(path: Path, value: MixedMesh3 | MixedMeshData, *,
                 overwrite: bool) -> WriteReport:
    """A mixed-cell mesh as .vtu (geomexact's binary writer; with polyhedra its VTU
    text), .vtk (meshio's writer; with polyhedra geomexact's VTK text,
    :mod:`geomexact.io.vtk_polyhedra`) or Gmsh 2.2 text .msh (standard kinds only;
    Gmsh 4.1 through meshio takes one cell type per file).  Cells in ``cell_list()``
    order, cell data ``kind`` (VTK type) and the caller's arrays; points as doubles,
    rounding counted.  Everything is refused before anything is written."""
    mesh, extra = parts_of(value)
    name = str(path)
    suffix = path.suffix.lower()
    if suffix not in _MIXED_EXTENSIONS:
        raise FormatError(name, None, f"a mixed-cell mesh is written as "
                          f"{', '.join(_MIXED_EXTENSIONS)} only, not {suffix or 'no extension'}")
    polyhedra = [cell for cell in mesh.cell_list() if cell.kind == CellKind.POLYHEDRON]
    if polyhedra and suffix == ".msh":
        raise FormatError(name, None, f"Gmsh .msh has no polyhedron cells and the mesh has "
                          f"{len(polyhedra)} (the first {clipped(str(polyhedra[0]), 120)}); "
                          "nothing was written: write .vtu or .vtk")

    def gmsh_exact(array: str, values: Sequence[int]) -> None:
        big = [v for v in values if abs(v) >= _GMSH_DOUBLE_INTEGERS]
        if big and suffix == ".msh":
            raise FormatError(name, None, f"cell data {array!r} holds {big[0]}, which Gmsh's "
                              "double values cannot hold exactly; nothing was written")

    arrays = cell_arrays(mesh, extra, gmsh_exact)
    if path.exists() and not overwrite:
        raise OverwriteError(name)
    rows, rounded = _doubles3(path, [mesh.point(v) for v in range(mesh.vertex_count)])
    if polyhedra:
        types, entries = cell_entries(mesh)
        writer = vtu_text if suffix == ".vtu" else legacy_vtk_text
        text = writer(rows.tolist(), types, entries, arrays)
        write_bytes_atomic(path, text.encode("utf-8"), overwrite=overwrite)
        return WriteReport((path,), rounded, ())
    import numpy

    if suffix == ".vtu":
        types, entries = cell_entries(mesh)
        write_bytes_atomic(path, binary_vtu(
            rows, numpy.array(types, dtype=numpy.uint8),
            numpy.array([v for entry in entries for v in entry], dtype=numpy.int64),
            numpy.cumsum([len(entry) for entry in entries], dtype=numpy.int64),
            {name: numpy.array(values, dtype=numpy.int64) for name, values in arrays.items()}),
            overwrite=overwrite)
        return WriteReport((path,), rounded, ())
    meshio = meshio_module()

    blocks = meshio_blocks(mesh)
    index_type = numpy.int32 if mesh.vertex_count < 2**31 else numpy.int64
    cells = [(kind, numpy.array(rows_of_kind, dtype=index_type)) for kind, rows_of_kind in
             blocks]
    cell_data: dict[str, list[Any]] = {}
    start = 0
    for _, members in blocks:
        for array, values in arrays.items():
            # Python ints: meshio's Gmsh text writer prints each value's repr
            chunk = values[start:start + len(members)]
            cell_data.setdefault(array, []).append(
                numpy.array(chunk, dtype=object if suffix == ".msh" else numpy.int64))
        start += len(members)
    _write_through_meshio(path, meshio.Mesh(rows, cells, cell_data=cell_data),
                          overwrite=overwrite,
                          file_format="gmsh22" if suffix == ".msh" else None)
    return WriteReport((path,), rounded, ())
