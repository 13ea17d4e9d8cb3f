"""The control-volume file and `octree --voronoi` (issue 23, item 4): written exactly,
read back to the same volumes and couplings, the volumes summing to the box's volume; a
mesh that is not Delaunay refused with nothing written; a bad file named by its line."""

from __future__ import annotations

import json
import os
from fractions import Fraction
from pathlib import Path

import pytest

from geomexact.cli import main
from geomexact.errors import FormatError
from geomexact.io.control_volumes import read_control_volumes, write_control_volumes
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.octree.pipeline import generate
from geomexact.mesh3d.octree.stages import BoxGrid, RefineWhere
from geomexact.mesh3d.voronoi import control_volumes


def test_a_file_reads_back_to_the_same_values(tmp_path: Path) -> None:
    box = Box((0, 0, 0), (1, Fraction(1, 3), Fraction(2, 3)))
    mesh = generate(box, initial=BoxGrid(1, 1, 1), refinement=RefineWhere(2),
                    trace=False).mesh
    volumes = control_volumes(mesh)
    write_control_volumes(tmp_path / "m.cv", mesh, volumes)
    read, couplings = read_control_volumes(tmp_path / "m.cv")
    assert read == volumes.volumes
    assert couplings == {face.edge: face.coupling for face in volumes.faces}
    assert sum(read.values()) == Fraction(2, 9)


def test_octree_voronoi_writes_the_volumes(capsys: pytest.CaptureFixture[str],
                                          tmp_path: Path) -> None:
    code = main(["octree", "--level", "2", "--box", "0", "0", "0", "2", "1", "1",
                 "--voronoi", str(tmp_path / "c.cv"), "--json"])
    report = json.loads(capsys.readouterr().out)
    assert code == 0 and report["voronoi"]["total"] == "2"
    assert report["voronoi"]["inadequate_faces"] == 0
    volumes, _ = read_control_volumes(tmp_path / "c.cv")
    assert len(volumes) == report["vertices"] and sum(volumes.values()) == 2


def test_octree_voronoi_refuses_a_mesh_that_is_not_delaunay(
        capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """Refined near a ball the octree's tetrahedra are not Delaunay: exit 2, one line,
    neither the mesh nor the volumes written."""
    code = main(["octree", "--level", "3", "--refine-sphere", "0", "0", "0", "0.5",
                 "-o", str(tmp_path / "m.ele"), "--voronoi", str(tmp_path / "c.cv")])
    err = capsys.readouterr().err
    assert code == 2 and "--voronoi: the mesh is not Delaunay" in err
    assert err.count("\n") == 1 and os.listdir(tmp_path) == []


@pytest.mark.parametrize(("text", "line"), [
    ("# something else\n", 1),
    ("# geomexact control volumes 1\nvertices x\n", 2),
    ("# geomexact control volumes 1\nvertices 1\n0 0 0 0 one\nfaces 0\n", 3),
    ("# geomexact control volumes 1\nvertices 1\n0 0 0 0 1\nfaces 1\n0 1 0 0\n", 5),
])
def test_a_bad_file_is_named_by_its_line(tmp_path: Path, text: str, line: int) -> None:
    (tmp_path / "bad.cv").write_text(text)
    with pytest.raises(FormatError) as caught:
        read_control_volumes(tmp_path / "bad.cv")
    assert caught.value.line == line


def test_a_short_file_is_refused(tmp_path: Path) -> None:
    (tmp_path / "short.cv").write_text("# geomexact control volumes 1\nvertices 2\n0 0 0 0 1\n")
    with pytest.raises(FormatError, match="ends before"):
        read_control_volumes(tmp_path / "short.cv")
