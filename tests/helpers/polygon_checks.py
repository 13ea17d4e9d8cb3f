"""Shared helpers of the Polylla and convex-decomposition tests: mesh strategies with many
exact ties, constraints and holes, an independent recomputation of terminal-edge regions
from :func:`geomexact.mesh2d.longest_edge.lepp`, and the invariants every result must satisfy."""

from __future__ import annotations

from collections.abc import Sequence

from hypothesis import assume
from hypothesis import strategies as st

from geomexact import Mesh2, mesh_from_triangles, mpq, point2, total_area
from geomexact.errors import PreconditionError
from geomexact.kernel.points import Point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.longest_edge import lepp, longest_edge
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.polygonal.polylla_meshing import PolyllaRun
from geomexact.mesh2d.snapshot import Edge, Triangle, canonical_triangle
from geomexact.strategies import coordinates, pslgs, triangulations


def _delaunay_of(points: list[tuple[object, object]]) -> Mesh2:
    unique = list(dict.fromkeys(point2(x, y) for x, y in points))
    try:
        return triangulate(unique).mesh
    except PreconditionError:  # collinear or too few points
        assume(False)
        raise  # pragma: no cover


@st.composite
def lattice_meshes(draw: st.DrawFn, max_points: int = 30, side: int = 6) -> Mesh2:
    """Delaunay meshes of lattice points: right isosceles triangles and cocircular
    squares everywhere, so longest edges are often exactly tied."""
    points = draw(st.lists(st.tuples(st.integers(0, side), st.integers(0, side)),
                           min_size=3, max_size=max_points, unique=True))
    return _delaunay_of(list(points))


@st.composite
def scattered_meshes(draw: st.DrawFn, max_points: int = 25) -> Mesh2:
    """Delaunay meshes of lattice points scaled by a rational of any magnitude (huge,
    tiny, subnormal, beyond the double range), to stress the float filters.  The lattice
    is triangulated first and then scaled (``triangulate`` itself is not the subject)."""
    scale = draw(coordinates().filter(lambda q: q != 0))
    raw = draw(st.lists(st.tuples(st.integers(-50, 50), st.integers(-50, 50)),
                        min_size=3, max_size=max_points, unique=True))
    lattice = _delaunay_of(list(raw))
    points = [lattice.point(v) for v in range(lattice.vertex_count)]
    scaled = [(p.x * scale, p.y * scale) for p in points]
    return mesh_from_triangles(scaled, lattice.triangles())  # (x, y) -> s (x, y) turns


@st.composite
def constrained_meshes(draw: st.DrawFn) -> Mesh2:
    """Constrained Delaunay triangulations of PSLGs: non-convex domains, holes,
    constrained segments."""
    pslg = draw(pslgs(max_boundary=10, max_points=12))
    try:
        return triangulate(pslg).mesh
    except PreconditionError:
        assume(False)
        raise  # pragma: no cover


def any_meshes() -> st.SearchStrategy[Mesh2]:
    """Every kind of mesh above, plus the foundation's ``triangulations()``."""
    return st.one_of(triangulations(max_steps=25), lattice_meshes(), constrained_meshes(),
                     scattered_meshes())


def undirected(edge: Edge) -> Edge:
    u, v = edge
    return (u, v) if u < v else (v, u)


def lepp_regions(mesh: Mesh2) -> list[frozenset[Triangle]]:
    """Terminal-edge regions recomputed from scratch with :func:`geomexact.mesh2d.longest_edge.lepp`:
    triangles grouped by where their Lepp ends.  An interior terminal edge that is the
    longest edge of both its triangles gathers both sides; any other terminal edge gathers
    only the side the path arrived from."""
    groups: dict[object, set[Triangle]] = {}
    for triangle in mesh.triangles():
        path = lepp(mesh, triangle)
        edge = undirected(path.terminal_edge)
        key: object = (edge, path.path[-1])
        if path.kind == "interior":
            other = path.terminal_triangles[1]
            if undirected(longest_edge(mesh, other)) == edge:
                key = edge
        groups.setdefault(key, set()).add(triangle)
    return sorted((frozenset(group) for group in groups.values()), key=min)


def polygon_edges(polygon: Sequence[int]) -> list[Edge]:
    return [(polygon[i - 1], polygon[i]) for i in range(len(polygon))]


def triangle_boundary(triangles: Sequence[Triangle]) -> set[Edge]:
    halfedges = {(t[i], t[(i + 1) % 3]) for t in triangles for i in range(3)}
    return {(u, v) for u, v in halfedges if (v, u) not in halfedges}


def assert_partition(mesh: Mesh2, polygons: PolygonMesh, *, simple: bool = True) -> None:
    """The polygons partition the triangulation exactly (checked here independently of
    ``validate``, and by ``validate``)."""
    assert polygons.sources and len(polygons.sources) == len(polygons.polygons)
    listed = [canonical_triangle(*t) for source in polygons.sources for t in source]
    assert sorted(listed) == mesh.triangles()  # every triangle in exactly one polygon
    area = sum((polygons.area(i) for i in range(len(polygons.polygons))), mpq(0))
    assert area == total_area(mesh)  # union = domain, exactly
    for index, (polygon, source) in enumerate(zip(polygons.polygons, polygons.sources,
                                                  strict=True)):
        assert polygons.area(index) > 0
        cycle = set(polygon_edges(polygon))
        if simple:
            assert triangle_boundary(source) == cycle
        else:  # a barrier edge is walked both ways; it is inside the triangles' union
            assert triangle_boundary(source) == {(u, v) for u, v in cycle
                                                 if (v, u) not in cycle}
        if simple:
            assert len(set(polygon)) == len(polygon), polygon
            assert polygon[0] == min(polygon)
    if simple:
        assert polygons.validate(mesh) == []
    assert list(polygons.polygons) == sorted(polygons.polygons)
    for point, index in zip(polygons.vertices, range(mesh.vertex_count), strict=True):
        assert point == mesh.point(index)


def assert_sound_run(mesh: Mesh2, run: PolyllaRun) -> None:
    """Everything a repaired Polylla run promises."""
    assert_partition(mesh, run.mesh)
    assert len(run.mesh.polygons) == run.regions + len(run.repair_edges)
    edges = {undirected(e) for polygon in run.mesh.polygons for e in polygon_edges(polygon)}
    for u, v in mesh.segments:  # constrained edges are frontier edges
        assert (u, v) in edges
    for u, v in mesh.boundary_edges():
        assert undirected((u, v)) in edges
    for edge in run.repair_edges:
        assert mesh.is_edge(*edge)
    if len(mesh.triangle_attributes):
        for u, v in mesh.edges():
            w, x = mesh.apex(u, v), mesh.apex(v, u)
            if w is not None and x is not None:
                first = mesh.triangle_attributes.get(canonical_triangle(u, v, w))
                second = mesh.triangle_attributes.get(canonical_triangle(v, u, x))
                if first != second:
                    assert (u, v) in edges


def is_convex(points: Sequence[Point2], polygon: Sequence[int]) -> bool:
    """Independent exact convexity test: no clockwise corner, no repeated vertex."""
    count = len(polygon)
    return len(set(polygon)) == count and all(
        orient2d(points[polygon[i - 1]], points[polygon[i]],
                 points[polygon[(i + 1) % count]]) != Orientation.CLOCKWISE
        for i in range(count)
    )
