"""The mesh checker (``geomexact.mesh2d.validation``): each invariant of
``specs/snapshot.md``, broken in a mesh built by hand, is reported with its kind and the
elements involved; valid meshes give ``[]``; ``check`` raises ``InvalidMeshError``."""

from __future__ import annotations

from collections.abc import Iterable

import attrs
import immutables
import pytest
from hypothesis import given, settings

from geomexact.errors import InvalidMeshError, Violation
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.snapshot import Mesh2, full_digest
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.mesh2d import validation
from geomexact.mesh2d.validation import check, validate
from geomexact.strategies import triangulations

FEW = settings(max_examples=min(settings().max_examples, 40))


@pytest.fixture(autouse=True, params=["scalar", "arrays"])
def checker(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    """Every test runs twice: small meshes with the element-by-element checker (as
    ``validate`` checks them), then every mesh on arrays (as ``validate`` checks large
    ones): the same violations in the same order."""
    if request.param == "arrays":
        monkeypatch.setattr(validation, "_VECTORISED_FROM", 0)

Triple = tuple[int, int, int]


def raw_mesh(
    points: dict[int, tuple[object, object]] | list[tuple[object, object]],
    triangles: Iterable[Triple],
    **fields: object,
) -> Mesh2:
    """A Mesh2 made directly from its tables, trusting every input (no checks): the
    half-edges of ``triangles`` as given, a hint for each vertex of a triangle, the given
    triangle count, then ``fields`` replaced, and the digest recomputed (so that it is no
    violation unless a test says so)."""
    table = dict(enumerate(points)) if isinstance(points, list) else dict(points)
    halfedges: dict[tuple[int, int], int] = {}
    outgoing: dict[int, int] = {}
    count = 0
    for a, b, c in triangles:
        halfedges[(a, b)], halfedges[(b, c)], halfedges[(c, a)] = c, a, b
        outgoing.update({a: b, b: c, c: a})
        count += 1
    mesh = Mesh2(
        vertices=immutables.Map({i: point2(*p) for i, p in table.items()}),
        halfedges=immutables.Map(halfedges),
        outgoing=immutables.Map(outgoing),
        segments=immutables.Map(),
        vertex_markers=immutables.Map(),
        vertex_attributes=immutables.Map(),
        triangle_attributes=immutables.Map(),
        triangle_count=count,
        digest=0,
    )
    mesh = attrs.evolve(mesh, **fields)
    return attrs.evolve(mesh, digest=full_digest(mesh))


SQUARE = [(0, 0), (1, 0), (1, 1), (0, 1)]


def kinds(violations: list[Violation]) -> list[str]:
    return [violation.kind for violation in violations]


def annulus() -> Mesh2:
    """The square [0, 3]^2 with the square hole [1, 2]^2, in eight triangles."""
    return mesh_from_triangles(
        [(0, 0), (3, 0), (3, 3), (0, 3), (1, 1), (2, 1), (2, 2), (1, 2)],
        [(0, 1, 5), (0, 5, 4), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4),
         (3, 4, 7)],
    )


# -- valid meshes -----------------------------------------------------------------------------
@FEW
@given(triangulations(max_steps=20))
def test_meshes_made_by_the_ops_are_valid(mesh: Mesh2) -> None:
    """Every mesh made by random valid steps has no violation, and check returns it."""
    assert validate(mesh) == []
    assert validate(mesh, allow_isolated=False) == []
    assert check(mesh) is mesh


def two_copies(mesh: Mesh2, dx: object) -> Mesh2:
    """``mesh`` and a copy of it moved by (dx, 0), as one mesh."""
    n = mesh.vertex_count
    points = [(p.x, p.y) for _, p in sorted(mesh.vertices.items())]
    moved = [(x + dx, y) for x, y in points]  # type: ignore[operator]
    triangles = mesh.triangles()
    copy = [(a + n, b + n, c + n) for a, b, c in triangles]
    return mesh_from_triangles(points + moved, triangles + copy)


@FEW
@given(triangulations(max_steps=10))
def test_a_disjoint_copy_is_valid_and_a_coincident_copy_overlaps(mesh: Mesh2) -> None:
    """Two copies of a mesh side by side are a valid mesh of two components; two copies on
    the same points (different ids) overlap."""
    xs = [p.x for p in mesh.vertices.values()]
    width = max(xs) - min(xs)
    assert validate(two_copies(mesh, width + mpq(1, 1000))) == []
    assert "overlap" in kinds(validate(two_copies(mesh, 0)))


def test_raw_mesh_of_a_proper_square_is_valid() -> None:
    """The hand builder itself makes valid meshes from proper tables (so the violations
    below come from what each test breaks)."""
    mesh = raw_mesh(SQUARE, [(0, 1, 2), (0, 2, 3)])
    assert validate(mesh) == []
    assert mesh == mesh_from_triangles(SQUARE, [(0, 1, 2), (0, 2, 3)])


def test_a_mesh_with_a_hole_and_an_island_in_it_is_valid() -> None:
    """An annulus, and a triangle lying inside its hole (a second component that overlaps
    nothing), are valid; the empty mesh and bare vertices too."""
    ring = annulus()
    assert validate(ring) == []
    island = raw_mesh(
        {**{i: (p.x, p.y) for i, p in ring.vertices.items()},
         8: (mpq(5, 4), mpq(5, 4)), 9: (mpq(7, 4), mpq(5, 4)), 10: (mpq(3, 2), mpq(7, 4))},
        [*ring.triangles(), (8, 9, 10)],
    )
    assert validate(island) == []
    assert validate(raw_mesh([], [])) == []
    assert validate(raw_mesh(SQUARE, [])) == []


# -- one test per invariant -------------------------------------------------------------------
def test_vertex_ids_must_be_0_to_n_minus_1() -> None:
    """Ids with a gap are reported as vertex-ids."""
    mesh = raw_mesh({0: (0, 0), 1: (1, 0), 2: (0, 1), 5: (3, 3)}, [(0, 1, 2)])
    assert kinds(validate(mesh)) == ["vertex-ids"]


def test_half_edges_must_refer_to_existing_vertices() -> None:
    """Each half-edge of a triangle on a missing vertex is reported with its ids."""
    mesh = raw_mesh(SQUARE[:3], [(0, 1, 9)], triangle_count=0)
    found = validate(mesh)
    assert kinds(found) == ["missing-vertex"] * 3
    assert all(9 in violation.elements for violation in found)


def test_the_half_edges_of_a_triangle_must_agree() -> None:
    """(u, v) -> w requires (v, w) -> u and (w, u) -> v."""
    mesh = raw_mesh(SQUARE, [], halfedges=immutables.Map({(0, 1): 2, (1, 2): 0, (2, 0): 3}))
    found = validate(mesh)
    assert kinds(found) == ["adjacency"] * 3
    assert found[0].elements == (0, 1, 2)


def test_triangles_must_be_counter_clockwise() -> None:
    """A clockwise triangle is reported as clockwise."""
    found = validate(raw_mesh(SQUARE, [(0, 2, 1)]))
    assert kinds(found) == ["orientation"]
    assert "clockwise" in found[0].message and found[0].elements == (0, 2, 1)


def test_triangles_must_not_be_degenerate() -> None:
    """A triangle on three collinear points (here exactly collinear far below double
    precision) is reported as degenerate."""
    tiny = mpq(1, 2**200)
    found = validate(raw_mesh([(0, 0), (1, tiny), (2, 2 * tiny)], [(0, 1, 2)]))
    assert kinds(found) == ["orientation"] and "degenerate" in found[0].message


def test_triangle_count_must_match() -> None:
    """A wrong triangle_count is reported."""
    mesh = raw_mesh(SQUARE, [(0, 1, 2), (0, 2, 3)], triangle_count=3)
    found = validate(mesh)
    assert kinds(found) == ["triangle-count"] and "3" in found[0].message


@pytest.mark.parametrize(
    "outgoing", [{1: 2, 2: 0, 3: 0}, {0: 9, 1: 2, 2: 0, 3: 0}, {0: 3, 1: 2, 2: 0, 3: 0}],
    ids=["missing", "to a missing vertex", "not a half-edge"],
)
def test_every_vertex_of_a_triangle_needs_a_valid_hint(outgoing: dict[int, int]) -> None:
    """A missing hint, a hint to a missing vertex, or a hint that is no half-edge ((0, 3)
    is only the twin of a boundary half-edge) is reported for vertex 0."""
    mesh = raw_mesh(SQUARE, [(0, 1, 2), (0, 2, 3)], outgoing=immutables.Map(outgoing))
    found = validate(mesh)
    assert kinds(found) == ["outgoing"] and found[0].elements == (0,)


def test_any_half_edge_is_a_valid_hint() -> None:
    """The hint may be any w with (vertex, w) a half-edge: 0 -> 1 and 0 -> 2 both do."""
    for hint in (1, 2):
        outgoing = immutables.Map({0: hint, 1: 2, 2: 0, 3: 0})
        assert validate(raw_mesh(SQUARE, [(0, 1, 2), (0, 2, 3)], outgoing=outgoing)) == []


def test_isolated_vertices_are_reported_only_when_asked() -> None:
    """A vertex in no triangle is legal by default and reported with allow_isolated=False.
    """
    mesh = raw_mesh([*SQUARE, (5, 5)], [(0, 1, 2), (0, 2, 3)])
    assert validate(mesh) == []
    found = validate(mesh, allow_isolated=False)
    assert kinds(found) == ["isolated-vertex"] and found[0].elements == (4,)


def test_boundary_edges_must_form_closed_loops() -> None:
    """A stray half-edge leaves the boundary open at its two ends."""
    mesh = raw_mesh(SQUARE, [(0, 1, 2)])
    mesh = attrs.evolve(mesh, halfedges=mesh.halfedges.set((2, 3), 0))
    found = validate(mesh, check_digest=False)
    loops = [v for v in found if v.kind == "boundary-loop"]
    assert sorted(v.elements for v in loops) == [(2,), (3,)]


def test_boundary_loops_must_not_touch_at_a_vertex() -> None:
    """Two triangles sharing only a vertex (a bowtie) make it non-manifold."""
    mesh = raw_mesh([(0, 0), (1, -1), (1, 1), (-1, 1), (-1, -1)], [(0, 1, 2), (0, 3, 4)])
    found = validate(mesh)
    assert kinds(found) == ["non-manifold-vertex"] and found[0].elements == (0,)


def test_constrained_segments_must_be_edges() -> None:
    """A segment across the square's other diagonal is no edge of the mesh."""
    mesh = raw_mesh(SQUARE, [(0, 1, 2), (0, 2, 3)], segments=immutables.Map({(1, 3): 1}))
    found = validate(mesh)
    assert kinds(found) == ["segment"] and found[0].elements == (1, 3)


def test_markers_and_attributes_must_refer_to_existing_elements() -> None:
    """Attributes of a missing triangle, and a marker and attributes of a missing vertex,
    are each reported."""
    mesh = raw_mesh(
        SQUARE, [(0, 1, 2), (0, 2, 3)],
        triangle_attributes=immutables.Map({(0, 1, 3): (mpq(1),)}),
        vertex_markers=immutables.Map({7: 1}),
        vertex_attributes=immutables.Map({8: (mpq(2),)}),
    )
    found = validate(mesh)
    assert kinds(found) == ["attribute"] * 3
    assert [v.elements for v in found] == [(0, 1, 3), (7,), (8,)]


def test_an_interior_star_must_turn_exactly_once() -> None:
    """Seven triangles around a vertex turning 720/7 degrees each (a heptagram fan) are all
    counter-clockwise and every interior edge has two triangles, but the star turns twice:
    fold-over."""
    # angles 0, 103, 206, 309, 51, 154, 257 degrees
    ring = [(100, 0), (-22, 97), (-90, -43), (62, -78), (62, 78), (-90, 43), (-22, -97)]
    mesh = mesh_from_triangles([(0, 0), *ring], [(0, i, i % 7 + 1) for i in range(1, 8)])
    found = validate(mesh)
    assert "fold-over" in kinds(found)
    assert (0,) in [v.elements for v in found if v.kind == "fold-over"]


def test_a_boundary_fan_must_turn_less_than_once() -> None:
    """Four triangles around a boundary vertex turning 100 degrees each (400 in all): each
    is proper, but the fan overlaps itself: fold-over at that vertex."""
    # angles 0, 100, 200, 300, 40 degrees
    ring = [(100, 0), (-17, 98), (-94, -34), (50, -87), (77, 64)]
    mesh = mesh_from_triangles([(0, 0), *ring], [(0, i, i + 1) for i in range(1, 5)])
    found = validate(mesh)
    assert "fold-over" in kinds(found)
    assert (0,) in [v.elements for v in found if v.kind == "fold-over"]


def test_boundary_edges_must_not_cross() -> None:
    """Two triangles overlapping partly: their boundary edges cross (overlap)."""
    mesh = raw_mesh([(0, 0), (4, 0), (0, 4), (1, 1), (5, 1), (1, 5)], [(0, 1, 2), (3, 4, 5)])
    found = validate(mesh)
    assert set(kinds(found)) == {"overlap"}
    assert any({1, 2} <= set(v.elements) for v in found)


def test_a_component_must_not_lie_on_another() -> None:
    """A small triangle inside a big one: no boundary edges cross, but the small
    component's vertex lies in the big one's triangle (overlap)."""
    mesh = raw_mesh([(0, 0), (10, 0), (0, 10), (1, 1), (2, 1), (1, 2)],
                    [(0, 1, 2), (3, 4, 5)])
    found = validate(mesh)
    assert kinds(found) == ["overlap"]
    assert found[0].elements == (3, 0, 1, 2)


def test_the_digest_must_equal_its_recomputation() -> None:
    """A digest that is off by one is reported unless check_digest is false."""
    mesh = mesh_from_triangles(SQUARE, [(0, 1, 2), (0, 2, 3)])
    wrong = attrs.evolve(mesh, digest=(mesh.digest + 1) % (1 << 128))
    assert kinds(validate(wrong)) == ["digest"]
    assert validate(wrong, check_digest=False) == []


# -- reporting --------------------------------------------------------------------------------
def test_every_violation_is_reported_in_a_deterministic_order() -> None:
    """Several broken invariants are all reported, in the order of the invariants, the
    same on every call."""
    mesh = raw_mesh(
        SQUARE, [(0, 2, 1)],
        triangle_count=5,
        segments=immutables.Map({(1, 3): 0}),
        vertex_markers=immutables.Map({9: 1}),
    )
    mesh = attrs.evolve(mesh, digest=mesh.digest ^ 1)
    found = validate(mesh)
    assert kinds(found) == ["orientation", "triangle-count", "segment", "attribute", "digest"]
    assert validate(mesh) == found


def test_a_violation_reads_kind_colon_message() -> None:
    """str(violation) is "kind: message"."""
    violation = Violation("segment", "constrained segment (1, 3) is not an edge", (1, 3))
    assert str(violation) == "segment: constrained segment (1, 3) is not an edge"


def test_check_raises_with_every_violation() -> None:
    """check raises InvalidMeshError holding the same violations as validate, and names the
    first in its message."""
    mesh = raw_mesh(SQUARE, [(0, 2, 1)], triangle_count=2)
    with pytest.raises(InvalidMeshError) as caught:
        check(mesh)
    assert caught.value.violations == tuple(validate(mesh))
    assert len(caught.value.violations) == 2
    assert str(caught.value.violations[0]) in str(caught.value)
    assert isinstance(caught.value, ValueError)
