"""``geomexact octree --final mixed|polyhedral`` and ``geomexact cuboid P --final …``
(issue 23, item 6): counts by kind, the exact check, files meshio reads back with the
same cells and the level of each, traces that ``replay`` checks, control volumes of the
polyhedral final, and the refusals (nothing written)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from helpers.command import run
from helpers.mixed_files import meshio_cells

from geomexact import io
from geomexact.mesh3d.mixed.snapshot import MixedMesh3

meshio = pytest.importorskip("meshio")

SHELL = ["--level", "3", "--refine-sphere", "1/2", "1/2", "1/2", "3/10", "--surface"]


@pytest.mark.parametrize("final", ["mixed", "polyhedral"])
def test_octree_cell_final_reports_writes_and_replays(
        capsys: pytest.CaptureFixture[str], tmp_path: Path, final: str) -> None:
    out, trace, start = tmp_path / "m.vtu", tmp_path / "m.trace", tmp_path / "s.ele"
    code, text, err = run(capsys, "octree", *SHELL, "--level", "4", "--final", final, "-o", out,
                          "--trace", trace, "--start", start, "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["final"] == final and report["conforming"] is True
    assert sum(report["cells_by_kind"].values()) == report["cells"]
    assert report["volume"] == "1" and report["steps"] == report["cells"] + report[
        "added_points"]
    assert sum(report["templates"].values()) == report["leaves"]
    assert ("polyhedra" in report["cells_by_kind"]) == (final == "polyhedral")
    # meshio reads the same cells (polyhedra beside other cells: with geomexact's fix of
    # its VTU reader), with the kind and the leaf level of each, in cell_list() order
    mesh = io.read(out)
    assert isinstance(mesh, MixedMesh3) and mesh.cell_count == report["cells"]
    cells, arrays = meshio_cells(out)
    assert cells == mesh.cell_list()
    assert [int(k) for k in arrays["kind"]] == [int(cell.kind) for cell in cells]
    assert set(arrays["level"]) == {int(level) for level in report["levels"]}
    # every point is a double (added points are quarter-lattice): the file is exact
    assert mesh.digest_text == report["digest"]
    # the trace replays on the start (the vertices) to the same digest
    code, text, err = run(capsys, "replay", start, trace, "-o", tmp_path / "r.vtu", "--json")
    assert code == 0, err
    replayed = json.loads(text)
    assert replayed["final_digest"] == report["digest"] and replayed["cells"] == report["cells"]
    code, text, _ = run(capsys, "trace", "show", trace, "--input", start, "--check")
    assert code == 0 and "add_cell" in text
    code, _, err = run(capsys, "trace", "bisect", start, trace, "--fails", "valid")
    assert code == 2 and "mixed-cell mesh" in err


def test_polyhedral_final_writes_control_volumes(capsys: pytest.CaptureFixture[str],
                                                 tmp_path: Path) -> None:
    cv = tmp_path / "p.cv"
    code, text, err = run(capsys, "octree", *SHELL, "--final", "polyhedral", "--voronoi", cv,
                          "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["voronoi"]["total"] == "1" and report["voronoi"]["inadequate_faces"] == 0
    assert report["voronoi"]["vertices"] == report["vertices"]
    assert cv.read_text().startswith("# geomexact control volumes 1")


def test_voronoi_on_a_cell_final_that_is_not_delaunay_writes_nothing(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """Leaves three times as tall as wide: each leaf's cells are Delaunay, their union
    is not (a circumsphere reaches into the next leaf), and the exact check says so."""
    out, cv = tmp_path / "m.vtu", tmp_path / "m.cv"
    code, _, err = run(capsys, "octree", "--box", "0", "0", "0", "1", "1", "3", "--level", "3",
                       "--refine-sphere", "0", "0", "0", "1/2", "--final", "polyhedral",
                       "-o", out, "--voronoi", cv)
    assert code == 2 and "not Delaunay" in err and "when the leaves are cubes" in err
    assert list(tmp_path.iterdir()) == []


def test_unknown_final_and_tetrahedral_formats_are_refused(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    code, _, err = run(capsys, "octree", "--final", "hexes")
    assert code == 2 and "invalid choice" in err
    code, _, err = run(capsys, "octree", "--final", "mixed", "-o", tmp_path / "m.ele")
    assert code == 2 and "not a mixed mesh" in err
    code, _, err = run(capsys, "cuboid", "3", "--final", "mixed", "--improve")
    assert code == 2 and "--improve" in err
    assert list(tmp_path.iterdir()) == []


def test_cuboid_cell_finals(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    code, text, _ = run(capsys, "cuboid", "1", "--final", "mixed", "--json")
    report = json.loads(text)
    assert code == 0 and report["cells_by_kind"] == {"pyramids": 4}
    assert report["template"] == "star" and report["valid"] is True
    code, text, _ = run(capsys, "cuboid", "0", "--final", "polyhedral", "--json")
    assert json.loads(text)["cells_by_kind"] == {"hexahedra": 1}
    out, trace = tmp_path / "c.vtu", tmp_path / "c.trace"
    code, text, err = run(capsys, "cuboid", "4111", "--final", "polyhedral", "--shape", "2",
                          "1", "1", "-o", out, "--trace", trace, "--json")
    assert code == 0, err
    report = json.loads(text)
    assert report["volume"] == "2" and "polyhedra" in report["cells_by_kind"]
    # replayed without INPUT: the start is rebuilt from the trace's parameters
    code, text, err = run(capsys, "replay", trace, "-o", tmp_path / "r.vtu", "--json")
    assert code == 0, err
    assert json.loads(text)["final_digest"] == report["digest"]
    code, text, _ = run(capsys, "cuboid", "4111", "--final", "delaunay", "--json")
    assert code == 0 and json.loads(text)["flips"] is not None
