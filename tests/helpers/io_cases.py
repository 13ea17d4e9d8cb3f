"""Helpers shared by the ``test_io_*`` files (no tests here): random valid meshes and
PSLGs, geometric comparisons, and writing small input files."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

from hypothesis import strategies as st

from geomexact import Mesh2, mesh_from_triangles, mpq, point2
from geomexact.kernel.numbers import Rational, to_float
from geomexact.mesh2d.pslg import PSLG, RegionSeed

DATA = Path(__file__).resolve().parents[1] / "data"
BAD = DATA / "bad"

# jitter below 1/8 keeps both diagonals of every grid cell valid (both triangles of either
# split are counter-clockwise), so any split of the grid is a valid mesh
_JITTER = Fraction(1, 9)


def _rational(value: Fraction) -> Rational:
    return mpq(value.numerator, value.denominator)


def jitters(*, dyadic: bool) -> st.SearchStrategy[Rational]:
    """Small offsets: dyadic (exact doubles) or with any small denominator."""
    if dyadic:
        return st.integers(-7, 7).map(lambda k: mpq(k, 64))
    return st.fractions(-_JITTER, _JITTER, max_denominator=60).map(_rational)


@st.composite
def grid_meshes(
    draw: st.DrawFn,
    *,
    dyadic: bool = False,
    extras: bool = True,
    max_side: int = 5,
) -> Mesh2:
    """A jittered grid of cols x rows points, each cell split along a random diagonal,
    vertices numbered in a random order; with ``extras`` random vertex markers, vertex
    and triangle attributes, and boundary segments with markers."""
    cols = draw(st.integers(2, max_side))
    rows = draw(st.integers(2, max_side))
    # a negative scale turns the grid by 180 degrees: orientation is kept
    scale = draw(st.sampled_from([mpq(1), mpq(1, 8), mpq(1000)] if dyadic else
                                 [mpq(1), mpq(1, 10), mpq(1000), mpq(-3, 7)]))
    jitter = jitters(dyadic=dyadic)
    grid = []
    for j in range(rows):
        for i in range(cols):
            x = (mpq(i) + draw(jitter)) * scale
            y = (mpq(j) + draw(jitter)) * scale
            grid.append((x, y))
    count = len(grid)
    order = draw(st.permutations(range(count)))  # grid index -> vertex id
    points = [point2(0, 0)] * count
    for index, (x, y) in enumerate(grid):
        points[order[index]] = point2(x, y)
    triangles = []
    for j in range(rows - 1):
        for i in range(cols - 1):
            a, b = j * cols + i, j * cols + i + 1
            c, d = b + cols, a + cols
            split_ac = draw(st.booleans())
            cells = [(a, b, c), (a, c, d)] if split_ac else [(a, b, d), (b, c, d)]
            triangles.extend(tuple(order[v] for v in cell) for cell in cells)
    markers = attributes = triangle_attributes = None
    segments: list[tuple[int, int, int]] = []
    if extras:
        if draw(st.booleans()):
            markers = draw(st.lists(st.integers(0, 3), min_size=count, max_size=count))
        width = draw(st.integers(0, 2))
        if width:
            values = st.tuples(*[jitter] * width)
            attributes = draw(st.lists(values, min_size=count, max_size=count))
        if draw(st.booleans()):
            triangle_attributes = draw(
                st.lists(st.tuples(jitter), min_size=len(triangles), max_size=len(triangles))
            )
        boundary = [(j * cols + i, j * cols + i + 1) for j in (0, rows - 1)
                    for i in range(cols - 1)]
        chosen = draw(st.lists(st.sampled_from(boundary), unique=True, max_size=4))
        segments = [(order[u], order[v], draw(st.integers(0, 2))) for u, v in chosen]
    return mesh_from_triangles(
        points,
        triangles,
        segments,
        vertex_markers=markers,
        vertex_attributes=attributes,
        triangle_attributes=triangle_attributes,
    )


@st.composite
def pslgs(draw: st.DrawFn, *, dyadic: bool = False) -> PSLG:
    """A random PSLG: distinct points, segments between them, holes, regions, optional
    markers and attributes (not geometrically meaningful: the formats do not care)."""
    coordinate = jitters(dyadic=dyadic).map(lambda value: value * 100)
    raw = draw(
        st.lists(st.tuples(coordinate, coordinate), min_size=2, max_size=12, unique=True)
    )
    vertices = [point2(x, y) for x, y in raw]
    count = len(vertices)
    pairs = st.tuples(st.integers(0, count - 1), st.integers(0, count - 1)).filter(
        lambda pair: pair[0] != pair[1]
    )
    segments = [(u, v, draw(st.integers(0, 5))) for u, v in draw(st.lists(pairs, max_size=8))]
    holes = [point2(x, y) for x, y in draw(st.lists(st.tuples(coordinate, coordinate),
                                                      max_size=3))]
    regions = [
        RegionSeed(point2(x, y), a, area)
        for x, y, a, area in draw(
            st.lists(
                st.tuples(coordinate, coordinate, coordinate,
                          st.none() | coordinate.filter(lambda v: v > 0)),
                max_size=2,
            )
        )
    ]
    markers = draw(st.none() | st.lists(st.integers(0, 4), min_size=count, max_size=count))
    width = draw(st.integers(0, 2))
    attributes = (
        draw(st.lists(st.tuples(*[coordinate] * width), min_size=count, max_size=count))
        if width
        else []
    )
    return PSLG(
        vertices=vertices,
        segments=segments,
        holes=holes,
        regions=regions,
        vertex_markers=markers or (),
        vertex_attributes=attributes,
    )


def geometric_triangles(mesh: Mesh2) -> set[frozenset[tuple[Rational, Rational]]]:
    """The triangles of ``mesh`` as sets of exact corner coordinates (id-free)."""
    result = set()
    for triangle in mesh.triangles():
        result.add(frozenset((mesh.point(v).x, mesh.point(v).y) for v in triangle))
    return result


def same_doubles(a: Mesh2, b: Mesh2) -> bool:
    """True when both meshes have the same triangles and vertex ids, and every
    coordinate of ``b`` rounds to the same double as in ``a``."""
    if a.triangles() != b.triangles() or a.vertex_count != b.vertex_count:
        return False
    return all(
        to_float(a.point(v).x) == to_float(b.point(v).x)
        and to_float(a.point(v).y) == to_float(b.point(v).y)
        for v in range(a.vertex_count)
    )


def plain(mesh: Mesh2) -> Mesh2:
    """``mesh`` without markers, attributes and segments (what OFF or meshio keep)."""
    points = [mesh.point(v) for v in range(mesh.vertex_count)]
    return mesh_from_triangles(points, mesh.triangles())


def write(directory: Path, name: str, text: str) -> Path:
    """Write ``text`` (dedented of a leading newline) to ``directory/name``."""
    path = directory / name
    path.write_text(text.lstrip("\n"), encoding="utf-8")
    return path
