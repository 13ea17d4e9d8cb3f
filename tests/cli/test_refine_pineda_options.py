"""The refine options of Pineda's program that geomexact maps (docs/pineda-options.md):
--print-region, -o DIR with --filename, --polylla in that mode, --centred-rectangle."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from geomexact import io
from geomexact.cli import main
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import mesh_from_triangles


@pytest.fixture
def grid(tmp_path: Path) -> Path:
    """A 4 x 4 grid of squares, two triangles each."""
    points = [(x, y) for y in range(5) for x in range(5)]
    triangles = []
    for y in range(4):
        for x in range(4):
            a = 5 * y + x
            triangles += [(a, a + 1, a + 6), (a, a + 6, a + 5)]
    path = tmp_path / "grid.off"
    io.write(path, mesh_from_triangles(points, triangles))
    return path


def test_print_region_writes_the_selected_triangles(grid: Path, tmp_path: Path) -> None:
    """--print-region: the input's triangles with a vertex in the region."""
    region = tmp_path / "region.off"
    assert main(["refine", str(grid), "--max-area", "1/8", "--rectangle", "0", "0", "1",
                 "1", "--print-region", str(region)]) == 0
    mesh = io.read(region)
    assert isinstance(mesh, Mesh2)
    assert 2 <= mesh.triangle_count < 32


def test_output_directory_with_filename_and_polylla(
    grid: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """-o DIR/ --filename NAME --polylla: NAME.off, NAME_polylla.off and
    NAME_input_polylla.off in DIR, and as Pineda's program does (issue 26, item 8) the
    result's non-convex polygons (NAME_polylla_reflex.off, every vertex kept) and its
    convex decomposition (NAME_polylla_convex.off)."""
    out = tmp_path / "out"
    assert main(["refine", str(grid), "--max-area", "1/4", "-o", f"{out}/", "--filename",
                 "run1", "--polylla", "--json"]) == 0
    written = json.loads(capsys.readouterr().out)["written"]
    names = sorted(Path(path).name for path in written)
    assert names == ["run1.off", "run1_input_polylla.off", "run1_polylla.off",
                     "run1_polylla_convex.off", "run1_polylla_reflex.off"]
    assert isinstance(io.read(out / "run1_input_polylla.off"), PolygonMesh)
    polygons, reflex, convex = (io.read(out / f"run1_polylla{suffix}.off")
                                for suffix in ("", "_reflex", "_convex"))
    assert isinstance(polygons, PolygonMesh) and isinstance(convex, PolygonMesh)
    from geomexact.mesh2d.polygonal.polygon_mesh import nonconvex_polygons

    # an OFF without faces reads as an empty triangle mesh
    faces = reflex.polygons if isinstance(reflex, PolygonMesh) else ()
    assert reflex.vertex_count if isinstance(reflex, Mesh2) else len(reflex.vertices)
    assert sorted(faces) == sorted(polygons.polygons[index] for index in
                                   nonconvex_polygons(polygons))
    assert not nonconvex_polygons(convex)
    assert len(convex.polygons) >= len(polygons.polygons)


def test_filename_without_directory_and_bare_polylla_are_usage_errors(
    grid: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """One line each, exit 2."""
    assert main(["refine", str(grid), "--max-area", "1/4", "-o", str(tmp_path / "a.off"),
                 "--filename", "x"]) == 2
    assert main(["refine", str(grid), "--max-area", "1/4", "--polylla"]) == 2
    err = capsys.readouterr().err
    assert "--filename" in err and "--polylla" in err and "Traceback" not in err


def test_centred_rectangle_is_the_same_region(
    grid: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--centred-rectangle 2 2 2 2 selects what --rectangle 1 1 2 2 does."""
    results = []
    for region in (["--rectangle", "1", "1", "2", "2"],
                   ["--centred-rectangle", "2", "2", "2", "2"]):
        assert main(["refine", str(grid), "--max-area", "1/16", *region, "--json"]) == 0
        report = json.loads(capsys.readouterr().out)
        results.append((report["triangles"], report["region"]))
    assert results[0] == results[1]


def test_polylla_files_on_poisson_points_match_the_program(
    shared_data: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """500poisson.off, nothing to refine, --preset pineda --polylla -o DIR/: the program's
    76 non-convex polygons and its 306 + 93 convex ones."""
    source = shared_data / "polylla-refinement" / "500poisson.off"
    out = tmp_path / "p"
    assert main(["refine", str(source), "--max-area", "1", "--method", "centroid",
                 "--preset", "pineda", "--polylla", "-o", f"{out}/"]) == 0
    capsys.readouterr()
    reflex = io.read(out / "500poisson_polylla_reflex.off")
    convex = io.read(out / "500poisson_polylla_convex.off")
    assert isinstance(reflex, PolygonMesh) and isinstance(convex, PolygonMesh)
    assert len(reflex.polygons) == 76 and len(convex.polygons) == 306 + 93
