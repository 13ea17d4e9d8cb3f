"""Planar straight-line graphs (``geomexact.mesh2d.pslg``): an immutable value of exact
vertices, marked segments, hole and region seeds and per-vertex tables, refusing segments
on missing vertices, segments with equal ends and tables of the wrong length."""

from __future__ import annotations

import attrs
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.pslg import PSLG, RegionSeed, point_set
from geomexact.strategies import points2, pslgs, rationals

FEW = settings(max_examples=min(settings().max_examples, 40))
TRIANGLE = [point2(0, 0), point2(4, 0), point2(0, 4)]


def test_a_pslg_holds_its_tables_as_tuples() -> None:
    """Lists given for any table are stored as tuples; unspecified tables are empty."""
    pslg = PSLG(vertices=list(TRIANGLE), segments=[(0, 1, 1), (1, 2, 1), (2, 0, 2)])
    assert pslg.vertices == tuple(TRIANGLE)
    assert pslg.segments == ((0, 1, 1), (1, 2, 1), (2, 0, 2))
    assert pslg.holes == () and pslg.regions == ()
    assert pslg.vertex_markers == () and pslg.vertex_attributes == ()
    assert all(isinstance(table, tuple) for table in attrs.astuple(pslg, recurse=False))


def test_a_pslg_is_frozen_and_compares_by_value() -> None:
    """Fields cannot be assigned; equal content gives equal, equally hashed values."""
    pslg = PSLG(vertices=TRIANGLE, segments=[(0, 1, 1)])
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        pslg.segments = ()  # type: ignore[misc]
    same = PSLG(vertices=tuple(TRIANGLE), segments=((0, 1, 1),))
    assert pslg == same and hash(pslg) == hash(same)
    assert pslg != PSLG(vertices=TRIANGLE, segments=[(0, 1, 2)])
    assert pslg != PSLG(vertices=TRIANGLE, segments=[(0, 1, 1)], holes=[point2(1, 1)])


def test_point_set_is_a_pslg_without_segments() -> None:
    """point_set keeps the points in order, with no segments, holes or regions."""
    pslg = point_set(TRIANGLE)
    assert pslg == PSLG(vertices=TRIANGLE)
    assert pslg.vertices == tuple(TRIANGLE) and pslg.segments == ()


def test_markers_default_to_zero() -> None:
    """marker(v) reads the table, or 0 when the input has no markers."""
    assert [point_set(TRIANGLE).marker(v) for v in range(3)] == [0, 0, 0]
    marked = PSLG(vertices=TRIANGLE, vertex_markers=[3, 0, 7])
    assert [marked.marker(v) for v in range(3)] == [3, 0, 7]


def test_region_seeds_hold_exact_values() -> None:
    """A region seed has a point, an attribute and an optional maximum area (None by
    default); the PSLG keeps its holes and regions in order."""
    seed = RegionSeed(point2(1, 1), mpq(2, 3))
    assert seed.max_area is None
    limited = RegionSeed(point2(mpq(1, 2), 1), mpq(5), max_area=mpq(1, 10))
    pslg = PSLG(vertices=TRIANGLE, segments=[(0, 1, 1), (1, 2, 1), (2, 0, 1)],
                holes=[point2(mpq(1, 4), mpq(1, 4))], regions=[seed, limited])
    assert pslg.regions == (seed, limited)
    assert pslg.regions[1].max_area == mpq(1, 10)
    assert pslg.holes == (point2(mpq(1, 4), mpq(1, 4)),)
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        seed.attribute = mpq(0)  # type: ignore[misc]


@pytest.mark.parametrize(
    ("segment", "message"),
    [((0, 3, 1), "missing vertex"), ((-1, 2, 1), "missing vertex"),
     ((5, 0, 0), "missing vertex"), ((2, 2, 1), "equal ends")],
)
def test_bad_segments_are_refused(segment: tuple[int, int, int], message: str) -> None:
    """A segment on an id outside 0..n-1 or with equal ends is refused, naming its index."""
    with pytest.raises(PreconditionError, match=f"segment #1 .*{message}"):
        PSLG(vertices=TRIANGLE, segments=[(0, 1, 1), segment])


@pytest.mark.parametrize("table", ["vertex_markers", "vertex_attributes"])
@pytest.mark.parametrize("length", [2, 4])
def test_per_vertex_tables_need_one_entry_per_vertex(table: str, length: int) -> None:
    """Markers and attribute tables, when given, have exactly one entry per vertex."""
    entry = 1 if table == "vertex_markers" else (mpq(1),)
    with pytest.raises(PreconditionError, match=f"{table} has {length} entries for 3"):
        PSLG(vertices=TRIANGLE, **{table: [entry] * length})
    assert len(getattr(PSLG(vertices=TRIANGLE, **{table: [entry] * 3}), table)) == 3


def test_an_empty_pslg_is_allowed() -> None:
    """No vertices and no segments is a valid (empty) PSLG."""
    assert PSLG(vertices=()).vertices == ()


@FEW
@given(st.lists(points2(rationals()), min_size=2, max_size=8), st.data())
def test_any_segment_between_existing_distinct_vertices_is_accepted(
    points: list[object], data: st.DataObject
) -> None:
    """Segments between any two distinct ids in range are accepted whatever the geometry
    (a PSLG does not check crossings)."""
    n = len(points)
    pairs = st.tuples(st.integers(0, n - 1), st.integers(0, n - 1)).filter(
        lambda pair: pair[0] != pair[1])
    segments = [(u, v, data.draw(st.integers(-3, 3)))
                for u, v in data.draw(st.lists(pairs, max_size=10))]
    pslg = PSLG(vertices=points, segments=segments)
    assert pslg.segments == tuple(segments)


@FEW
@given(pslgs())
def test_generated_pslgs_rebuild_to_equal_values(pslg: PSLG) -> None:
    """The strategy's PSLGs are valid values: rebuilding one from its fields gives an equal
    PSLG, every segment joins two distinct existing vertices, and every hole seed is a
    point apart from the vertices."""
    again = PSLG(
        vertices=list(pslg.vertices), segments=list(pslg.segments), holes=list(pslg.holes),
        regions=list(pslg.regions), vertex_markers=list(pslg.vertex_markers),
        vertex_attributes=list(pslg.vertex_attributes),
    )
    assert again == pslg
    n = len(pslg.vertices)
    assert all(0 <= u < n and 0 <= v < n and u != v for u, v, _ in pslg.segments)
    assert all(hole not in pslg.vertices for hole in pslg.holes)
    assert len(set(pslg.vertices)) == n
