"""docs/octree.md as written: its Python examples run and give the numbers in their
comments, its pictures exist (each under 150 KB) and are linked from the guide's index."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

DOCS = Path(__file__).resolve().parents[2] / "docs"
GUIDE = DOCS / "octree.md"


def _blocks() -> list[str]:
    return re.findall(r"```python\n(.*?)```", GUIDE.read_text(encoding="utf-8"), re.S)


def test_python_examples_give_the_numbers_they_state() -> None:
    first, second = _blocks()
    space: dict[str, Any] = {}
    exec(first, space)  # the guide's own example
    run = space["run"]
    assert (run.mesh.tetrahedron_count, run.mesh.vertex_count) == (9_080, 2_005)
    assert run.octree.leaf_count == 1_416 and run.volume == 2
    assert (run.conformity.interior_faces, run.conformity.boundary_faces) == (17_832, 656)
    for stated in ("9,080 tetrahedra, 2,005 vertices", "1,416", "17,832", "656"):
        assert stated in first
    first_run = second.split("\nrun = ")
    assert len(first_run) == 3
    exec(first_run[0] + "\nrun = " + first_run[1], space)
    run = space["run"]
    assert run.octree.leaf_count == 1_996 and run.mesh.tetrahedron_count == 13_952
    assert run.leaf_mesh.forced_splits == 0
    assert dict(run.octree.levels()) == {2: 20, 3: 248, 4: 704, 5: 1024}
    exec(second, space)
    run = space["run"]
    assert (run.refined.leaf_count, run.leaf_mesh.forced_splits,
            run.octree.leaf_count) == (36, 31, 253)
    assert run.mesh.tetrahedron_count == 1_804
    assert "# 36, 31, 253" in second and "1,804 tetrahedra" in GUIDE.read_text()


def test_pictures_exist_are_small_and_linked() -> None:
    text = GUIDE.read_text(encoding="utf-8")
    pictures = re.findall(r"!\[[^\]]*\]\((images/[^)]+\.png)\)", text)
    assert len(pictures) == 6
    for name in pictures:
        path = DOCS / name
        assert path.is_file(), name
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert path.stat().st_size < 150 * 1024, name
    assert "(octree.md)" in (DOCS / "index.md").read_text(encoding="utf-8")
    assert "## octree" in (DOCS / "cli.md").read_text(encoding="utf-8")
    assert "(images/octree-sphere-surface.png)" in text


def test_stated_counts_of_the_ball() -> None:
    """The ball picture's caption, checked by the library (the level-6 sphere's counts
    are checked in tests/viz/test_octree_viewer_browser.py)."""
    from geomexact.mesh3d.cuboid.boxes import Box
    from geomexact.mesh3d.octree.pipeline import generate
    from geomexact.mesh3d.octree.regions import BallRegion
    from geomexact.mesh3d.octree.stages import RefineWhere

    text = GUIDE.read_text(encoding="utf-8")
    assert "geomexact octree --refine-sphere 0.5 0.5 0.5 0.3 --level 5" in text
    run = generate(Box((0, 0, 0), (1, 1, 1)), trace=False,
                   refinement=RefineWhere(5, region=BallRegion(("1/2",) * 3, "3/10")))
    assert (run.octree.leaf_count, run.mesh.tetrahedron_count, run.mesh.vertex_count) == (
        6_840, 39_848, 8_221)
    assert "6,840\nleaves, 39,848 tetrahedra, 8,221 vertices" in text


def test_stated_counts_of_the_cell_finals() -> None:
    """The mixed and polyhedral pictures' captions, checked by the library."""
    from geomexact.cli.summaries import cells_by_kind
    from geomexact.mesh3d.cuboid.boxes import Box
    from geomexact.mesh3d.octree.pipeline import generate_cells
    from geomexact.mesh3d.octree.regions import SphereSurfaceRegion
    from geomexact.mesh3d.octree.stages import MixedPartition, PolyhedralPartition, RefineWhere

    text = GUIDE.read_text(encoding="utf-8")
    refinement = RefineWhere(4, region=SphereSurfaceRegion(("1/2",) * 3, "3/10"))
    mixed = generate_cells(Box((0, 0, 0), (1, 1, 1)), MixedPartition(), trace=False,
                           refinement=refinement)
    assert (mixed.octree.leaf_count, mixed.mesh.cell_count, mixed.mesh.vertex_count,
            mixed.leaf_mesh.added) == (1_352, 3_264, 1_945, 40)
    assert cells_by_kind(mixed.mesh) == {"tetrahedra": 776, "pyramids": 1_200, "wedges": 168,
                                         "hexahedra": 1_120}
    polyhedral = generate_cells(Box((0, 0, 0), (1, 1, 1)), PolyhedralPartition(),
                                trace=False, refinement=refinement)
    assert cells_by_kind(polyhedral.mesh) == {
        "tetrahedra": 568, "pyramids": 1_056, "wedges": 168, "hexahedra": 1_120,
        "polyhedra": 64}
    assert polyhedral.mesh.vertex_count == 1_905
    for stated in ("3,264 cells (1,120 hexahedra, 168 wedges, 1,200 pyramids, 776",
                   "1,945 vertices (40 added", "2,976 cells (1,120 hexahedra, 168 wedges, 1,056",
                   "pyramids, 568 tetrahedra, 64 polyhedra), 1,905 vertices"):
        assert stated in text.replace("\n", " ").replace("  ", " "), stated
