"""Delaunay and constrained Delaunay triangulation: properties (hypothesis), exact unit
cases, degenerate inputs and errors.  Real data: ``test_delaunay_data.py``; determinism
across processes: ``test_delaunay_determinism.py``; the independent checks:
``tests/helpers/delaunay_checks.py``."""

from __future__ import annotations

import itertools
import random

import pytest
from helpers.delaunay_checks import (
    COLLINEAR,
    assert_sound,
    boundary_loops,
    components,
    convex_hull,
    coordinate_triangles,
    differ_only_where_cocircular,
    euler_characteristic,
    globally_non_empty,
    hull_boundary_points,
    inside,
    locally_non_delaunay,
    mesh_area,
    on_closed_segment,
    point_set_triangle_count,
    polygon_area,
    segment_is_union_of_constrained_edges,
    triangles_containing,
    used_vertices,
)
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from geomexact import (
    PSLG,
    CircleLocation,
    Mesh2,
    PreconditionError,
    incircle,
    mesh_from_triangles,
    mpq,
    orient2d,
    point2,
    replay,
    validate,
)
from geomexact.kernel.numbers import to_rational
from geomexact.kernel.points import Point2
from geomexact.mesh2d.delaunay.triangulation import (
    SegmentError,
    insertion_order,
    is_delaunay,
    make_delaunay,
    non_delaunay_edges,
    triangulate,
    triangulate_points,
)
from geomexact.mesh2d.pslg import RegionSeed
from geomexact.strategies import (
    MAGNITUDES,
    coordinates,
    near_degenerate_points2,
    points2,
    pslgs,
    rationals,
    simple_polygons,
    triangulations,
)

# =======================================================================================
# strategies
# =======================================================================================


def _cocircular(quadruple: tuple[Point2, ...]) -> bool:
    """Four points on one circle (or one line): exact incircle is zero."""
    a, b, c, d = quadruple
    return incircle(a, b, c, d) == CircleLocation.COCIRCULAR


def _not_collinear(points: list[Point2]) -> bool:
    first, second = points[0], next((p for p in points if p != points[0]), points[0])
    return any(orient2d(first, second, p) != COLLINEAR for p in points)


def point_sets(min_size: int = 3, max_size: int = 20) -> st.SearchStrategy[list[Point2]]:
    """Distinct points, not all collinear, with coordinates of one magnitude per example
    (ordinary, decimal, dyadic, huge, tiny, beyond the double range)."""
    return (
        st.sampled_from(MAGNITUDES)
        .flatmap(lambda magnitude: st.lists(
            st.builds(point2, coordinates([magnitude]), coordinates([magnitude])),
            min_size=min_size, max_size=max_size, unique=True))
        .filter(_not_collinear)
    )


def lattice_points(size: int = 6, min_size: int = 3, max_size: int = 25
                   ) -> st.SearchStrategy[list[Point2]]:
    """Distinct points of the integer grid [0, size]²: full of collinear and cocircular
    subsets (Delaunay is not unique there)."""
    return st.lists(
        st.builds(point2, st.integers(0, size), st.integers(0, size)),
        min_size=min_size, max_size=max_size, unique=True,
    ).filter(_not_collinear)


def dyadic_point_sets(max_size: int = 30) -> st.SearchStrategy[list[Point2]]:
    """Distinct points with exact double coordinates (k / 2^e), not all collinear."""
    dyadic = st.builds(lambda k, e: mpq(k, 2**e), st.integers(-(2**20), 2**20),
                       st.integers(0, 20))
    return st.lists(st.builds(point2, dyadic, dyadic), min_size=3, max_size=max_size,
                    unique=True).filter(_not_collinear)


def circle_points(count: int, denominator: int = 2) -> list[Point2]:
    """``count`` distinct rational points of the circle of radius 5 centred at (1/3, 2),
    all exactly cocircular (stereographic parameters k / denominator, spread around)."""
    points = []
    for k in range(count):
        s = mpq(k - count // 2, denominator)
        w = 1 + s * s
        points.append(point2(mpq(1, 3) + 5 * (1 - s * s) / w, 2 + 5 * 2 * s / w))
    return points


def grid(columns: int, rows: int, step: object = 1) -> list[Point2]:
    step_q = to_rational(step)
    return [point2(i * step_q, j * step_q) for j in range(rows) for i in range(columns)]


def square(x0: int, y0: int, side: int) -> list[Point2]:
    return [point2(x0, y0), point2(x0 + side, y0), point2(x0 + side, y0 + side),
            point2(x0, y0 + side)]


def loop_segments(start: int, count: int, marker: int = 1) -> list[tuple[int, int, int]]:
    return [(start + i, start + (i + 1) % count, marker) for i in range(count)]


def pslg_domain_area(pslg: PSLG) -> object:
    """Area of the polygon with holes of a :func:`geomexact.strategies.pslgs` value: its
    outer loop has marker 1 and its hole loop marker 2 (both counter-clockwise)."""
    twice = mpq(0)
    for u, v, marker in pslg.segments:
        p, q = pslg.vertices[u], pslg.vertices[v]
        cross = p.x * q.y - q.x * p.y
        twice += cross if marker == 1 else -cross
    return twice / 2


# =======================================================================================
# Delaunay triangulation of point sets: properties
# =======================================================================================


@given(point_sets(max_size=16))
def test_point_set_triangulation_has_the_empty_circle_property(points: list[Point2]) -> None:
    """No vertex lies strictly inside the circumcircle of any triangle (exact incircle,
    checked against every vertex), for coordinates of every magnitude."""
    run = triangulate_points(points)
    assert_sound(run)
    assert globally_non_empty(run.mesh) == []
    assert locally_non_delaunay(run.mesh) == []
    assert non_delaunay_edges(run.mesh) == []
    assert is_delaunay(run.mesh)


@st.composite
def near_degenerate_point_sets(draw: st.DrawFn) -> list[Point2]:
    """A nearly (or exactly) cocircular quadruple and a nearly collinear triple (one
    point nudged by 2^-k relative, one ulp or to the next double), similar to each other,
    plus a few points of any magnitude."""
    points: list[Point2] = [*draw(near_degenerate_points2(4)), *draw(near_degenerate_points2(3))]
    points += draw(st.lists(points2(), max_size=4))
    unique = list(dict.fromkeys(points))
    assume(len(unique) >= 3 and _not_collinear(unique))
    return unique


@given(st.one_of(
    near_degenerate_point_sets(),
    st.lists(points2(), min_size=3, max_size=12, unique=True).filter(_not_collinear),
))
@settings(suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
def test_near_degenerate_and_mixed_magnitude_points_are_triangulated_exactly(
    points: list[Point2]
) -> None:
    """Nearly cocircular / collinear configurations and points mixing 1e-400 and 1e400:
    valid, empty circles (exact), 2n - 2 - h triangles, the exact hull area."""
    run = triangulate_points(points)
    assert_sound(run)
    assert globally_non_empty(run.mesh) == []
    assert run.mesh.triangle_count == point_set_triangle_count(points)
    assert mesh_area(run.mesh) == polygon_area(convex_hull(points))


@given(point_sets(max_size=25))
def test_point_set_triangulation_satisfies_euler_formula(points: list[Point2]) -> None:
    """T = 2n - 2 - h (h: points on the hull boundary, collinear ones included),
    V - E + T = 1, every point is a vertex and the boundary has h edges."""
    mesh = triangulate_points(points).mesh
    assert mesh.triangle_count == point_set_triangle_count(points)
    assert euler_characteristic(mesh) == 1
    assert used_vertices(mesh) == set(range(len(points)))
    assert len(mesh.boundary_edges()) == len(hull_boundary_points(points))


@given(point_sets(max_size=25))
def test_point_set_triangulation_covers_the_convex_hull_exactly(points: list[Point2]) -> None:
    """The triangles' total area equals the exact area of the convex hull."""
    mesh = triangulate_points(points).mesh
    assert mesh_area(mesh) == polygon_area(convex_hull(points))
    assert boundary_loops(mesh) == components(mesh) == 1


@given(point_sets(max_size=20))
def test_point_set_triangulation_replays_from_its_trace(points: list[Point2]) -> None:
    """replay(start, trace) reproduces the mesh, digest by digest; start is the isolated
    input vertices."""
    run = triangulate_points(points)
    assert replay(run.start, run.trace) == run.mesh
    assert run.start.vertex_count == len(points) and run.start.triangle_count == 0
    assert [run.mesh.point(i) for i in range(len(points))] == points


@given(st.lists(st.builds(point2, rationals(max_numerator=10**4, max_denominator=50),
                          rationals(max_numerator=10**4, max_denominator=50)),
                min_size=3, max_size=10, unique=True).filter(_not_collinear),
       st.randoms(use_true_random=False))
def test_permuting_the_points_gives_the_same_triangles(
    points: list[Point2], rng: random.Random
) -> None:
    """Without four cocircular points the Delaunay triangulation is unique: any input
    order gives the same triangles (as sets of exact coordinates)."""
    assume(not any(_cocircular(q) for q in itertools.combinations(points, 4)))
    permuted = list(points)
    rng.shuffle(permuted)
    first = triangulate_points(points).mesh
    second = triangulate_points(permuted).mesh
    assert coordinate_triangles(first) == coordinate_triangles(second)


@given(dyadic_point_sets(), st.integers(0, 3))
def test_point_set_triangulation_matches_triangle_except_where_cocircular(
    points: list[Point2], seed: int
) -> None:
    """On exact doubles, Triangle (exact predicates) and geomexact give the same
    triangles, except among cocircular points where the Delaunay triangulation is not
    unique (ours must then still have empty circles)."""
    triangle = pytest.importorskip("triangle")
    numpy = pytest.importorskip("numpy")
    mesh = triangulate_points(points, seed=seed).mesh
    result = triangle.triangulate(
        {"vertices": numpy.array([[p.fx, p.fy] for p in points])}, "Q")
    theirs = {frozenset((points[i].x, points[i].y) for i in t)
              for t in result["triangles"].tolist()}
    ours = coordinate_triangles(mesh)
    assert globally_non_empty(mesh) == []
    if ours != theirs:
        corners = sorted({c for t in ours ^ theirs for c in t})
        assert any(_cocircular(tuple(point2(x, y) for x, y in q))
                   for q in itertools.combinations(corners, 4))
    assert len(ours) == len(theirs)


@pytest.mark.slow
@pytest.mark.parametrize("count", [20_000])
def test_many_random_points_match_triangle_and_replay(count: int) -> None:
    """20 000 random doubles (exact): the same triangles as Triangle, Delaunay by the
    exact local test, T = 2n - 2 - h, and the trace replays."""
    triangle = pytest.importorskip("triangle")
    numpy = pytest.importorskip("numpy")
    rng = random.Random(11)
    doubles = [(rng.random(), rng.random()) for _ in range(count)]
    points = [point2(x, y) for x, y in doubles]
    run = triangulate_points(points)
    result = triangle.triangulate({"vertices": numpy.array(doubles)}, "Q")
    assert {tuple(sorted(t)) for t in result["triangles"].tolist()} == {
        tuple(sorted(t)) for t in run.mesh.triangles()}
    assert locally_non_delaunay(run.mesh) == []
    assert run.mesh.triangle_count == point_set_triangle_count(points)
    assert_sound(run)


@given(point_sets(max_size=15), st.integers(0, 2**32))
def test_seed_changes_nothing_where_delaunay_is_unique(points: list[Point2], seed: int) -> None:
    """Another insertion order (seed) gives the same triangles up to cocircular ties, and
    always a valid Delaunay triangulation."""
    first = triangulate_points(points).mesh
    run = triangulate_points(points, seed=seed)
    assert_sound(run)
    assert globally_non_empty(run.mesh) == []
    assert differ_only_where_cocircular(first, run.mesh)


@given(lattice_points(), st.integers(0, 5))
def test_lattice_points_give_a_valid_deterministic_delaunay_triangulation(
    points: list[Point2], seed: int
) -> None:
    """On grids full of cocircular quadruples the result is valid, Delaunay (no vertex
    strictly inside a circumcircle), has 2n - 2 - h triangles, and the same input and
    seed always give the same mesh and trace."""
    run = triangulate_points(points, seed=seed)
    assert_sound(run)
    assert globally_non_empty(run.mesh) == []
    assert run.mesh.triangle_count == point_set_triangle_count(points)
    again = triangulate_points(list(points), seed=seed)
    assert again.mesh == run.mesh and again.mesh.digest == run.mesh.digest
    assert again.trace == run.trace


@pytest.mark.parametrize(("columns", "rows", "step"),
                         [(2, 2, 1), (3, 3, 1), (4, 5, "1/3"), (7, 7, 1), (10, 3, "0.1")])
@pytest.mark.parametrize("seed", [0, 1, 7])
def test_grid_triangulation_is_delaunay_and_deterministic(
    columns: int, rows: int, step: str | int, seed: int
) -> None:
    """A grid: every cell's four corners are cocircular, so any diagonal is Delaunay; the
    output is valid, Delaunay (non-strict), covers the rectangle, has 2(c-1)(r-1)
    triangles, and repeats exactly."""
    points = grid(columns, rows, step)
    run = triangulate_points(points, seed=seed)
    assert_sound(run)
    assert globally_non_empty(run.mesh) == []
    assert run.mesh.triangle_count == 2 * (columns - 1) * (rows - 1)
    step_q = to_rational(step)
    assert mesh_area(run.mesh) == (columns - 1) * (rows - 1) * step_q * step_q
    again = triangulate_points(points, seed=seed)
    assert again.mesh == run.mesh and again.trace == run.trace


@pytest.mark.parametrize("count", [3, 4, 5, 8, 13, 30])
@pytest.mark.parametrize("centre", [False, True])
@pytest.mark.parametrize("seed", [0, 3])
def test_points_on_a_circle_give_a_valid_deterministic_triangulation(
    count: int, centre: bool, seed: int
) -> None:
    """Exactly cocircular points (all Delaunay triangulations of them are equally valid):
    n - 2 triangles (2n - 2 - h with the centre added), Delaunay, deterministic."""
    points = circle_points(count)
    if centre:
        points.append(point2(mpq(1, 3), 2))
    run = triangulate_points(points, seed=seed)
    assert_sound(run)
    assert globally_non_empty(run.mesh) == []
    assert run.mesh.triangle_count == point_set_triangle_count(points)
    if not centre:
        assert run.mesh.triangle_count == count - 2
    assert mesh_area(run.mesh) == polygon_area(convex_hull(points))
    again = triangulate_points(list(points), seed=seed)
    assert again.mesh == run.mesh and again.trace == run.trace


def test_insertion_order_is_a_deterministic_permutation() -> None:
    """insertion_order is a permutation of the ids, fixed by the points and the seed."""
    points = grid(9, 9)
    order = insertion_order(points, seed=5)
    assert sorted(order) == list(range(len(points)))
    assert insertion_order(points, seed=5) == order
    assert insertion_order(points, seed=6) != order
    assert insertion_order([], seed=0) == []


def reference_insertion_order(points: list[Point2], seed: int) -> list[int]:
    """The definition of ``insertion_order`` (its docstring), written out in plain Python:
    the vectorised implementation must give exactly this order."""
    import math

    order = list(range(len(points)))
    random.Random(seed).shuffle(order)
    if not points:
        return order
    xs = [points[i].fx * 0.5 for i in order]
    ys = [points[i].fy * 0.5 for i in order]
    finite_x = [x for x in xs if math.isfinite(x)] or [0.0]
    finite_y = [y for y in ys if math.isfinite(y)] or [0.0]
    low_x, low_y = min(finite_x), min(finite_y)
    span = max(max(finite_x) - low_x, max(finite_y) - low_y) or 1.0
    rounds: list[list[int]] = []
    end = len(order)
    while end > 0:
        begin = end // 2 if end > 64 else 0
        rounds.append(order[begin:end])
        end = begin
    result: list[int] = []
    for chunk in reversed(rounds):
        cells = max(1, int(math.sqrt(len(chunk) / 2)))
        keyed = []
        for vertex in chunk:
            point = points[vertex]
            x = point.fx * 0.5 if math.isfinite(point.fx) else low_x
            y = point.fy * 0.5 if math.isfinite(point.fy) else low_y
            column = min(cells - 1, int((x - low_x) / span * cells))
            keyed.append((column, (y - low_y) if column % 2 == 0 else (low_y - y), vertex))
        keyed.sort()
        result.extend(vertex for _, _, vertex in keyed)
    return result


@given(st.lists(points2(), max_size=300), st.integers(0, 3))
def test_insertion_order_follows_its_definition(points: list[Point2], seed: int) -> None:
    """Any magnitudes (doubles that overflow to infinity included), repeats, ties."""
    assert insertion_order(points, seed=seed) == reference_insertion_order(points, seed)


def test_insertion_order_follows_its_definition_on_large_sets() -> None:
    rng = random.Random(3)
    points = [point2(rng.random(), rng.random()) for _ in range(5000)] + grid(30, 30)
    assert insertion_order(points, seed=1) == reference_insertion_order(points, 1)


# =======================================================================================
# constrained Delaunay triangulation of PSLGs: properties
# =======================================================================================


@given(pslgs())
def test_pslg_triangulation_covers_exactly_the_polygon_minus_its_holes(pslg: PSLG) -> None:
    """Total area equals the exact area of the outer polygon minus the hole; every hole
    seed lies in no triangle."""
    run = triangulate(pslg)
    assert_sound(run)
    assert mesh_area(run.mesh) == pslg_domain_area(pslg)
    for seed in pslg.holes:
        assert triangles_containing(run.mesh, seed) == []


@given(pslgs())
def test_pslg_triangulation_satisfies_euler_formula(pslg: PSLG) -> None:
    """V - E + T = 1 - holes = 2 (components) - (boundary loops), all vertices used."""
    mesh = triangulate(pslg).mesh
    assert euler_characteristic(mesh) == 1 - len(pslg.holes)
    assert components(mesh) == 1
    assert boundary_loops(mesh) == 1 + len(pslg.holes)
    assert used_vertices(mesh) == set(range(len(pslg.vertices)))


@given(pslgs())
def test_pslg_segments_are_constrained_edges(pslg: PSLG) -> None:
    """Every input segment is a constrained edge with its marker; nothing else is."""
    mesh = triangulate(pslg).mesh
    expected = {(min(u, v), max(u, v)): marker for u, v, marker in pslg.segments}
    assert dict(mesh.segments.items()) == expected


@given(pslgs())
def test_pslg_triangulation_is_delaunay_except_across_segments(pslg: PSLG) -> None:
    """Every unconstrained interior edge is locally Delaunay (exact incircle)."""
    mesh = triangulate(pslg).mesh
    assert locally_non_delaunay(mesh) == []
    assert non_delaunay_edges(mesh) == []


@given(pslgs(), st.randoms(use_true_random=False), st.integers(0, 2**16))
def test_pslg_triangulation_does_not_depend_on_vertex_order_or_seed(
    pslg: PSLG, rng: random.Random, seed: int
) -> None:
    """Renumbering the vertices (segments and holes follow) or changing the seed gives
    the same triangles up to cocircular ties."""
    n = len(pslg.vertices)
    new_id = list(range(n))
    rng.shuffle(new_id)
    vertices = [pslg.vertices[0]] * n
    for old, new in enumerate(new_id):
        vertices[new] = pslg.vertices[old]
    renumbered = PSLG(vertices=vertices, holes=pslg.holes,
                      segments=[(new_id[u], new_id[v], m) for u, v, m in pslg.segments])
    first = triangulate(pslg).mesh
    for run in (triangulate(renumbered), triangulate(pslg, seed=seed)):
        assert_sound(run)
        assert locally_non_delaunay(run.mesh) == []
        assert differ_only_where_cocircular(first, run.mesh)
        assert mesh_area(run.mesh) == mesh_area(first)


@given(pslgs())
def test_triangulate_leaves_its_input_unchanged(pslg: PSLG) -> None:
    """The PSLG value (vertices, segments, holes) is the same before and after."""
    before = (tuple((p.x, p.y) for p in pslg.vertices), pslg.segments,
              tuple((p.x, p.y) for p in pslg.holes), pslg.regions)
    triangulate(pslg, keep_convex_hull=True)
    triangulate(pslg)
    after = (tuple((p.x, p.y) for p in pslg.vertices), pslg.segments,
             tuple((p.x, p.y) for p in pslg.holes), pslg.regions)
    assert before == after


@given(simple_polygons(3, 14))
def test_polygon_triangulation_has_n_minus_2_triangles(polygon: list[Point2]) -> None:
    """A simple polygon without inner points: n - 2 triangles covering its exact area;
    keeping the convex hull covers the hull's area instead."""
    n = len(polygon)
    pslg = PSLG(vertices=polygon, segments=loop_segments(0, n))
    run = triangulate(pslg)
    assert_sound(run)
    assert run.mesh.triangle_count == n - 2
    assert mesh_area(run.mesh) == polygon_area(polygon)
    hull_run = triangulate(pslg, keep_convex_hull=True)
    assert_sound(hull_run)
    assert mesh_area(hull_run.mesh) == polygon_area(convex_hull(polygon))
    assert len(hull_run.mesh.segments) == n


def _segments_meet(points: list[Point2], segments: list[tuple[int, int]]) -> bool:
    """A vertex strictly inside a segment, or two segments crossing at an inner point of
    both (independent of geomexact.mesh2d.segments)."""
    for u, v in segments:
        for w, p in enumerate(points):
            if w not in (u, v) and on_closed_segment(p, points[u], points[v]):
                return True
    for (u, v), (a, b) in itertools.combinations(segments, 2):
        if {u, v} & {a, b}:
            continue
        pu, pv, pa, pb = points[u], points[v], points[a], points[b]
        if (orient2d(pu, pv, pa) * orient2d(pu, pv, pb) < 0
                and orient2d(pa, pb, pu) * orient2d(pa, pb, pv) < 0):
            return True
    return False


@st.composite
def lattice_pslgs(
    draw: st.DrawFn, max_segments: int = 6
) -> tuple[list[Point2], list[tuple[int, int]]]:
    """Lattice points and random segments between them: crossings, T-junctions, collinear
    overlaps and vertices on segments are frequent."""
    points = draw(lattice_points(size=5, min_size=4, max_size=12))
    pairs = st.tuples(st.integers(0, len(points) - 1), st.integers(0, len(points) - 1))
    segments = draw(st.lists(pairs.filter(lambda p: p[0] != p[1]), min_size=1,
                             max_size=max_segments,
                             unique_by=lambda p: (min(p), max(p))))
    return points, segments


@given(lattice_pslgs())
@settings(suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
def test_split_segments_are_unions_of_constrained_edges(
    case: tuple[list[Point2], list[tuple[int, int]]]
) -> None:
    """With split_segments, crossing segments and segments through vertices are split
    exactly: every input segment is a chain of constrained edges, every constrained edge
    lies on an input segment, every new vertex is a crossing of two input segments, and
    the result is constrained Delaunay, covers the hull, and replays."""
    points, segments = case
    pslg = PSLG(vertices=points, segments=[(u, v, 1) for u, v in segments])
    run = triangulate(pslg, split_segments=True, keep_convex_hull=True)
    assert_sound(run)
    mesh = run.mesh
    for u, v in segments:
        assert segment_is_union_of_constrained_edges(mesh, points[u], points[v]), (u, v)
    for a, b in mesh.segments:
        assert any(on_closed_segment(mesh.point(a), points[u], points[v])
                   and on_closed_segment(mesh.point(b), points[u], points[v])
                   for u, v in segments), (a, b)
    for vertex in range(len(points), mesh.vertex_count):
        carriers = [(u, v) for u, v in segments
                    if on_closed_segment(mesh.point(vertex), points[u], points[v])]
        assert len(carriers) >= 2
    assert locally_non_delaunay(mesh) == []
    assert mesh_area(mesh) == polygon_area(convex_hull(points))


@given(lattice_pslgs())
@settings(suppress_health_check=[HealthCheck.filter_too_much, HealthCheck.too_slow])
def test_segments_raise_exactly_when_they_cross_or_pass_through_a_vertex(
    case: tuple[list[Point2], list[tuple[int, int]]]
) -> None:
    """Without split_segments: SegmentError exactly when a vertex lies inside a segment or
    two segments cross; otherwise every segment is one constrained edge."""
    points, segments = case
    pslg = PSLG(vertices=points, segments=[(u, v, 1) for u, v in segments])
    if _segments_meet(points, segments):
        with pytest.raises(SegmentError):
            triangulate(pslg, keep_convex_hull=True)
    else:
        run = triangulate(pslg, keep_convex_hull=True)
        assert_sound(run)
        assert all(run.mesh.is_constrained(u, v) for u, v in segments)
        assert len(run.mesh.segments) == len(segments)


# =======================================================================================
# duplicates, too few points, collinear input
# =======================================================================================


def test_duplicate_points_are_reported_with_their_ids() -> None:
    """Duplicates raise PreconditionError naming each (duplicate, first copy) pair."""
    points = [point2(0, 0), point2(1, 0), point2(0, 1), point2(0, 0), point2(1, 1),
              point2("0.5", 0), point2(1, 0), point2(mpq(1, 2), 0)]
    with pytest.raises(PreconditionError) as caught:
        triangulate_points(points)
    error = caught.value
    assert error.details["duplicates"] == ((3, 0), (6, 1), (7, 5))
    for text in ("3 duplicate points", "3 = 0", "6 = 1", "7 = 5", "merge_duplicates"):
        assert text in str(error)
    with pytest.raises(PreconditionError):
        triangulate(PSLG(vertices=points, segments=[(0, 1, 1)]))


def test_merge_duplicates_keeps_the_first_copy_and_isolates_the_others() -> None:
    """merge_duplicates=True: the first copy is triangulated, later copies stay isolated
    vertices (ids unchanged), listed in Construction.duplicates."""
    points = [point2(0, 0), point2(2, 0), point2(0, 0), point2(2, 2), point2(0, 2),
              point2(2, 2), point2(1, 1)]
    run = triangulate_points(points, merge_duplicates=True)
    assert_sound(run)
    assert run.duplicates == ((2, 0), (5, 3))
    mesh = run.mesh
    assert mesh.vertex_count == 7
    assert used_vertices(mesh) == {0, 1, 3, 4, 6}
    assert mesh.outgoing.get(2) is None and mesh.outgoing.get(5) is None
    assert mesh.triangle_count == point_set_triangle_count(points) == 4


def test_merge_duplicates_redirects_segments_to_the_first_copy() -> None:
    """A segment naming a dropped copy is inserted between the kept copies."""
    points = [*square(0, 0, 4), point2(4, 4), point2(1, 2)]
    segments = [*loop_segments(0, 4), (4, 0, 7)]  # vertex 4 repeats vertex 2
    run = triangulate(PSLG(vertices=points, segments=segments), merge_duplicates=True)
    assert_sound(run)
    assert run.duplicates == ((4, 2),)
    assert run.mesh.is_constrained(0, 2)
    assert run.mesh.segments[(0, 2)] == 7
    assert 4 not in used_vertices(run.mesh)


@pytest.mark.parametrize("points", [
    [],
    [point2(0, 0)],
    [point2(0, 0), point2(1, 1)],
])
def test_fewer_than_three_points_raise(points: list[Point2]) -> None:
    with pytest.raises(PreconditionError, match="need at least 3"):
        triangulate_points(points)


def test_fewer_than_three_distinct_points_after_merging_raise() -> None:
    points = [point2(0, 0), point2(1, 1), point2(0, 0), point2(1, 1)]
    with pytest.raises(PreconditionError, match="2 distinct points"):
        triangulate_points(points, merge_duplicates=True)


@pytest.mark.parametrize("points", [
    [point2(0, 0), point2(1, 1), point2(2, 2)],
    [point2(i, 3 * i + 1) for i in range(50)],
    [point2(mpq(1, 3) * i, mpq(2, 7)) for i in range(10)],
    [point2(mpq(10) ** 400 * i, -mpq(10) ** 400 * i) for i in range(5)],
])
def test_all_collinear_points_raise_a_clear_error(points: list[Point2]) -> None:
    with pytest.raises(PreconditionError, match="collinear"):
        triangulate_points(points)
    with pytest.raises(PreconditionError, match="collinear"):
        triangulate(PSLG(vertices=points, segments=[(0, 1, 1)]))


def test_collinear_points_plus_one_off_the_line() -> None:
    """Many collinear points and one apex: a fan of n - 2 triangles."""
    points = [point2(i, 0) for i in range(12)] + [point2(5, 1)]
    run = triangulate_points(points)
    assert_sound(run)
    assert run.mesh.triangle_count == 11
    assert globally_non_empty(run.mesh) == []


@pytest.mark.parametrize("points", [
    [point2(1.5e308, 0), point2(-1.5e308, 0), point2(0, 1), point2(1, 2)],
    [point2(1.7976931348623157e308, 1.7976931348623157e308), point2(-1.7e308, 0),
     point2(0, -1.7e308), point2(3, 4)],
    [point2(0, 0), point2(mpq(1, 10**308), 0), point2(0, mpq(1, 10**308))],
    [point2(mpq(i, 10**309), mpq(j, 10**309)) for i in range(3) for j in range(3)],
    [point2(0, 0), point2(mpq(1, 10**320), 0), point2(mpq(1, 10**320), mpq(1, 10**320))],
    [point2(mpq(10) ** 400, 0), point2(0, mpq(10) ** -400), point2(-(mpq(10) ** 400), 1),
     point2(0, mpq(1, 10**308))],
])
def test_coordinates_near_the_double_limits_triangulate(points: list[Point2]) -> None:
    """Finite doubles whose differences overflow, subnormal spans whose reciprocal
    overflows, coordinates beyond the double range: the insertion order (a float
    heuristic) must not crash, and the result is exact."""
    run = triangulate_points(points)
    assert_sound(run)
    assert run.mesh.triangle_count == point_set_triangle_count(points)


# =======================================================================================
# segments through vertices, crossing segments
# =======================================================================================


def test_segment_through_a_vertex_raises_and_names_it() -> None:
    """Segment (0, 2) of a square passes exactly through vertex 4 at its centre."""
    points = [*square(0, 0, 2), point2(1, 1)]
    pslg = PSLG(vertices=points, segments=[*loop_segments(0, 4), (0, 2, 5)])
    with pytest.raises(SegmentError) as caught:
        triangulate(pslg)
    assert isinstance(caught.value, PreconditionError) and isinstance(caught.value, ValueError)
    assert "segment (0, 2) passes through vertex 4" in str(caught.value)
    assert "split_segments=True" in str(caught.value)


def test_segment_error_carries_the_offending_pairs() -> None:
    """SegmentError's documented ``pairs``: the (segment, segment-or-vertex) pairs."""
    points = [*square(0, 0, 2), point2(1, 1)]
    pslg = PSLG(vertices=points, segments=[*loop_segments(0, 4), (0, 2, 5)])
    with pytest.raises(SegmentError) as caught:
        triangulate(pslg)
    error = caught.value
    pairs = getattr(error, "pairs", None) or error.details.get("pairs")
    assert pairs, "SegmentError has no structured pairs (neither .pairs nor details)"
    assert ((0, 2), 4) in pairs


def test_split_segment_through_a_vertex_becomes_two_constrained_edges() -> None:
    points = [*square(0, 0, 2), point2(1, 1)]
    pslg = PSLG(vertices=points, segments=[*loop_segments(0, 4), (0, 2, 5)])
    run = triangulate(pslg, split_segments=True)
    assert_sound(run)
    mesh = run.mesh
    assert mesh.vertex_count == 5
    assert mesh.segments[(0, 4)] == 5 and mesh.segments[(2, 4)] == 5
    assert not mesh.is_edge(0, 2)
    assert mesh_area(mesh) == 4


def test_crossing_segments_raise_and_name_them() -> None:
    points = [point2(0, 0), point2(3, 1), point2(0, 1), point2(1, -2), point2(2, 2)]
    pslg = PSLG(vertices=points, segments=[(0, 1, 1), (2, 3, 2)])
    with pytest.raises(SegmentError) as caught:
        triangulate(pslg)
    message = str(caught.value)
    assert "meet" in message and "(0, 1)" in message and "(2, 3)" in message


def test_split_crossing_segments_meet_at_the_exact_crossing_point() -> None:
    """(0,0)-(3,1) and (0,1)-(1,-2) cross at (3/10, 1/10): a new vertex with exactly those
    coordinates, and the four halves are constrained with their segment's marker."""
    points = [point2(0, 0), point2(3, 1), point2(0, 1), point2(1, -2), point2(2, 2)]
    pslg = PSLG(vertices=points, segments=[(0, 1, 1), (2, 3, 2)])
    run = triangulate(pslg, split_segments=True, keep_convex_hull=True)
    assert_sound(run)
    mesh = run.mesh
    assert mesh.vertex_count == 6
    crossing = mesh.point(5)
    assert (crossing.x, crossing.y) == (mpq(3, 10), mpq(1, 10))
    assert orient2d(points[0], points[1], crossing) == COLLINEAR
    assert orient2d(points[2], points[3], crossing) == COLLINEAR
    assert {mesh.segments[(0, 5)], mesh.segments[(1, 5)]} == {1}
    assert {mesh.segments[(2, 5)], mesh.segments[(3, 5)]} == {2}
    assert len(mesh.segments) == 4
    assert locally_non_delaunay(mesh) == []
    assert mesh_area(mesh) == polygon_area(convex_hull(points))


def test_three_segments_through_one_point_share_one_new_vertex() -> None:
    """Three segments crossing at (1, 1): one new vertex, six constrained halves."""
    points = [point2(0, 0), point2(2, 2), point2(0, 2), point2(2, 0), point2(1, 3),
              point2(1, -1)]
    segments = [(0, 1, 1), (2, 3, 1), (4, 5, 1)]
    run = triangulate(PSLG(vertices=points, segments=segments), split_segments=True,
                      keep_convex_hull=True)
    assert_sound(run)
    mesh = run.mesh
    assert mesh.vertex_count == 7
    assert (mesh.point(6).x, mesh.point(6).y) == (1, 1)
    assert sorted(mesh.segments) == sorted((min(v, 6), max(v, 6)) for v in range(6))


def test_collinear_overlapping_segments_split_at_each_others_ends() -> None:
    """(0,0)-(2,0) and (1,0)-(3,0) overlap on [1, 2]: error, or three constrained edges."""
    points = [point2(0, 0), point2(1, 0), point2(2, 0), point2(3, 0), point2(1, 2)]
    pslg = PSLG(vertices=points, segments=[(0, 2, 1), (1, 3, 1)])
    with pytest.raises(SegmentError):
        triangulate(pslg, keep_convex_hull=True)
    mesh = triangulate(pslg, keep_convex_hull=True, split_segments=True).mesh
    assert sorted(mesh.segments) == [(0, 1), (1, 2), (2, 3)]


@pytest.mark.parametrize("segment", [(0, 2), (2, 0)])
def test_segment_along_the_hull_through_a_collinear_hull_vertex(
    segment: tuple[int, int]
) -> None:
    """Segment (0,0)-(2,0) lies on the hull and passes through the hull vertex (1,0): a
    SegmentError naming it, and with split two constrained edges (in either direction).
    """
    points = [point2(0, 0), point2(1, 0), point2(2, 0), point2(1, 1)]
    pslg = PSLG(vertices=points, segments=[(*segment, 1)])
    with pytest.raises(SegmentError, match="passes through vertex 1"):
        triangulate(pslg, keep_convex_hull=True)
    run = triangulate(pslg, keep_convex_hull=True, split_segments=True)
    assert_sound(run)
    assert sorted(run.mesh.segments) == [(0, 1), (1, 2)]


# =======================================================================================
# holes, convex hull, regions
# =======================================================================================


def _square_with_square_hole() -> PSLG:
    vertices = [*square(0, 0, 4), *square(1, 1, 2)]
    segments = [*loop_segments(0, 4, 1), *loop_segments(4, 4, 2)]
    return PSLG(vertices=vertices, segments=segments, holes=[point2(2, 2)])


def test_square_with_square_hole_covers_outer_minus_inner_exactly() -> None:
    """A 4x4 square with a 2x2 square hole (seed at its centre): area 16 - 4, an annulus
    (V - E + T = 0, two boundary loops) of 8 triangles; the seed is in no triangle."""
    pslg = _square_with_square_hole()
    run = triangulate(pslg)
    assert_sound(run)
    mesh = run.mesh
    assert mesh_area(mesh) == 16 - 4
    assert mesh.triangle_count == 8
    assert euler_characteristic(mesh) == 0 and boundary_loops(mesh) == 2
    assert triangles_containing(mesh, point2(2, 2)) == []
    assert triangles_containing(mesh, point2("1.5", "1.999")) == []
    assert len(mesh.segments) == 8


def test_hole_seed_anywhere_inside_the_hole_removes_the_same_triangles() -> None:
    base = _square_with_square_hole()
    seeds = [point2(2, 2), point2("1.01", "2.99"), point2(mpq(5, 3), mpq(7, 4))]
    meshes = [triangulate(PSLG(vertices=base.vertices, segments=base.segments,
                               holes=[seed])).mesh for seed in seeds]
    assert all(coordinate_triangles(m) == coordinate_triangles(meshes[0]) for m in meshes)


def test_hole_seed_outside_the_domain_is_ignored() -> None:
    vertices = square(0, 0, 4)
    pslg = PSLG(vertices=vertices, segments=loop_segments(0, 4), holes=[point2(9, 9)])
    run = triangulate(pslg)
    assert_sound(run)
    assert mesh_area(run.mesh) == 16


def test_keep_convex_hull_keeps_the_hull_triangles_but_eats_holes() -> None:
    """An L-shaped polygon: its own area by default, the hull's area with
    keep_convex_hull; a hole is removed in both cases."""
    outline = [point2(0, 0), point2(6, 0), point2(6, 2), point2(2, 2), point2(2, 6),
               point2(0, 6)]
    hole = [point2("0.5", "0.5"), point2("1.5", "0.5"), point2("1.5", "1.5"),
            point2("0.5", "1.5")]
    pslg = PSLG(vertices=[*outline, *hole],
                segments=[*loop_segments(0, 6), *loop_segments(6, 4, 2)],
                holes=[point2(1, 1)])
    default = triangulate(pslg)
    kept = triangulate(pslg, keep_convex_hull=True)
    for run in (default, kept):
        assert_sound(run)
        assert len(run.mesh.segments) == 10
        assert triangles_containing(run.mesh, point2(1, 1)) == []
        assert locally_non_delaunay(run.mesh) == []
    assert mesh_area(default.mesh) == polygon_area(outline) - 1
    assert mesh_area(kept.mesh) == polygon_area(convex_hull(outline)) - 1
    assert coordinate_triangles(default.mesh) < coordinate_triangles(kept.mesh)


def test_regional_attributes_are_set_on_every_triangle_of_each_region() -> None:
    """A square split by a constrained zig-zag into two regions with attributes 1/3 and 7;
    a third seed in the hole is ignored."""
    vertices = [*square(0, 0, 6), point2(3, 0), point2(2, 3), point2(4, 4), point2(3, 6),
                *[point2(x, y) for x, y in ((1, 1), (5, 1), (1, 5), (5, 5))],
                *square(4, 2, 1)]
    segments = [(0, 4, 1), (4, 1, 1), (1, 2, 1), (2, 7, 1), (7, 3, 1), (3, 0, 1),
                (4, 5, 2), (5, 6, 2), (6, 7, 2), *loop_segments(12, 4, 3)]
    regions = [RegionSeed(point2(1, 3), mpq(1, 3)), RegionSeed(point2(5, 3), mpq(7)),
               RegionSeed(point2("4.5", "2.5"), mpq(99))]
    pslg = PSLG(vertices=vertices, segments=segments, holes=[point2("4.5", "2.5")],
                regions=regions)
    run = triangulate(pslg)
    assert_sound(run)
    mesh = run.mesh
    left = [point2(0, 0), point2(3, 0), point2(2, 3), point2(4, 4), point2(3, 6),
            point2(0, 6)]
    left_area = mpq(0)
    for triangle in mesh.triangles():
        a, b, c = (mesh.point(v) for v in triangle)
        centroid = point2((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3)
        inside_left = inside(centroid, left)
        assert mesh.triangle_attributes[triangle] == ((mpq(1, 3),) if inside_left
                                                      else (mpq(7),))
        if inside_left:
            left_area += polygon_area([a, b, c])
    assert left_area == polygon_area(left)
    assert mesh_area(mesh) == 36 - 1


def test_region_seeds_without_segments_cover_the_hull() -> None:
    points = grid(3, 3)
    pslg = PSLG(vertices=points, regions=[RegionSeed(point2(1, 1), mpq(5, 2))])
    run = triangulate(pslg)
    assert_sound(run)
    assert run.mesh.triangle_count == 8
    assert set(run.mesh.triangle_attributes.values()) == {(mpq(5, 2),)}
    assert len(run.mesh.triangle_attributes) == 8


# =======================================================================================
# make_delaunay (Lawson flips)
# =======================================================================================


@given(triangulations(max_steps=25))
@settings(suppress_health_check=[HealthCheck.too_slow])
def test_make_delaunay_flips_any_triangulation_to_delaunay(mesh: Mesh2) -> None:
    """Lawson flips give a constrained Delaunay mesh on the same vertices, segments,
    boundary and area; the trace of flips replays; the input is unchanged; a second run
    flips nothing; without constraints it is *the* Delaunay triangulation of the vertices
    (up to cocircular ties)."""
    before = mesh.digest
    result, trace = make_delaunay(mesh)
    assert mesh.digest == before and validate(mesh) == []
    assert validate(result) == []
    assert locally_non_delaunay(result) == [] and is_delaunay(result)
    assert all(step.op == "flip" for step in trace.steps)
    assert replay(mesh, trace) == result
    assert result.vertices == mesh.vertices and result.segments == mesh.segments
    assert result.boundary_edges() == mesh.boundary_edges()
    assert mesh_area(result) == mesh_area(mesh)
    assert len(make_delaunay(result)[1]) == 0
    if not mesh.segments:
        points = [mesh.point(v) for v in range(mesh.vertex_count)]
        assert differ_only_where_cocircular(result, triangulate_points(points).mesh)


def test_make_delaunay_and_is_delaunay_agree_on_region_borders() -> None:
    """A thin quadrilateral whose diagonal fails the incircle test, its two triangles
    carrying different attributes (a .ele file with a region column, no segments): the
    diagonal is a region border, which no flip may cross, so make_delaunay leaves it and
    is_delaunay exempts it like a constrained edge."""
    points = [(0, 0), (4, -1), (8, 0), (4, 1)]
    mesh = mesh_from_triangles(points, [(0, 1, 2), (0, 2, 3)],
                               triangle_attributes=[(mpq(1),), (mpq(2),)])
    assert validate(mesh) == [] and locally_non_delaunay(mesh) == [(0, 2)]
    assert non_delaunay_edges(mesh) == [] and is_delaunay(mesh)
    result, trace = make_delaunay(mesh)
    assert len(trace) == 0 and result == mesh
    same = mesh_from_triangles(points, [(0, 1, 2), (0, 2, 3)],
                               triangle_attributes=[(mpq(1),), (mpq(1),)])
    assert non_delaunay_edges(same) == [(0, 2)]
    result, trace = make_delaunay(same)
    assert [step.op for step in trace.steps] == ["flip"] and is_delaunay(result)
    assert set(result.triangle_attributes.values()) == {(mpq(1),)}
