"""Polyhedral Delaunay cells (issue 23, items 2 and 3): co-spherical tetrahedra grouped
exactly; a cuboid without Steiner points is one cell, one Steiner point on an edge gives
the four pyramids met's Patterns module names, one on a face five; the cells partition
the tetrahedra, every cell's vertices lie on one sphere, and the census counts shapes up
to the cube's symmetries."""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from geomexact.errors import PreconditionError
from geomexact.kernel.predicate_results import SphereLocation
from geomexact.kernel.predicates3d import insphere
from geomexact.mesh3d.cospherical import polyhedral_cells
from geomexact.mesh3d.cuboid.polyhedral_census import pattern_cells, polyhedral_census
from geomexact.mesh3d.measures import tetrahedron_volume
from geomexact.mesh3d.transient import mesh3_from_tetrahedra


def test_a_cube_without_steiner_points_is_one_cell() -> None:
    mesh, cells = pattern_cells(0)
    assert len(mesh.tetrahedra()) == 5 and len(cells) == 1
    assert len(cells[0].vertices) == 8 and not cells[0].is_tetrahedron


@pytest.mark.parametrize("bit", range(12))
def test_one_steiner_point_on_an_edge_gives_four_pyramids(bit: int) -> None:
    """Arancibia (2007): "a 1-irregular cuboid with only one edge carrying a Steiner
    point ... gives a list of four pyramids"."""
    _, cells = pattern_cells(1 << bit)
    assert [len(cell.vertices) for cell in cells] == [5, 5, 5, 5]


@pytest.mark.parametrize("bit", range(12, 18))
def test_one_steiner_point_on_a_face_gives_five_pyramids(bit: int) -> None:
    _, cells = pattern_cells(1 << bit)
    assert [len(cell.vertices) for cell in cells] == [5, 5, 5, 5, 5]


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=0, max_value=2 ** 18 - 1))
def test_cells_partition_the_tetrahedra_and_are_cospherical(pattern: int) -> None:
    mesh, cells = pattern_cells(pattern)
    grouped = sorted(t for cell in cells for t in cell.tetrahedra)
    assert grouped == sorted(mesh.iter_tetrahedra())
    assert sum(tetrahedron_volume(mesh, t) for t in grouped) == 1
    for cell in cells:
        first = [mesh.point(v) for v in cell.tetrahedra[0]]
        for vertex in set(cell.vertices) - set(cell.tetrahedra[0]):
            assert insphere(*first, mesh.point(vertex)) == SphereLocation.COSPHERICAL


def test_a_mesh_that_is_not_delaunay_is_refused() -> None:
    points = [(0, 0, 0), (4, 0, 0), (0, 4, 0), (1, 1, 1), (1, 1, -1)]
    mesh = mesh3_from_tetrahedra(points, [(0, 1, 2, 3), (0, 2, 1, 4)], orient=True)
    with pytest.raises(PreconditionError, match="not Delaunay"):
        polyhedral_cells(mesh)


def test_the_census_counts_shapes_up_to_the_cubes_symmetries() -> None:
    """The twelve one-edge patterns make 48 pyramids of at most two shapes (the
    symmetries identify the rest); the census is the same run twice."""
    edges = polyhedral_census([1 << bit for bit in range(12)])
    assert edges.cells == 48 and edges.cells_per_pattern == {4: 12}
    assert sum(edges.shapes.values()) == 48 and len(edges.shapes) <= 2
    first, second = polyhedral_census(range(64)), polyhedral_census(range(64))
    assert first == second and first.tetrahedra >= first.cells


def test_a_cuboid_of_unequal_sides_keeps_fewer_symmetries() -> None:
    """On a 1 x 1 x 2 box the long axis is not exchanged with the others."""
    from geomexact.mesh3d.cuboid.boxes import Box

    box = Box((0, 0, 0), (1, 1, Fraction(2)))
    census = polyhedral_census([1 << bit for bit in range(12)], box)
    assert census.cells_per_pattern and census.cells == sum(census.shapes.values())


def test_cuboid_reports_its_cells(capsys: pytest.CaptureFixture[str]) -> None:
    """geomexact cuboid 1 --improve --allow-boundary-flips --json: four cells of five
    vertices; without the boundary flips the mesh is not Delaunay: null."""
    import json

    from geomexact.cli import main

    assert main(["cuboid", "1", "--improve", "--allow-boundary-flips", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["cells"] == [5, 5, 5, 5]
    assert main(["cuboid", "1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["cells"] is None


def test_census_cells_counts_and_writes_the_shapes(capsys: pytest.CaptureFixture[str],
                                                   tmp_path: Path) -> None:
    """census --cells over the one-edge patterns: 48 cells, the CSV's counts add up."""
    import json

    from geomexact.cli import main

    patterns = ",".join(str(1 << bit) for bit in range(12))
    out = tmp_path / "cells.csv"
    assert main(["census", "--cells", "--patterns", patterns, "--workers", "1",
                 "-o", str(out), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["cells"] == 48 and report["cells_per_pattern"] == {"4": 12}
    rows = out.read_text().splitlines()[1:]
    assert sum(int(row.split(",")[1]) for row in rows) == 48
    assert main(["census", "--cells", "--patterns", "1", "-o", str(tmp_path / "x.txt")]) == 2
