"""The exact surface checks: each kind of problem found on a constructed surface with
its ids, the good surfaces pass, inward ones are turned outward, two surfaces' meeting
triangles found, the shared surfaces judged (fandisk and spot good; bunny and woody open
with 223 and 119 boundary edges), and fandisk's enclosed volume against plain
``fractions``."""

from __future__ import annotations

import time
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from helpers.surface_cases import CASES, cube, tetrahedron, torus
from hypothesis import given
from hypothesis import strategies as st

from geomexact.errors import FormatError
from geomexact.io.surface_files import read_surface
from geomexact.mesh3d.surface import (
    TriangleSurface,
    check_surface,
    oriented_outward,
    surface_problems,
    surfaces_intersect,
    triangle_surface,
)


def kinds(surface: TriangleSurface) -> list[str]:
    return [problem.kind for problem in surface_problems(surface)]


def edited(surface: TriangleSurface, rows: list[list[int]],
           points: list[object] | None = None) -> TriangleSurface:
    return triangle_surface(list(surface.points) + (points or []), rows)


@pytest.mark.parametrize("case", sorted(CASES))
def test_good_surfaces_have_no_problem(case: str) -> None:
    surface = CASES[case]()
    assert surface_problems(surface) == []
    check_surface(surface, "good.obj")
    assert surface.enclosed_volume() > 0


def test_torus_is_genus_one() -> None:
    """V - E + F = 0 for the torus case."""
    surface = torus()
    assert surface.vertex_count - surface.triangle_count * 3 // 2 + surface.triangle_count == 0


def test_degenerate_triangles_repeated_and_collinear() -> None:
    base = cube()
    rows = [*base.triangles.tolist(), [0, 0, 1], [0, 1, 8]]
    surface = edited(base, rows, [(2, 0, 0)])  # point 8 on the line of 0 and 1
    found = [p for p in surface_problems(surface) if p.kind == "degenerate-triangle"]
    assert [p.elements for p in found] == [(12,), (13,)]
    assert "repeated vertex" in found[0].message and "collinear" in found[1].message


def test_boundary_edges_are_listed_as_their_triangle_orders_them() -> None:
    rows = cube().triangles.tolist()[:-1]
    found = [p for p in surface_problems(edited(cube(), rows)) if p.kind == "boundary-edge"]
    assert sorted(p.elements for p in found) == [(1, 5), (5, 7), (7, 1)]


def test_non_manifold_edge() -> None:
    """A fin on the cube's edge (0, 1): three triangles on it."""
    rows = [*cube().triangles.tolist(), [0, 1, 8], [1, 0, 8]]
    found = surface_problems(edited(cube(), rows, [(Fraction(1, 2), -1, -1)]))
    assert [p.elements for p in found if p.kind == "non-manifold-edge"] == [(0, 1)]


def test_non_manifold_vertex() -> None:
    """Two tetrahedra sharing one vertex only: a bow tie at vertex 0."""
    tetra = tetrahedron()
    points = [*tetra.points, (-1, 0, 0), (0, -1, 0), (0, 0, -1)]
    rows = [*tetra.triangles.tolist(), [0, 4, 5], [0, 6, 4], [0, 5, 6], [4, 6, 5]]
    found = surface_problems(triangle_surface(points, rows))
    assert [(p.kind, p.elements) for p in found] == [("non-manifold-vertex", (0,))]


def test_inconsistent_orientation() -> None:
    rows = cube().triangles.tolist()
    rows[3] = rows[3][::-1]
    found = [p for p in surface_problems(edited(cube(), rows))
             if p.kind == "inconsistent-orientation"]
    assert len(found) == 3
    assert all(set(p.elements) <= set(rows[3]) for p in found)


def test_inward_orientation_and_oriented_outward() -> None:
    inward = torus().reversed()
    assert kinds(inward) == ["inward-orientation"]
    outward, flipped = oriented_outward(inward)
    assert flipped and surface_problems(outward) == []
    assert oriented_outward(outward)[1] is False
    opened = edited(cube(), cube().reversed().triangles.tolist()[:-1])
    assert oriented_outward(opened) == (opened, False)


def test_self_intersection_of_two_crossing_boxes() -> None:
    """Two overlapping cubes in one surface: crossing triangles reported in pairs."""
    other = cube(Fraction(1, 2))
    surface = triangle_surface(cube().points + other.points,
                               np.concatenate([cube().triangles, other.triangles + 8]))
    found = [p for p in surface_problems(surface) if p.kind == "self-intersection"]
    assert found and all(p.elements[0] < 12 <= p.elements[1] for p in found)
    assert kinds(surface) == ["self-intersection"] * len(found)


def test_touching_at_a_point_counts_for_disjoint_ids() -> None:
    """Two cubes touching at the corner (1, 1, 1) (no shared id) intersect; sharing the
    corner's id and nothing else they are a non-manifold vertex, not an intersection."""
    far = cube(Fraction(1))
    assert surfaces_intersect(cube(), far)
    assert surfaces_intersect(cube(), cube(Fraction(2))) == []
    joined = triangle_surface(cube().points + far.points,
                              np.concatenate([cube().triangles, far.triangles + 8]))
    assert set(kinds(joined)) == {"self-intersection"}


def test_shared_edge_folds_and_shared_vertex_overlaps_are_caught() -> None:
    """Coplanar triangles on one side of a shared edge overlap; a triangle through the
    plane of its neighbour at a shared vertex pierces it; those that only touch along the
    shared part do not."""
    points = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (1, 1, 0), (1, 1, 1), (3, 3, -1),
              (-1, -1, 1), (0, -4, 0)]
    fold = triangle_surface(points, [[0, 1, 2], [1, 0, 3]])
    assert [p.elements for p in surface_problems(fold) if p.kind == "self-intersection"] \
        == [(0, 1)]
    flat = triangle_surface(points, [[0, 1, 2], [1, 0, 7]])
    assert "self-intersection" not in kinds(flat)
    pierce = triangle_surface(points, [[0, 1, 2], [0, 4, 5]])
    assert "self-intersection" in kinds(pierce)
    apart = triangle_surface(points, [[0, 1, 2], [0, 4, 6]])
    assert "self-intersection" not in kinds(apart)
    wedge = triangle_surface(points, [[0, 1, 2], [0, 3, 7]])  # coplanar, overlapping at 0
    assert "self-intersection" in kinds(wedge)


def test_surfaces_intersect_finds_pairs_between_surfaces() -> None:
    pairs = surfaces_intersect(cube(), cube(Fraction(1, 2)))
    assert pairs and all(0 <= a < 12 and 0 <= b < 12 for a, b in pairs)
    assert surfaces_intersect(cube(), cube(Fraction(1, 4), Fraction(1, 2))) == []


def test_check_surface_words_each_problem_for_a_user() -> None:
    rows = cube().triangles.tolist()[:-1]
    with pytest.raises(FormatError) as caught:
        check_surface(edited(cube(), rows), "part.obj")
    text = str(caught.value)
    assert text.startswith("part.obj: the surface is not closed: 3 boundary edges, e.g. ")
    assert "a domain needs a closed surface" in text
    with pytest.raises(FormatError, match="face inward"):
        check_surface(torus().reversed(), "in.obj")


@st.composite
def closed_boxes(draw: st.DrawFn) -> TriangleSurface:
    """A random box with random rational extents, vertex ids permuted, triangles shuffled
    and each rotated: a closed convex surface, outward."""
    low = [draw(st.fractions(-10, 10, max_denominator=50)) for _ in range(3)]
    size = [draw(st.fractions(Fraction(1, 50), 10, max_denominator=50)) for _ in range(3)]
    box = cube()
    points = [tuple(low[k] + size[k] * Fraction(int(p[k])) for k in range(3))
              for p in box.points]
    order = draw(st.permutations(range(8)))
    new_id = {old: new for new, old in enumerate(order)}
    rows = [[new_id[v] for v in row] for row in box.triangles.tolist()]
    rows = draw(st.permutations(rows))
    turns = draw(st.lists(st.integers(0, 2), min_size=12, max_size=12))
    rows = [row[t:] + row[:t] for row, t in zip(rows, turns, strict=True)]
    return triangle_surface([points[old] for old in order], rows)


@given(closed_boxes(), st.integers(0, 11))
def test_random_boxes_pass_and_one_flipped_triangle_is_caught(
        surface: TriangleSurface, flipped: int) -> None:
    assert surface_problems(surface) == []
    rows = surface.triangles.tolist()
    rows[flipped] = rows[flipped][::-1]
    found = kinds(triangle_surface(surface.points, rows))
    assert found == ["inconsistent-orientation"] * 3


def _surfaces(shared_data: Path) -> Path:
    folder = shared_data / "surfaces"
    if not folder.is_dir():
        pytest.skip(f"no surfaces in {shared_data}")
    return folder


@pytest.mark.parametrize("name", ["fandisk.obj", "spot.obj"])
def test_shared_closed_surfaces_are_good(shared_data: Path, name: str) -> None:
    """Closed, 2-manifold, outward, no self-intersection; fandisk checked in seconds."""
    surface = read_surface(_surfaces(shared_data) / name)
    start = time.perf_counter()
    assert surface_problems(surface) == []
    assert time.perf_counter() - start < 30
    assert surface.enclosed_volume() > 0


@pytest.mark.parametrize(("name", "count"), [("stanford-bunny.obj", 223), ("woody.obj", 119)])
def test_shared_open_surfaces_are_refused_with_their_counts(
        shared_data: Path, name: str, count: int) -> None:
    surface = read_surface(_surfaces(shared_data) / name)
    found = kinds(surface)
    assert set(found) == {"boundary-edge"}
    assert len(found) == count
    with pytest.raises(FormatError, match=f"^{name}: the surface is not closed: {count} "
                       "boundary edges"):
        check_surface(surface, name)


def test_fandisk_volume_against_plain_fractions(shared_data: Path) -> None:
    """The enclosed volume recomputed from the file's text with ``fractions`` alone."""
    path = _surfaces(shared_data) / "fandisk.obj"
    points: list[tuple[Fraction, ...]] = []
    total = Fraction(0)
    with open(path) as handle:
        for line in handle:
            fields = line.split()
            if fields and fields[0] == "v":
                points.append(tuple(Fraction(text) for text in fields[1:4]))
            elif fields and fields[0] == "f":
                a, b, c = (points[int(ref.split("/")[0]) - 1] for ref in fields[1:4])
                total += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                          + a[2] * (b[0] * c[1] - b[1] * c[0]))
    volume = read_surface(path).enclosed_volume()
    assert Fraction(int(volume.numerator), int(volume.denominator)) == total / 6
