"""Today's writers before the bulk ones (issue 15, item 2), kept as the reference the
bulk writers must match byte for byte: one number at a time through the uncached
number text, one line at a time through Python formatting."""

from __future__ import annotations

from collections.abc import Sequence

from geomexact.io.registry import (
    NumberStyle,
    exact_decimal_text,
    expected_neighbours,
    mpz_text,
    nearest_double_text,
    uniform_attributes,
)
from geomexact.kernel.numbers import Rational
from geomexact.kernel.points import Point2
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG, RegionSeed
from geomexact.mesh2d.snapshot import Attributes, Mesh2
from geomexact.mesh3d.snapshot import Mesh3

_EXACT_INTEGER_LIMIT = 1 << 53


class LegacyNumberText:
    """The number text of one write before the bulk writers: no cache, no fast path."""

    def __init__(self, style: NumberStyle) -> None:
        self.style = style
        self.rounded = 0

    def __call__(self, value: Rational) -> str:
        if self.style == "float":
            if value.denominator == 1 and abs(value.numerator) <= _EXACT_INTEGER_LIMIT:
                return mpz_text(value.numerator)
        else:
            text = exact_decimal_text(value)
            if text is not None:
                return text
            if self.style == "exact":
                return f"{mpz_text(value.numerator)}/{mpz_text(value.denominator)}"
        text, exact = nearest_double_text(value)
        if not exact:
            self.rounded += 1
        return text


def off_text(value: Mesh2 | PolygonMesh, number: LegacyNumberText) -> str:
    if isinstance(value, Mesh2):
        points = [value.vertices[index] for index in range(value.vertex_count)]
        faces: list[tuple[int, ...]] = list(value.triangles())
    else:
        points = list(value.vertices)
        faces = list(value.polygons)
    out = ["OFF", f"{len(points)} {len(faces)} 0"]
    out.extend(f"{number(point.x)} {number(point.y)} 0" for point in points)
    out.extend(f"{len(face)} {' '.join(map(str, face))}" for face in faces)
    return "\n".join(out) + "\n"


def node_text(
    points: Sequence[Point2],
    markers: Sequence[int] | None,
    attributes: Sequence[Attributes | None],
    number: LegacyNumberText,
) -> str:
    count, rows = uniform_attributes(attributes, "vertex")
    out = [f"{len(points)} 2 {count} {1 if markers is not None else 0}"]
    for index, point in enumerate(points):
        fields = [str(index), number(point.x), number(point.y)]
        fields.extend(number(value) for value in rows[index])
        if markers is not None:
            fields.append(str(markers[index]))
        out.append(" ".join(fields))
    return "\n".join(out) + "\n"


def pslg_node_text(pslg: PSLG, number: LegacyNumberText) -> str:
    attributes: Sequence[Attributes | None] = (
        pslg.vertex_attributes if pslg.vertex_attributes else [None] * len(pslg.vertices)
    )
    markers = pslg.vertex_markers if pslg.vertex_markers else None
    return node_text(pslg.vertices, markers, attributes, number)


def poly_sections_text(
    segments: Sequence[tuple[int, int, int]],
    holes: Sequence[Point2],
    regions: Sequence[RegionSeed],
    number: LegacyNumberText,
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


def poly_text(pslg: PSLG, number: LegacyNumberText) -> str:
    return pslg_node_text(pslg, number) + "\n".join(
        poly_sections_text(pslg.segments, pslg.holes, pslg.regions, number)
    ) + "\n"


def triangle_texts(mesh: Mesh2, number: LegacyNumberText) -> dict[str, str]:
    """The texts of ``.node``, ``.ele``, ``.neigh`` (and ``.poly``) by extension."""
    points = [mesh.vertices[index] for index in range(mesh.vertex_count)]
    markers = [mesh.vertex_markers.get(index, 0) for index in range(mesh.vertex_count)]
    vertex_attributes = [mesh.vertex_attributes.get(index) for index in range(len(points))]
    texts = {".node": node_text(points, markers, vertex_attributes, number)}
    triangles = mesh.triangles()
    count, rows = uniform_attributes(
        [mesh.triangle_attributes.get(triangle) for triangle in triangles], "triangle"
    )
    ele = [f"{len(triangles)} 3 {count}"]
    for index, (a, b, c) in enumerate(triangles):
        ele.append(" ".join([str(index), str(a), str(b), str(c), *map(number, rows[index])]))
    neigh = [f"{len(triangles)} 3"]
    neigh.extend(
        f"{index} {n0} {n1} {n2}"
        for index, (n0, n1, n2) in enumerate(expected_neighbours(triangles))
    )
    texts[".ele"] = "\n".join(ele) + "\n"
    texts[".neigh"] = "\n".join(neigh) + "\n"
    segments = mesh.segment_list()
    if segments:
        poly = ["0 2 0 1", *poly_sections_text(segments, (), (), number)]
        texts[".poly"] = "\n".join(poly) + "\n"
    return texts


def tetgen_texts(mesh: Mesh3, number: LegacyNumberText) -> dict[str, str]:
    node = [f"{mesh.vertex_count} 3 0 0"]
    for index in range(mesh.vertex_count):
        p = mesh.vertices[index]
        node.append(f"{index} {number(p.x)} {number(p.y)} {number(p.z)}")
    tetrahedra = mesh.tetrahedra()
    ele = [f"{len(tetrahedra)} 4 0"]
    ele.extend(f"{i} {a} {b} {c} {d}" for i, (a, b, c, d) in enumerate(tetrahedra))
    faces = mesh.boundary_faces()
    face = [f"{len(faces)} 1"]
    face.extend(f"{i} {a} {c} {b} 1" for i, (a, b, c) in enumerate(faces))
    return {
        extension: "\n".join(rows) + "\n"
        for extension, rows in ((".node", node), (".ele", ele), (".face", face))
    }
