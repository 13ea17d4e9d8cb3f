"""Meshes as NumPy arrays, without files (issue 26, item 2): :func:`to_arrays` and
:func:`from_arrays` for triangle meshes, PSLGs and tetrahedral meshes, and
:func:`triangulate_arrays`, a one-call API in the manner of the ``triangle`` package
(``triangulate({"vertices": ..., "segments": ..., "holes": ...}, ...)`` returning arrays).

Keys (those of the ``triangle`` package where they exist): ``vertices`` (n x 2 or n x 3),
``vertex_markers`` (n), ``vertex_attributes`` (n x k), ``triangles`` (t x 3, counter-
clockwise), ``triangle_attributes`` (t x k), ``segments`` (s x 2), ``segment_markers`` (s),
``holes`` (h x 2), ``regions`` (r x 4: x, y, attribute, maximum area or NaN),
``tetrahedra`` (t x 4, positive).  Numbers (``numbers=``): ``"double"`` (the default:
float64, refused when a value is not exactly a double -- nothing is rounded silently),
``"nearest"`` (float64, each value rounded to the nearest double, on purpose) or
``"exact"`` (an object array of ``mpq``); reading takes doubles (each exactly the rational
it is), integers, ``Fraction``/``mpq`` or exact text.  Nothing is dropped: every marker,
attribute and segment of the value is in the arrays and comes back; ids follow the
value's own order (vertices by id, triangles as :meth:`Mesh2.triangles` lists them)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Literal

import numpy as np

from geomexact.errors import PreconditionError, RationalParseError
from geomexact.io.registry import TriangleTable, build_mesh
from geomexact.kernel.numbers import Rational, mpq, to_rational
from geomexact.kernel.points import point2, point3
from geomexact.mesh2d.pslg import PSLG, RegionSeed
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_tetrahedra

__all__ = ["from_arrays", "number_array", "to_arrays", "triangulate_arrays"]

SOURCE = "arrays"
"""How errors name an input given as arrays."""


Numbers = Literal["double", "nearest", "exact"]


def number_array(values: Any, numbers: Numbers) -> Any:
    """Rows of numbers as an array: float64 (``"double"``: refused unless every value is
    exactly a double; ``"nearest"``: rounded on purpose) or ``mpq`` objects (``"exact"``)."""
    rows = [list(row) for row in values]
    if numbers == "exact":
        array = np.empty((len(rows), len(rows[0]) if rows else 0), dtype=object)
        for i, row in enumerate(rows):
            for j, value in enumerate(row):
                array[i, j] = None if value is None else mpq(value)
        return array
    doubles = np.array([[float(v) for v in row] for row in rows], dtype=np.float64).reshape(
        len(rows), -1)
    if numbers == "double":
        inexact = sum(1 for row in rows for v in row
                      if isinstance(v, type(mpq(0))) and mpq(float(v)) != v)
        if inexact:
            raise PreconditionError(
                "to_arrays", f"{inexact} number{'s are' if inexact != 1 else ' is'} not "
                "exactly a double: give numbers='exact' (rationals) or numbers='nearest' "
                "(rounded on purpose)")
    return doubles


def to_arrays(value: Mesh2 | PSLG | Mesh3, *, numbers: Numbers = "double"
              ) -> dict[str, Any]:
    """The arrays of ``value`` (module docstring), its numbers as ``numbers`` says."""
    if isinstance(value, Mesh2):
        ids = sorted(value.vertices)
        index = {vertex: i for i, vertex in enumerate(ids)}
        arrays: dict[str, Any] = {
            "vertices": number_array(([value.vertices[v].x, value.vertices[v].y] for v in ids),
                                 numbers).reshape(-1, 2)}
        triangles = value.triangles()
        arrays["triangles"] = np.array([[index[v] for v in t] for t in triangles],
                                       dtype=np.int64).reshape(-1, 3)
        if len(value.triangle_attributes):
            arrays["triangle_attributes"] = number_array(
                (value.triangle_attributes.get(t, ()) for t in triangles), numbers)
        if len(value.vertex_markers):
            arrays["vertex_markers"] = np.array([value.vertex_markers.get(v, 0) for v in ids],
                                                dtype=np.int64)
        if len(value.vertex_attributes):
            arrays["vertex_attributes"] = number_array(
                (value.vertex_attributes.get(v, ()) for v in ids), numbers)
        if len(value.segments):
            edges = sorted(value.segments.items())
            arrays["segments"] = np.array([[index[u], index[v]] for (u, v), _ in edges],
                                          dtype=np.int64).reshape(-1, 2)
            arrays["segment_markers"] = np.array([m for _, m in edges], dtype=np.int64)
        return arrays
    if isinstance(value, PSLG):
        arrays = {"vertices": number_array(([p.x, p.y] for p in value.vertices),
                                       numbers).reshape(-1, 2)}
        if value.segments:
            arrays["segments"] = np.array([[u, v] for u, v, _ in value.segments],
                                          dtype=np.int64)
            arrays["segment_markers"] = np.array([m for _, _, m in value.segments],
                                                 dtype=np.int64)
        if value.holes:
            arrays["holes"] = number_array(([p.x, p.y] for p in value.holes), numbers)
        if value.regions:
            arrays["regions"] = number_array(
                ([r.point.x, r.point.y, r.attribute,
                  r.max_area if r.max_area is not None else
                  None if numbers == "exact" else float("nan")] for r in value.regions),
                numbers)
        if value.vertex_markers:
            arrays["vertex_markers"] = np.array(value.vertex_markers, dtype=np.int64)
        if value.vertex_attributes:
            arrays["vertex_attributes"] = number_array(value.vertex_attributes, numbers)
        return arrays
    if isinstance(value, Mesh3):
        points = value.point_list()
        return {"vertices": number_array(([p.x, p.y, p.z] for p in points), numbers).reshape(-1, 3),
                "tetrahedra": np.array(value.tetrahedra(), dtype=np.int64).reshape(-1, 4)}
    raise PreconditionError("to_arrays", f"arrays hold a Mesh2, a PSLG or a Mesh3, not a "
                            f"{type(value).__name__}")


def _rational(value: Any, what: str) -> Rational:
    if isinstance(value, float) and not np.isfinite(value):
        raise PreconditionError("from_arrays", f"{what} is {value}, not a finite number")
    try:
        return to_rational(value.item() if hasattr(value, "item") else value)
    except (RationalParseError, TypeError, ValueError) as error:
        raise PreconditionError("from_arrays", f"{what}: {error}") from None


def _rows(arrays: Mapping[str, Any], key: str, width: int | None) -> list[list[Any]]:
    if key not in arrays:
        return []
    array = np.asarray(arrays[key], dtype=object if np.asarray(arrays[key]).dtype == object
                       else None)
    if array.ndim == 1 and width is None:
        return [[value] for value in array.tolist()]
    if array.size == 0:
        return []
    if array.ndim != 2 or (width is not None and array.shape[1] != width):
        raise PreconditionError("from_arrays", f"{key!r} has shape {array.shape}; expected "
                                f"n x {width if width is not None else 'k'}")
    return [list(row) for row in array]


def _ids(arrays: Mapping[str, Any], key: str, width: int, count: int) -> list[list[int]]:
    rows = _rows(arrays, key, width)
    found = []
    for number, row in enumerate(rows):
        ids = [int(v) for v in row]
        if any(not 0 <= v < count for v in ids):
            raise PreconditionError("from_arrays", f"{key} row {number} {ids} names a vertex "
                                    f"outside 0..{count - 1}")
        found.append(ids)
    return found


def from_arrays(arrays: Mapping[str, Any]) -> Mesh2 | PSLG | Mesh3:
    """The value of ``arrays``: a :class:`Mesh3` when they hold ``tetrahedra``, a
    :class:`Mesh2` when they hold ``triangles``, else a :class:`PSLG`.  Checked as a file
    is (duplicate vertices, degenerate or overlapping triangles, …; a triangle given
    clockwise is turned and said in ``notes`` of the mesh reader); every problem a
    :class:`PreconditionError` or a :class:`~geomexact.errors.FormatError` naming
    ``arrays``."""
    if "vertices" not in arrays:
        raise PreconditionError("from_arrays", "the arrays have no 'vertices'")
    raw = _rows(arrays, "vertices", None)
    dimension = len(raw[0]) if raw else 2
    if "tetrahedra" in arrays:
        points3 = [point3(*(_rational(c, f"vertex {i}") for c in row[:3]))
                   for i, row in enumerate(raw)]
        tets = _ids(arrays, "tetrahedra", 4, len(points3))
        return mesh3_from_tetrahedra(points3, tets, orient=True)
    if dimension != 2:
        raise PreconditionError("from_arrays", f"2D vertices are n x 2, not n x {dimension}")
    points = [point2(_rational(row[0], f"vertex {i}"), _rational(row[1], f"vertex {i}"))
              for i, row in enumerate(raw)]
    markers_rows = _rows(arrays, "vertex_markers", None)
    markers = [int(row[0]) for row in markers_rows] if markers_rows else None
    attribute_rows = _rows(arrays, "vertex_attributes", None)
    vertex_attributes = ([tuple(_rational(v, f"vertex attribute {i}") for v in row)
                          for i, row in enumerate(attribute_rows)] if attribute_rows else None)
    segment_ids = _ids(arrays, "segments", 2, len(points))
    segment_marker_rows = _rows(arrays, "segment_markers", None)
    segments = [(u, v, int(segment_marker_rows[i][0]) if segment_marker_rows else 1)
                for i, (u, v) in enumerate(segment_ids)]
    if "triangles" not in arrays:
        holes = [point2(_rational(r[0], "hole"), _rational(r[1], "hole"))
                 for r in _rows(arrays, "holes", 2)]
        regions = [RegionSeed(point2(_rational(r[0], "region"), _rational(r[1], "region")),
                              _rational(r[2], "region attribute"),
                              None if r[3] is None or (isinstance(r[3], float)
                                                       and np.isnan(r[3]))
                              else _rational(r[3], "region area"))
                   for r in _rows(arrays, "regions", 4)]
        return PSLG(vertices=points, segments=segments, holes=holes, regions=regions,
                    vertex_markers=tuple(markers or ()),
                    vertex_attributes=tuple(vertex_attributes or ()))
    triangles = [tuple(t) for t in _ids(arrays, "triangles", 3, len(points))]
    triangle_attribute_rows = _rows(arrays, "triangle_attributes", None)
    table = TriangleTable(
        path=SOURCE, triangles=triangles, lines=[None] * len(triangles),  # type: ignore[arg-type]
        attributes=[tuple(_rational(v, f"triangle attribute {i}") for v in row)
                    for i, row in enumerate(triangle_attribute_rows)]
        if triangle_attribute_rows else None)
    notes: list[str] = []
    return build_mesh(points, [None] * len(points), table, point_path=SOURCE, notes=notes,
                      vertex_markers=markers, vertex_attributes=vertex_attributes,
                      segments=segments, segment_lines=[None] * len(segments),
                      segment_path=SOURCE)


def triangulate_arrays(arrays: Mapping[str, Any], *, min_angle: Any = None,
                       max_area: Any = None, numbers: Numbers = "nearest"
                       ) -> dict[str, Any]:
    """The constrained Delaunay triangulation of the PSLG in ``arrays`` (``vertices``,
    ``segments``, ``holes``, ``regions``), refined by Lepp-centroid until no angle is
    below ``min_angle`` and no triangle is larger than ``max_area`` (either, both or
    neither: Triangle's ``-pq30a0.01``), as arrays (:func:`to_arrays`; doubles rounded
    to the nearest by default, as the ``triangle`` package gives them)."""
    from geomexact.mesh2d.delaunay.triangulation import triangulate
    from geomexact.mesh2d.refinement.api import refine
    from geomexact.mesh2d.refinement.criteria import AnyOf, MaxArea, MinAngle

    value = from_arrays({key: arrays[key] for key in arrays if key != "triangles"})
    if not isinstance(value, PSLG):  # pragma: no cover - no triangles: a PSLG
        raise PreconditionError("triangulate_arrays", "the arrays are not a PSLG")
    mesh = triangulate(value).mesh
    members: list[Any] = []
    if min_angle is not None:
        members.append(MinAngle(to_rational(min_angle)))
    if max_area is not None:
        members.append(MaxArea(to_rational(max_area)))
    if members:
        criterion = members[0] if len(members) == 1 else AnyOf(tuple(members))
        mesh = refine(mesh, criterion, method="centroid" if min_angle is not None
                      else "bisection").mesh
    return to_arrays(mesh, numbers=numbers)


