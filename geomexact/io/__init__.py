"""Reading and writing meshes (2D, tetrahedral and mixed-cell), PSLGs and polygon meshes,
one module per format behind one registry.  Spec: ``specs/formats/registry.md`` (and one spec per
format beside it).

>>> from geomexact import io
>>> sorted(io.FORMATS)  # doctest: +NORMALIZE_WHITESPACE
['geomview3d', 'geomview3d-boundary', 'mellado', 'meshio', 'node', 'off', 'poly', 'pslg',
 'tetgen', 'triangle', 'trilist', 'vect']
>>> io.detect_format("pikachu.1.ele")
'triangle'

``read`` parses numbers exactly (decimal text is a rational, never a double) and reports
every problem of the input as a :class:`~geomexact.errors.FormatError` naming the file,
the line and the problem.  ``write`` refuses to replace an existing file unless
``overwrite=True`` and writes atomically.  It is lossless by default: every number with a
finite decimal expansion (integers, decimals, dyadic midpoints, grid centroids) is written
as that exact decimal, and only the others are rounded to the nearest double, counted in
the :class:`WriteReport` of :func:`write_with_report`; ``numbers="exact"`` (or
``exact=True``) writes those as ``p/q`` instead, ``numbers="float"`` rounds every number
to the nearest double.  What a format cannot hold (the markers in an OFF file, …) is
listed in the report.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from pathlib import Path
from types import MappingProxyType
from typing import Any

import attrs

from geomexact.errors import FormatError, UnsupportedValueError
from geomexact.io.registry import (
    MESHIO_EXTENSIONS,
    NUMBER_STYLES,
    Format,
    NumberStyle,
    Reading,
    SourceLines,
    Value,
    WriteReport,
    bounded,
)
from geomexact.kernel.collector import collector_paused
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3


@attrs.frozen(slots=True)
class _OnFirstUse:
    """A function of a format's module, imported when first called: a command loads only
    the formats it reads and writes (NumPy, meshio and the bulk readers are not paid for by
    ``geomexact info`` on a small OFF file)."""

    module: str
    name: str

    def __call__(self, *args: Any, **options: Any) -> Any:
        function = getattr(importlib.import_module(f"geomexact.io.{self.module}"), self.name)
        return function(*args, **options)


read_off, write_off = _OnFirstUse("off", "read_off"), _OnFirstUse("off", "write_off")
read_mellado = _OnFirstUse("mellado_text", "read_mellado")
read_triangle_list = _OnFirstUse("triangle_list", "read_triangle_list")
read_triangle = _OnFirstUse("triangle", "read_triangle")
write_triangle = _OnFirstUse("triangle", "write_triangle")
read_tetgen, write_tetgen = _OnFirstUse("tetgen", "read_tetgen"), _OnFirstUse(
    "tetgen", "write_tetgen")


def _read_ele(path: Path) -> tuple[Value, list[str]]:
    """An ``.ele`` mesh: TetGen when the ``.node`` beside it says dimension 3, else
    Triangle."""
    from geomexact.io.tetgen import node_dimension

    if node_dimension(path) == 3:
        return read_tetgen(path)  # type: ignore[no-any-return]
    return read_triangle(path)  # type: ignore[no-any-return]


def _write_ele(
    path: Path, value: Value, /, *, overwrite: bool, numbers: NumberStyle
) -> WriteReport:
    """A :class:`Mesh3` as TetGen files, anything else as Triangle files."""
    writer = write_tetgen if isinstance(value, Mesh3) else write_triangle
    return writer(path, value, overwrite=overwrite, numbers=numbers)  # type: ignore[no-any-return]


def _read_txt(path: Path) -> tuple[Value, list[str]]:
    """A ``.txt`` mesh: Mellado's text when it starts with a section header (his programs
    write ``.txt``), else the triangle list."""
    from geomexact.io.mellado_text import looks_like_mellado

    if looks_like_mellado(path):
        return read_mellado(path)  # type: ignore[no-any-return]
    return read_triangle_list(path)  # type: ignore[no-any-return]


def _write_only(path: Path) -> tuple[Value, list[str]]:
    """The reader of a write-only format: a FormatError."""
    raise FormatError(str(path), None, "this format is write-only (a picture of a Mesh3)")


def _ele_outputs(path: Path) -> tuple[Path, ...]:
    from geomexact.io.tetgen import tetgen_output_paths
    from geomexact.io.triangle import triangle_output_paths

    return tuple(dict.fromkeys(triangle_output_paths(path) + tetgen_output_paths(path)))


_FORMATS: tuple[Format, ...] = (
    Format(
        "triangle",
        (".ele",),
        "Triangle mesh: .ele named, .node beside it (required), .neigh checked, "
        ".poly segments; a 3D .node (dimension 3) or a Mesh3 goes to tetgen",
        _read_ele,
        _write_ele,
        (Mesh2, Mesh3),
        _ele_outputs,
    ),
    Format(
        "tetgen",
        (),
        "TetGen tetrahedral mesh: .ele named, 3D .node beside it (required), .face "
        "checked; selected for .ele by the .node's dimension 3",
        read_tetgen,
        write_tetgen,
        (Mesh3,),
        _OnFirstUse("tetgen", "tetgen_output_paths"),
    ),
    Format(
        "node",
        (".node",),
        "Triangle .node alone: a point set (PSLG without segments)",
        _OnFirstUse("triangle", "read_node"),
        _OnFirstUse("triangle", "write_node"),
        (PSLG,),
    ),
    Format(
        "poly",
        (".poly",),
        "Triangle .poly: a PSLG with segments, holes and regions",
        _OnFirstUse("triangle", "read_poly"),
        _OnFirstUse("triangle", "write_poly"),
        (PSLG,),
    ),
    Format(
        "off",
        (".off",),
        "OFF (also inside a Geomview { appearance … LIST … } block), planar: triangle or "
        "polygon mesh",
        read_off,
        write_off,
        (Mesh2, PolygonMesh),
    ),
    Format(
        "pslg",
        (".pslg",),
        "line-tagged PSLG text: v/s/h/r records (PSLG) or v/t/n/s records (mesh)",
        _OnFirstUse("pslg_text", "read_pslg_text"),
        _OnFirstUse("pslg_text", "write_pslg_text"),
        (PSLG, Mesh2),
    ),
    Format(
        "trilist",
        (".txt",),
        "one triangle per line 'x1 y1 x2 y2 x3 y3' (a .txt that starts with a Vertices, "
        "Triangles or Neighbors header is read as Mellado's text)",
        _read_txt,
        _OnFirstUse("triangle_list", "write_triangle_list"),
        (Mesh2,),
    ),
    Format(
        "mellado",
        (".mellado",),
        "Mellado's text: Vertices/Triangles/Neighbors sections of v/t/n lines (0-based)",
        read_mellado,
        _OnFirstUse("mellado_text", "write_mellado"),
        (Mesh2,),
    ),
    Format(
        "meshio",
        MESHIO_EXTENSIONS,
        "2D triangle, tetrahedral and mixed-cell meshes through meshio (VTK, VTU, XDMF, "
        "Gmsh, …), doubles; mixed cells to .vtu, .vtk (polyhedra too) and .msh",
        _OnFirstUse("meshio_bridge", "read_meshio"),
        _OnFirstUse("meshio_bridge", "write_meshio"),
        (Mesh2, Mesh3, MixedMesh3, MixedMeshData),
    ),
)

_FORMATS += (
    Format(
        "geomview3d",
        (),
        "Geomview OFF of a tetrahedral mesh: 4 faces per tetrahedron, coloured by "
        "tetrahedron (write-only)",
        _write_only,
        _OnFirstUse("geomview3d", "write_tetrahedra_off"),
        (Mesh3,),
    ),
    Format(
        "geomview3d-boundary",
        (),
        "Geomview OFF of a tetrahedral mesh's boundary faces (write-only)",
        _write_only,
        _OnFirstUse("geomview3d", "write_boundary_off"),
        (Mesh3,),
    ),
    Format(
        "vect",
        (".vect",),
        "Geomview VECT wireframe of a tetrahedral mesh's edges (write-only)",
        _write_only,
        _OnFirstUse("geomview3d", "write_vect"),
        (Mesh3,),
    ),
)

FORMATS: Mapping[str, Format] = MappingProxyType({fmt.name: fmt for fmt in _FORMATS})
"""The registry: format name -> :class:`Format`."""

_BY_EXTENSION: dict[str, str] = {
    extension: fmt.name for fmt in _FORMATS for extension in fmt.extensions
}


def detect_format(path: str | Path) -> str:
    """The name of the format that ``path``'s extension selects (case-insensitive);
    :class:`FormatError` when no format claims it."""
    suffix = Path(path).suffix.lower()
    name = _BY_EXTENSION.get(suffix)
    if name is None:
        known = ", ".join(sorted(_BY_EXTENSION))
        shown = f"extension {suffix!r}" if suffix else "no extension"
        raise FormatError(
            str(path), None,
            f"{shown} names no known format (known: {known}); pass format= to name one",
        )
    return name


def _format(path: str | Path, format: str | None) -> Format:
    name = format if format is not None else detect_format(path)
    try:
        return FORMATS[name]
    except KeyError:
        raise FormatError(
            str(path), None, f"unknown format {name!r} (known: {', '.join(sorted(FORMATS))})"
        ) from None


def output_paths(path: str | Path, format: str | None = None) -> tuple[Path, ...]:
    """The files a write to ``path`` (format from its extension unless ``format`` names
    one) may create: ``path`` itself, or a multi-file format's set (``x.1.ele`` also
    writes ``x.1.node``, ``x.1.neigh`` and maybe ``x.1.poly``)."""
    return _format(path, format).outputs(Path(path))


def read_with_notes(path: str | Path, *, format: str | None = None) -> tuple[Value, list[str]]:
    """Read ``path`` (format from its extension unless ``format`` names one); return the
    value and the reader's notes (what it fixed or ignored, for verbose output)."""
    reader = _format(path, format).read
    try:
        with collector_paused():
            return reader(Path(path))
    except FormatError as error:
        raise bounded(error) from error.__cause__


_SOURCED_READERS: Mapping[str, Callable[[Path], Reading]] = MappingProxyType({
    "node": _OnFirstUse("triangle", "node_reading"),
    "poly": _OnFirstUse("triangle", "poly_reading"),
    "pslg": _OnFirstUse("pslg_text", "pslg_text_reading"),
})
"""The readers that also give the line of each item (:class:`SourceLines`)."""


def read_with_sources(path: str | Path, *, format: str | None = None) -> Reading:
    """:func:`read_with_notes`, with the file and line of each vertex, segment, hole and
    region where the format has lines for them (``node``, ``poly``, ``pslg``; else
    ``sources`` is None), so that a later error can name the input's lines."""
    chosen = _format(path, format)
    try:
        with collector_paused():
            sourced = _SOURCED_READERS.get(chosen.name)
            if sourced is not None:
                return sourced(Path(path))
            value, notes = chosen.read(Path(path))
    except FormatError as error:
        raise bounded(error) from error.__cause__
    return Reading(value, notes)


def read(path: str | Path, *, format: str | None = None) -> Value:
    """Read ``path`` as a :class:`Mesh2`, :class:`PSLG`, :class:`PolygonMesh`,
    :class:`Mesh3` or :class:`MixedMesh3` (see :func:`read_with_notes`)."""
    value, _ = read_with_notes(path, format=format)
    return value


def write_with_report(
    path: str | Path,
    value: Value,
    *,
    format: str | None = None,
    overwrite: bool = False,
    numbers: NumberStyle = "decimal",
    exact: bool = False,
) -> WriteReport:
    """Write ``value`` to ``path`` (and the other files of a multi-file format); return
    the paths written, how many numbers were rounded and what the format dropped.
    ``numbers`` is a :data:`~geomexact.io.registry.NumberStyle`; ``exact=True`` is
    ``numbers="exact"``.  ``UnsupportedValueError`` (a ``TypeError``) when the format
    cannot hold this kind of value."""
    chosen = _format(path, format)
    if not isinstance(value, chosen.kinds):
        kinds = " or ".join(kind.__name__ for kind in chosen.kinds)
        raise UnsupportedValueError(
            f"the {chosen.name} format writes a {kinds}, not a {type(value).__name__}"
        )
    if exact:
        numbers = "exact"
    if numbers not in NUMBER_STYLES:
        raise ValueError(f"numbers must be one of {', '.join(NUMBER_STYLES)}, not {numbers!r}")
    with collector_paused():  # a writer's tables are many small objects, freed at once
        return chosen.write(Path(path), value, overwrite=overwrite, numbers=numbers)


def write(
    path: str | Path,
    value: Value,
    *,
    format: str | None = None,
    overwrite: bool = False,
    numbers: NumberStyle = "decimal",
    exact: bool = False,
) -> list[Path]:
    """Write ``value`` to ``path``; return the paths written (see
    :func:`write_with_report`)."""
    report = write_with_report(
        path, value, format=format, overwrite=overwrite, numbers=numbers, exact=exact
    )
    return list(report.paths)


__all__ = [
    "FORMATS",
    "NUMBER_STYLES",
    "Format",
    "NumberStyle",
    "Reading",
    "SourceLines",
    "Value",
    "WriteReport",
    "detect_format",
    "output_paths",
    "read",
    "read_with_notes",
    "read_with_sources",
    "write",
    "write_with_report",
]
