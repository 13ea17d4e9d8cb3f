"""The compiled Delaunay kernel (``geomexact.mesh2d.delaunay.delaunay_kernel`` through
``geomexact.mesh2d.delaunay.compiled``) against the Python engine ``BatchDelaunay``: the same
steps, the same digest after every step, the same final mesh (``outgoing`` hints
included) on every input — random, lattices (cocircular ties), collinear prefixes,
duplicates, huge / tiny / beyond-double coordinates, non-dyadic rationals, real point
sets.  Skipped when the extension is not built."""

from __future__ import annotations

import inspect
import random
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact import io
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2, point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d
from geomexact.mesh2d.delaunay.compiled import AVAILABLE, CompiledConstruction, run_compiled
from geomexact.mesh2d.delaunay.triangulation import (
    BatchDelaunay,
    duplicate_points,
    insertion_order,
    triangulate_points,
    vertices_mesh,
)
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.strategies import coordinates, dyadic_rationals, points2
from geomexact.trace.playback import replay

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="the compiled Delaunay kernel is not built")


def prepared(points: Sequence[Point2], seed: int = 0) -> tuple[Any, ...] | None:
    """What ``triangulate_points`` hands the builder (duplicates merged): (vertices, start,
    (a, b, c), rest), or None when there is no triangle."""
    pslg = PSLG(vertices=tuple(points))
    vertices = pslg.vertices
    dropped = {d for d, _ in duplicate_points(vertices)}
    order = [v for v in insertion_order(vertices, seed=seed) if v not in dropped]
    if len(order) < 3:
        return None
    a, b = order[0], order[1]
    third = next((k for k in range(2, len(order)) if orient2d(
        vertices[a], vertices[b], vertices[order[k]]) != Orientation.COLLINEAR), None)
    if third is None:
        return None
    c = order.pop(third)
    return vertices, vertices_mesh(pslg), (a, b, c), order[2:]


def same(points: Sequence[Point2], seed: int = 0) -> CompiledConstruction | None:
    """Run the kernel and the Python builder on the same input; assert they agree."""
    setup = prepared(points, seed)
    if setup is None:
        return None
    vertices, start, (a, b, c), rest = setup
    compiled = run_compiled(vertices, start, (a, b, c), rest)
    assert compiled is not None
    builder = BatchDelaunay(start)
    builder.make_triangle(a, b, c)
    for vertex in rest:
        builder.insert(vertex)
    python = builder.seal(start)
    assert compiled.steps == builder.steps
    assert compiled.digests == builder.digests
    mesh = compiled.mesh
    assert mesh == python
    assert mesh.digest == python.digest and mesh.triangle_count == python.triangle_count
    for table in ("vertices", "halfedges", "outgoing", "segments", "vertex_markers",
                  "vertex_attributes", "triangle_attributes"):
        assert getattr(mesh, table) == getattr(python, table), table
    assert type(mesh.halfedges) is type(python.halfedges)
    return compiled


def lattice(width: int, height: int, denominator: int = 1) -> list[Point2]:
    return [point2(mpq(x, denominator), mpq(y, denominator))
            for x in range(width) for y in range(height)]


# --- the benchmark's input: random doubles ---------------------------------------------
@pytest.mark.parametrize("count", [3, 10, 64, 65, 500, 3000])
def test_random_doubles(count: int) -> None:
    rng = random.Random(count)
    points = [point2(mpq(rng.random()), mpq(rng.random())) for _ in range(count)]
    run = same(points)
    assert run is not None and run.steps[0].op == "make_triangle"


def test_random_doubles_replay() -> None:
    rng = random.Random(7)
    points = [point2(mpq(rng.random()), mpq(rng.random())) for _ in range(400)]
    setup = prepared(points)
    assert setup is not None
    vertices, start, first, rest = setup
    run = run_compiled(vertices, start, first, rest)
    assert run is not None
    from geomexact.trace.record import Trace

    trace = Trace(start.digest, run.steps, run.digests)
    assert replay(start, trace) == run.mesh


@pytest.mark.parametrize("seed", [0, 1, 5])
def test_seeds(seed: int) -> None:
    rng = random.Random(99)
    same([point2(mpq(rng.randrange(-10**6, 10**6), 7), mpq(rng.randrange(10**6), 3))
          for _ in range(300)], seed=seed)


# --- cocircular ties, collinear runs, hull growth -----------------------------------------
@pytest.mark.parametrize(("width", "height", "denominator"),
                         [(3, 3, 1), (10, 10, 1), (17, 5, 8), (12, 12, 3), (25, 25, 10),
                          (40, 1, 1), (2, 30, 1)])
def test_lattices(width: int, height: int, denominator: int) -> None:
    """Every lattice square is cocircular: the tie rule (no flip) decides."""
    same(lattice(width, height, denominator))


def test_lattice_seeds() -> None:
    for seed in range(5):
        same(lattice(9, 7), seed=seed)


def test_circle_points() -> None:
    """All points on one circle (exact rational points of the unit circle)."""
    points = []
    for s in range(-20, 21):
        t = mpq(s, 7)
        points.append(point2((1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)))
    points.append(point2(-1, 0))
    same(points)


def test_collinear_prefixes() -> None:
    """Many collinear points before the first non-collinear one; points on hull edges."""
    line = [point2(i, 2 * i) for i in range(50)]
    same([*line, point2(3, 1)])
    same([*line, point2(3, 1), point2(-5, 40), point2(100, 1)])
    same([point2(i, 0) for i in range(30)] + [point2(i, 1) for i in range(30)])
    same([point2(i, 0) for i in range(20)] + [point2(0, i) for i in range(1, 20)])


def test_growing_hull() -> None:
    """Points on a convex curve: each new point outside the hull sees many edges."""
    same([point2(i, i * i) for i in range(-40, 41)])
    same([point2(mpq(1, i), i) for i in range(1, 60)])


def test_all_collinear_and_too_few() -> None:
    assert prepared([point2(i, i) for i in range(10)]) is None
    assert prepared([point2(0, 0), point2(1, 1), point2(0, 0)]) is None


# --- duplicates ----------------------------------------------------------------------------
def test_duplicates_merged() -> None:
    rng = random.Random(3)
    base = [point2(mpq(rng.randrange(20), 4), mpq(rng.randrange(20), 4)) for _ in range(300)]
    assert duplicate_points(base)  # many copies
    run = same(base)
    assert run is not None
    isolated = {d for d, _ in duplicate_points(base)}
    assert not any(u in isolated or v in isolated for u, v in run.mesh.halfedges)


# --- magnitudes ----------------------------------------------------------------------------
@pytest.mark.parametrize("scale", [mpq(1), mpq(2) ** 70, mpq(2) ** -80, mpq(10) ** 300,
                                   mpq(10) ** -300, mpq(10) ** 400, mpq(10) ** -400,
                                   mpq(1, 3), mpq(2) ** 1000])
def test_scaled_inputs(scale: Any) -> None:
    """Huge and tiny coordinates, beyond the double range, non-dyadic scales; a lattice
    (ties) and random points, each scaled."""
    rng = random.Random(11)
    same([point2(p.x * scale, p.y * scale) for p in lattice(6, 6)])
    same([point2(mpq(rng.randrange(10**9), 10**9) * scale,
                 mpq(rng.randrange(10**9), 10**9) * scale) for _ in range(200)])


def test_mixed_magnitudes() -> None:
    """Grid and off-grid vertices in one run (some doubles far below 2**-F)."""
    rng = random.Random(5)
    points = [point2(mpq(rng.random()), mpq(rng.random())) for _ in range(200)]
    points += [point2(mpq(rng.random()) * mpq(2) ** -70, mpq(rng.random())) for _ in range(50)]
    points += [point2(mpq(1, 3) + mpq(k, 10**40), mpq(1, 7)) for k in range(20)]
    same(points)


def test_non_dyadic_rationals() -> None:
    rng = random.Random(8)
    same([point2(mpq(rng.randrange(1, 1000), rng.randrange(1, 1000)),
                 mpq(rng.randrange(1, 1000), rng.randrange(1, 1000))) for _ in range(300)])
    same([point2(mpq(x, 10), mpq(y, 10)) for x in range(15) for y in range(15)])


def test_grid_states() -> None:
    """Doubles in [0, 1) at or above 2**-8 are on the grid, exact non-doubles are not."""
    from geomexact.mesh2d.delaunay import delaunay_kernel  # type: ignore[attr-defined]

    points = [point2(mpq(1, 2), mpq(3, 4)), point2(mpq(2) ** -8, mpq(0)),
              point2(mpq(2) ** -60, mpq(1, 2)), point2(mpq(1, 3), mpq(1, 2)),
              point2(mpq(2) ** -61, mpq(1, 2))]
    builder = delaunay_kernel.Builder(points, 0)
    assert builder.grid == (60, 3)
    assert builder.vertex_state(0) == (True, 2**59, 3 * 2**58)
    assert builder.vertex_state(1) == (True, 2**52, 0)
    assert builder.vertex_state(2)[0]
    assert not builder.vertex_state(3)[0] and not builder.vertex_state(4)[0]


def test_hashes_match_digest() -> None:
    from geomexact.kernel import digest
    from geomexact.mesh2d.delaunay import delaunay_kernel  # type: ignore[attr-defined]

    for cell in [(0, 1, 2), (5, 3, 9), (70000, 2, 123456)]:
        assert delaunay_kernel.cell_hash(*cell) == digest.cell_hash(cell)


# --- random inputs (hypothesis) ------------------------------------------------------------
@given(st.lists(points2(), min_size=3, max_size=30))
def test_random_points_any_magnitude(points: list[Point2]) -> None:
    same(points)


@given(st.lists(points2(dyadic_rationals(max_exponent=8)), min_size=3, max_size=60),
       st.integers(0, 3))
def test_random_dyadic_points(points: list[Point2], seed: int) -> None:
    same(points, seed=seed)


@given(st.lists(st.tuples(st.integers(0, 12), st.integers(0, 12)), min_size=3, max_size=80),
       st.sampled_from([1, 4, 3]))
def test_random_lattice_subsets(raw: list[tuple[int, int]], denominator: int) -> None:
    """Lattice subsets with repeats: ties, collinear runs and duplicates together."""
    same([point2(mpq(x, denominator), mpq(y, denominator)) for x, y in raw])


@settings(max_examples=20)
@given(st.lists(points2(coordinates(["ordinary", "decimal"])), min_size=3, max_size=120))
def test_random_ordinary_points(points: list[Point2]) -> None:
    same(points)


# --- the real point sets --------------------------------------------------------------------
@pytest.mark.parametrize("name", ["polylla-refinement/500poisson.off",
                                  "polylla-refinement/1500random.off"])
def test_real_point_sets(shared_data: Path, name: str) -> None:
    path = shared_data / name
    if not path.exists():
        pytest.skip(f"{path} not found")
    mesh = io.read(path)
    assert isinstance(mesh, Mesh2)
    run = same([mesh.point(v) for v in range(mesh.vertex_count)])
    assert run is not None


# --- through triangulate_points, once it has the engine parameter ---------------------------
def test_engines_of_triangulate_points() -> None:
    if "engine" not in inspect.signature(triangulate_points).parameters:
        pytest.skip("triangulate_points has no engine parameter yet")
    rng = random.Random(2)
    points = [point2(mpq(rng.random()), mpq(rng.random())) for _ in range(500)]
    points += points[:10]  # duplicates
    runs = {engine: triangulate_points(points, merge_duplicates=True, engine=engine)
            for engine in ("fast", "python")}
    fast, python = runs["fast"], runs["python"]
    assert fast.trace == python.trace
    assert fast.mesh == python.mesh and fast.mesh.outgoing == python.mesh.outgoing
    assert fast.duplicates == python.duplicates and fast.start == python.start
