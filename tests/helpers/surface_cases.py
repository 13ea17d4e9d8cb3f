"""Small closed surfaces (tetrahedron, cube, a genus-1 polyhedral torus) with dyadic
coordinates (exact as doubles too), and writers of them in every surface format the
readers take, for the reader and check tests."""

from __future__ import annotations

import struct
from fractions import Fraction
from pathlib import Path

from geomexact.kernel.numbers import format_decimal, mpq
from geomexact.mesh3d.surface.value import TriangleSurface, triangle_surface


def tetrahedron() -> TriangleSurface:
    """The unit corner tetrahedron, outward."""
    points = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    return triangle_surface(points, [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)], "tetra")


def cube(low: Fraction = Fraction(0), size: Fraction = Fraction(1)) -> TriangleSurface:
    """The cube [low, low + size]^3 in 12 outward triangles."""
    corners = [(low + size * (k & 1), low + size * (k >> 1 & 1), low + size * (k >> 2 & 1))
               for k in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2),
             (1, 3, 7, 5)]
    triangles = [t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))]
    return triangle_surface(corners, triangles, "cube")


def torus() -> TriangleSurface:
    """A closed genus-1 surface: 4 square cross-sections at the corners of a square,
    joined by 16 quads (32 triangles), outward."""
    centres = [(2, 2), (-2, 2), (-2, -2), (2, -2)]
    loop = [(-Fraction(1, 2), -Fraction(1, 2)), (Fraction(1, 2), -Fraction(1, 2)),
            (Fraction(1, 2), Fraction(1, 2)), (-Fraction(1, 2), Fraction(1, 2))]
    points = [(cx + s * cx / 2, cy + s * cy / 2, t) for cx, cy in centres for s, t in loop]
    triangles = []
    for i in range(4):
        for j in range(4):
            a, b = 4 * i + j, 4 * ((i + 1) % 4) + j
            c, d = 4 * ((i + 1) % 4) + (j + 1) % 4, 4 * i + (j + 1) % 4
            triangles += [(a, b, c), (a, c, d)]
    surface = triangle_surface(points, triangles, "torus")
    return surface.reversed() if surface.enclosed_volume() < 0 else surface


def octahedron(radius: object = mpq(7, 10), centre: object = mpq(1, 2)) -> TriangleSurface:
    """The octahedron |x - c|_1 = r, outward."""
    c, r = mpq(centre), mpq(radius)  # type: ignore[arg-type]
    points = [(c + r, c, c), (c - r, c, c), (c, c + r, c), (c, c - r, c), (c, c, c + r),
              (c, c, c - r)]
    triangles = []
    for x in (0, 1):
        for y in (2, 3):
            for z in (4, 5):
                triangle = [x, y, z]
                if (x == 1) ^ (y == 3) ^ (z == 5):
                    triangle = [x, z, y]
                triangles.append(triangle)
    return triangle_surface(points, triangles, "octahedron")


def notched_box() -> TriangleSurface:
    """A non-convex closed surface: the box [0,1]^2 x [0,1/2] with the notch
    [3/10,7/10] x [3/10,1] x [0,1/2] taken out (a U seen from above), moved by 1/10,
    outward (decimal coordinates: every surface format writes it exactly)."""
    outline = [(0, 0), (1, 0), (1, 1), (mpq(7, 10), 1), (mpq(7, 10), mpq(3, 10)),
               (mpq(3, 10), mpq(3, 10)), (mpq(3, 10), 1), (0, 1)]
    n = len(outline)
    points = [(x + mpq(1, 10), y + mpq(1, 10), mpq(1, 10)) for x, y in outline] + [
        (x + mpq(1, 10), y + mpq(1, 10), mpq(3, 5)) for x, y in outline]
    triangles = []
    for i in range(n):  # the sides, outward
        j = (i + 1) % n
        triangles += [(i, j, n + j), (i, n + j, n + i)]
    # bottom (facing -z) and top: the U as three convex pieces
    pieces = [(0, 1, 4, 5), (1, 2, 3, 4), (0, 5, 6, 7)]
    for a, b, c, d in pieces:
        triangles += [(a, c, b), (a, d, c)]
        triangles += [(n + a, n + b, n + c), (n + a, n + c, n + d)]
    return triangle_surface(points, triangles, "notched box")


CASES = {"tetrahedron": tetrahedron, "cube": cube, "torus": torus}


def _text(value: object) -> str:
    return format_decimal(value)  # type: ignore[arg-type]


def write_obj(path: Path, surface: TriangleSurface) -> Path:
    rows = ["# written by the tests", "o shape"]
    rows += [f"v {_text(p.x)} {_text(p.y)} {_text(p.z)}" for p in surface.points]
    rows += ["vn 0 0 1", "vt 0 0", "s off", "usemtl none"]
    rows += [f"f {a + 1}/1/1 {b + 1}//1 {c + 1}" for a, b, c in surface.triangles.tolist()]
    path.write_text("\n".join(rows) + "\n")
    return path


def write_off(path: Path, surface: TriangleSurface) -> Path:
    rows = ["OFF", f"{surface.vertex_count} {surface.triangle_count} 0"]
    rows += [f"{_text(p.x)} {_text(p.y)} {_text(p.z)}" for p in surface.points]
    rows += [f"3 {a} {b} {c}" for a, b, c in surface.triangles.tolist()]
    path.write_text("\n".join(rows) + "\n")
    return path


def write_ascii_stl(path: Path, surface: TriangleSurface) -> Path:
    rows = ["solid shape"]
    for index in range(surface.triangle_count):
        rows += ["facet normal 0 0 0", "outer loop"]
        rows += [f"vertex {_text(p.x)} {_text(p.y)} {_text(p.z)}"
                 for p in surface.triangle(index)]
        rows += ["endloop", "endfacet"]
    rows.append("endsolid shape")
    path.write_text("\n".join(rows) + "\n")
    return path


def write_binary_stl(path: Path, surface: TriangleSurface) -> Path:
    data = bytearray(b"binary stl".ljust(80, b" "))
    data += struct.pack("<I", surface.triangle_count)
    for index in range(surface.triangle_count):
        corners = [float(c) for p in surface.triangle(index) for c in p[:3]]
        data += struct.pack("<12fH", 0.0, 0.0, 0.0, *corners, 0)
    path.write_bytes(bytes(data))
    return path


def write_ascii_ply(path: Path, surface: TriangleSurface) -> Path:
    rows = ["ply", "format ascii 1.0", "comment tests",
            f"element vertex {surface.vertex_count}", "property float x",
            "property float y", "property float z", "property uchar red",
            f"element face {surface.triangle_count}",
            "property list uchar int vertex_indices", "end_header"]
    rows += [f"{_text(p.x)} {_text(p.y)} {_text(p.z)} 7" for p in surface.points]
    rows += [f"3 {a} {b} {c}" for a, b, c in surface.triangles.tolist()]
    path.write_text("\n".join(rows) + "\n")
    return path


def write_binary_ply(path: Path, surface: TriangleSurface, order: str = "<",
                     polygons: list[list[int]] | None = None) -> Path:
    """Binary PLY (``order`` '<' little or '>' big endian) of the surface's points and
    its triangles, or of the given ``polygons`` (any sizes)."""
    name = "binary_little_endian" if order == "<" else "binary_big_endian"
    faces = polygons if polygons is not None else surface.triangles.tolist()
    header = ("ply\n" f"format {name} 1.0\n" f"element vertex {surface.vertex_count}\n"
              "property double x\nproperty double y\nproperty double z\n"
              f"element face {len(faces)}\n"
              "property list uchar int vertex_indices\nend_header\n")
    data = bytearray(header.encode("ascii"))
    for p in surface.points:
        data += struct.pack(order + "3d", float(p.x), float(p.y), float(p.z))
    for face in faces:
        data += struct.pack(order + "B" + "i" * len(face), len(face), *face)
    path.write_bytes(bytes(data))
    return path


WRITERS = {
    "surface.obj": write_obj,
    "surface.off": write_off,
    "ascii.stl": write_ascii_stl,
    "binary.stl": write_binary_stl,
    "ascii.ply": write_ascii_ply,
    "binary.ply": write_binary_ply,
}
"""File name -> writer: every format and encoding :func:`read_surface` reads."""


def geometric_triangles(surface: TriangleSurface) -> list[tuple[tuple[Fraction, ...], ...]]:
    """The triangles as point triples (each rotated to start at its least point), sorted:
    equal for two surfaces that differ only in vertex numbering."""
    result = []
    for index in range(surface.triangle_count):
        corners = [tuple(Fraction(int(c.numerator), int(c.denominator)) for c in p[:3])
                   for p in surface.triangle(index)]
        start = corners.index(min(corners))
        result.append(tuple(corners[start:] + corners[:start]))
    return sorted(result)
