"""Scenes and histories (geomexact.viz.scene): what the pictures and the viewer draw, and
the per-step changes the viewer's slider replays."""

from __future__ import annotations

from pathlib import Path

import attrs
import pytest
from hypothesis import given

from geomexact import io
from geomexact.errors import TraceError
from geomexact.kernel.numbers import Rational, format_rational, mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG, RegionSeed
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import Transient2, mesh_from_triangles
from geomexact.strategies import meshes_with_traces
from geomexact.trace.playback import replay
from geomexact.trace.record import Trace
from geomexact.viz.scene import (
    History,
    doubles,
    exact_text,
    history_of,
    indices,
    is_convex_polygon,
    little_endian,
    mesh_scene,
    scale_exponent_of,
    scene_of,
    step_label,
    trace_start,
)

SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"


@pytest.fixture(scope="module")
def superior() -> PSLG:
    pslg = io.read(SUPERIOR)
    assert isinstance(pslg, PSLG)
    return pslg


def square() -> Mesh2:
    return mesh_from_triangles([("0", "0"), ("1", "0"), ("1", "1"), ("0", "1")],
                               [(0, 1, 2), (0, 2, 3)], [(0, 1, 1)])


def assert_history_matches_replay(start: Mesh2, trace: Trace, history: History,
                                  steps: list[int]) -> None:
    for step in steps:
        mesh = replay(start, trace, until=step)
        assert history.triangles_at(step) == mesh.triangles(), step
        assert history.segments_at(step) == [(u, v) for u, v, _ in mesh.segment_list()], step
        assert history.vertex_counts[step] == mesh.vertex_count, step


# ---------------------------------------------------------------------------------------
# histories
# ---------------------------------------------------------------------------------------
@given(meshes_with_traces(max_steps=12))
def test_history_reproduces_every_replayed_mesh(case: tuple[Mesh2, Mesh2, Trace]) -> None:
    """After k steps, the history's alive triangles, segments and vertex count are those
    of replay(start, trace, until=k), for every k; its final mesh is the trace's end."""
    start, end, trace = case
    history = history_of(start, trace)
    assert history.steps == len(trace)
    assert history.final == end
    assert_history_matches_replay(start, trace, history, list(range(len(trace) + 1)))


def test_history_of_superior_triangulation(superior: PSLG) -> None:
    """The 2,517-step constrained Delaunay triangulation of Lake Superior: the history
    matches replay at sampled steps and ends at the construction's mesh."""
    run = triangulate(superior)
    history = history_of(run.start, run.trace)
    assert history.steps == len(run.trace) > 2000
    assert history.final == run.mesh
    assert history.input_digest == f"{run.trace.input_digest:032x}"
    assert history.final_digest == run.mesh.digest_text
    assert_history_matches_replay(run.start, run.trace, history, [0, 1, 2, 3, 100, 1499,
                                                                  2000, len(run.trace)])
    assert len(history.labels) == len(run.trace)
    assert history.labels[0].startswith("make_triangle(")


def test_step_changes_of_a_flip() -> None:
    """A flip removes the two triangles of its edge and adds the two of the other
    diagonal; the offsets say so."""
    start = square()
    t = Transient2(start)
    from geomexact.mesh2d.ops import flip_in

    flip_in(t, 0, 2)
    t.seal()
    trace = Trace(start.digest, t.steps, t.step_digests)
    history = history_of(start, trace)
    added, removed = history.step_changes(1)
    assert removed == [(0, 1, 2), (0, 2, 3)]
    assert added == [(0, 1, 3), (1, 2, 3)]
    assert list(history.triangles.added_offsets) == [0, 2]
    assert list(history.triangles.removed_offsets) == [0, 2]
    with pytest.raises(ValueError):
        history.step_changes(2)
    with pytest.raises(ValueError):
        history.triangles_at(2)


def test_recreated_triangle_keeps_its_slot() -> None:
    """Flipping an edge twice re-creates the first triangles: they keep their slots, so
    the history has four cells, not six."""
    start = square()
    t = Transient2(start)
    from geomexact.mesh2d.ops import flip_in

    flip_in(t, 0, 2)
    flip_in(t, 1, 3)
    t.seal()
    history = history_of(start, Trace(start.digest, t.steps, t.step_digests))
    assert len(history.triangles.cells) // 3 == 4
    assert history.triangles_at(2) == history.triangles_at(0)


def test_region_step_is_both_removed_and_added(superior: PSLG) -> None:
    """A step that gives triangles a regional attribute lists them as removed and added
    (re-created): the triangle set is unchanged, the viewer highlights them."""
    pslg = attrs.evolve(superior, regions=(RegionSeed(point2("0.55", "-0.5"), 7),))
    run = triangulate(pslg)
    history = history_of(run.start, run.trace)
    last = history.steps
    assert run.trace.steps[-1].op == "set_region"
    added, removed = history.step_changes(last)
    assert added and added == removed
    assert history.triangles_at(last) == history.triangles_at(last - 1)


def test_history_refuses_another_start(superior: PSLG) -> None:
    """A trace replayed on a mesh it was not recorded on: TraceError, before any step."""
    run = triangulate(superior)
    with pytest.raises(TraceError, match="not the trace's input"):
        history_of(square(), run.trace)


def test_history_reports_a_diverging_step(superior: PSLG) -> None:
    """A trace whose 5th digest was altered: TraceError naming step 5."""
    run = triangulate(superior)
    digests = list(run.trace.digests)
    digests[4] ^= 1
    bad = Trace(run.trace.input_digest, run.trace.steps, digests)
    with pytest.raises(TraceError) as caught:
        history_of(run.start, bad)
    assert caught.value.step == 5


def test_trace_start_of_a_pslg_is_its_vertices(superior: PSLG) -> None:
    """A triangulation trace starts from the PSLG's isolated vertices; a polygon mesh
    cannot start a trace."""
    start = trace_start(superior)
    assert start.vertex_count == len(superior.vertices) and start.triangle_count == 0
    assert trace_start(square()) is not None
    with pytest.raises(TypeError):
        trace_start(PolygonMesh([point2(0, 0), point2(1, 0), point2(0, 1)], [(0, 1, 2)]))


def test_step_label_shows_exact_decimals() -> None:
    """Rational arguments are shown as the shortest exact decimal, else p/q."""
    from geomexact.kernel.numbers import parse_rational
    from geomexact.trace.step import Step

    assert step_label(Step("carve", (parse_rational("0.55"), parse_rational("-1/3")))) == \
        "carve(0.55, -1/3)"
    assert step_label(Step("flip", (3, 5))) == "flip(3, 5)"


# ---------------------------------------------------------------------------------------
# scenes
# ---------------------------------------------------------------------------------------
def test_mesh_scene_tables() -> None:
    """A mesh's scene: vertex doubles, sorted canonical triangles, segments, summary."""
    scene = scene_of(square())
    assert scene.kind == "triangles" and scene.dimension == 2
    assert list(scene.xy) == [0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0]
    assert list(scene.triangles) == [0, 1, 2, 0, 2, 3]
    assert list(scene.segments) == [0, 1]
    assert scene.regions is None
    assert scene.summary["triangles"] == 2 and scene.summary["total_area"] == "1"
    assert scene.exact == ("0 0", "1 0", "1 1", "0 1")


def test_mesh_scene_regions_follow_triangles(superior: PSLG) -> None:
    """The first triangle attribute of each triangle, NaN where it has none."""
    pslg = attrs.evolve(superior, regions=(RegionSeed(point2("0.55", "-0.5"), 7),))
    mesh = triangulate(pslg).mesh
    scene = scene_of(mesh, summary=False)
    assert scene.regions is not None and len(scene.regions) == mesh.triangle_count
    assert set(scene.regions) == {7.0}


def test_pslg_scene(superior: PSLG) -> None:
    """A PSLG's scene: vertices, segments, holes; no cells."""
    scene = scene_of(superior)
    assert scene.kind == "pslg"
    assert scene.vertex_count == 518 and len(scene.segments) == 2 * 518
    assert len(scene.holes) == 2 * 6 and scene.triangle_count == 0
    assert scene.summary == {"vertices": 518, "segments": 518, "holes": 6, "regions": 0}


def test_polygon_scene_finds_nonconvex_polygons_exactly() -> None:
    """An L-shaped hexagon is non-convex, a square with a vertex exactly on an edge is
    convex (collinear corner), a polygon repeating a vertex is non-convex."""
    points = [point2(*p) for p in [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2),
                                   (3, 0), (4, 0), (4, 1), (3, 1), ("3.5", 0)]]
    l_shape = (0, 1, 2, 3, 4, 5)
    square_with_midpoint = (6, 10, 7, 8, 9)
    mesh = PolygonMesh(points, [l_shape, square_with_midpoint])
    scene = scene_of(mesh)
    assert scene.kind == "polygons" and scene.polygon_count == 2
    assert scene.polygon(0) == l_shape and scene.polygon(1) == square_with_midpoint
    assert list(scene.nonconvex) == [0]
    assert scene.summary["nonconvex_polygons"] == 1
    assert not is_convex_polygon(points, (0, 1, 2, 1))


def test_scene_of_unknown_value() -> None:
    """Anything that is not a registered kind of value: TypeError naming the kinds."""
    with pytest.raises(TypeError, match="Mesh2"):
        scene_of("not a mesh")


def test_exact_text_budget() -> None:
    """Exact text is kept while it fits in the budget, else dropped entirely."""
    points = [point2("1/3", "2.5")] * 10
    assert exact_text(points) == ("1/3 2.5",) * 10
    assert exact_text(points, budget=50) is None
    assert scene_of(square(), exact_budget=0).exact is None


def test_arrays_are_little_endian() -> None:
    """Typed-array bytes are little-endian on every platform."""
    assert little_endian(indices([1, 256])) == bytes([1, 0, 0, 0, 0, 1, 0, 0])
    assert little_endian(doubles([1.0])) == bytes([0, 0, 0, 0, 0, 0, 0xF0, 0x3F])
    assert indices().itemsize == 4


def test_ordinary_scenes_are_drawn_unscaled(superior: PSLG) -> None:
    """Every ordinary input keeps its cached doubles (scale_exponent 0)."""
    scene = scene_of(triangulate(superior).mesh, summary=False)
    assert scene.scale_exponent == 0
    mesh = triangulate(superior).mesh
    assert list(scene.xy) == [c for v in range(mesh.vertex_count)
                              for c in (mesh.point(v).fx, mesh.point(v).fy)]
    assert scale_exponent_of([point2(0, 0)]) == 0 and scale_exponent_of() == 0


@pytest.mark.parametrize("scale", [mpq(10) ** 309, mpq(10) ** -400, mpq(2) ** 600,
                                   mpq(2) ** -600, mpq(10) ** 200_000,
                                   mpq(1, 7) / mpq(10) ** 100_000])
def test_scenes_beyond_the_band_are_drawn_scaled_exactly(scale: Rational) -> None:
    """The drawing is the exact coordinates times 2^-k, the largest in [1, 2), in every
    kind of scene; the exact text is unscaled."""
    corners = [(0, 0), (3, 1), (1, 4), (4, 5)]
    mesh = mesh_from_triangles([(x * scale, y * scale) for x, y in corners],
                               [(0, 1, 2), (1, 3, 2)])
    points = [mesh.point(v) for v in range(4)]
    pslg = PSLG(points, [(0, 1, 0), (1, 3, 0), (3, 2, 0), (2, 0, 0)],
                holes=[point2(2 * scale, 2 * scale)],
                regions=[RegionSeed(point2(scale, scale), 1)])
    polygons = PolygonMesh(points, [(0, 1, 3, 2)])
    for value in (mesh, pslg, polygons):
        scene = scene_of(value, summary=False)
        k = scene.scale_exponent
        assert mpq(2) ** k <= 5 * scale < mpq(2) ** (k + 1)
        assert list(scene.xy) == [float(c * scale / mpq(2) ** k) for xy in corners for c in xy]
        assert scene.exact is not None and scene.exact[3].split() == [
            format_rational(4 * scale), format_rational(5 * scale)]
    assert list(scene_of(pslg).holes) == [float(2 * scale / mpq(2) ** k)] * 2


def test_a_scene_from_a_kernels_arrays_equals_the_scene_from_tables() -> None:
    """A refined mesh whose tables are still the kernel's arrays gives the same scene
    (triangles sorted canonically, exact text) as the same mesh read back from its
    tables; the exact text writes each distinct coordinate once and stays exact."""
    from geomexact.mesh2d.refinement.api import refine
    from geomexact.mesh2d.refinement.criteria import MaxArea
    from geomexact.mesh2d.refinement.engines import compiled

    square = mesh_from_triangles([(0, 0), (1, 0), (1, 1), (0, mpq(1, 3))],
                                 [(0, 1, 2), (0, 2, 3)])
    refined = refine(square, MaxArea(mpq(1, 300))).mesh
    assert refined.source is not None or not compiled.AVAILABLE
    from_tables = mesh_from_triangles(refined.point_list(), refined.triangles())
    scene, again = mesh_scene(refined), mesh_scene(from_tables)
    assert list(scene.triangles) == [v for t in sorted(refined.triangles()) for v in t]
    assert scene.triangles == again.triangles and scene.exact == again.exact
    assert scene.exact is not None and scene.exact[3] == "0 1/3"
