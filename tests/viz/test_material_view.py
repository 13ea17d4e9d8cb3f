"""Colouring 3D meshes by material (issue 24): the pictures give each material its own
fill and a legend of the ids (named where names are given), the page's payload carries
each cell's material, and ``geomexact view --color-by material`` uses the file's material
cell array, refusing a file without one (exit 2, naming it)."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import numpy as np
import pytest
from helpers.command import run
from helpers.mesh3d_cases import cube_grid
from matplotlib.collections import PolyCollection
from matplotlib.colors import to_rgb
from matplotlib.figure import Figure

from geomexact import io
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.conversion import box_grid_mesh
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.viz.pictures3d import draw_mesh3
from geomexact.viz.scene3d import MATERIAL_FILLS, payload3, viewer_html_3d


def _by_x(mesh: Mesh3 | MixedMesh3, split: int = 1) -> list[int]:
    """Material 7 for the cells left of x = ``split`` (all vertices), 3 for the others:
    ids out of order, to check the colours follow increasing ids."""
    cells = (mesh.tetrahedra() if isinstance(mesh, Mesh3)
             else [c.vertices for c in mesh.cell_list()])
    return [7 if all(mesh.point(v).x <= split for v in cell) else 3 for cell in cells]


def _fill_index(colour: np.ndarray) -> int:
    """Which of :data:`MATERIAL_FILLS` a shaded face colour is (shading scales it)."""
    for index, fill in enumerate(MATERIAL_FILLS):
        ratio = colour[:3] / np.array(to_rgb(fill))
        if np.allclose(ratio, ratio[0], atol=1e-6):
            return index
    raise AssertionError(f"{colour} is no material's fill")


@pytest.mark.parametrize("case", ["tetrahedra", "hexahedra"])
def test_pictures_colour_each_material_with_a_legend(case: str) -> None:
    mesh: Mesh3 | MixedMesh3 = (cube_grid(2, 1, 1) if case == "tetrahedra" else
                                box_grid_mesh(Box((0, 0, 0), (2, 1, 1)), 2, 1, 1))
    ax = Figure().add_subplot()
    drawing = draw_mesh3(ax, mesh, colour="material", materials=_by_x(mesh),
                         material_names={7: "oxide"})
    assert drawing.legend == ("material 3", "material 7 (oxide)")
    assert [t.get_text() for t in ax.get_legend().get_texts()] == list(drawing.legend)
    faces = next(c for c in ax.collections if isinstance(c, PolyCollection))
    used = {_fill_index(colour) for colour in faces.get_facecolors()}
    assert used == {0, 1}  # material 3 the first fill, 7 the second
    plain = Figure().add_subplot()
    assert draw_mesh3(plain, mesh, colour="plain").legend == ()


def test_pictures_need_one_material_per_cell() -> None:
    mesh = cube_grid(1, 1, 1)
    ax = Figure().add_subplot()
    with pytest.raises(ValueError, match="needs materials"):
        draw_mesh3(ax, mesh, colour="material")
    with pytest.raises(ValueError, match="2 values for 6 cells"):
        draw_mesh3(ax, mesh, colour="material", materials=[1, 2])


def test_page_payload_carries_each_cells_material() -> None:
    mesh = cube_grid(2, 1, 1)
    materials = _by_x(mesh)
    data = payload3(mesh, colour="material", materials=materials,
                    material_names={3: "silicon"})
    assert data["options"]["colour"] == "material"
    assert data["material_ids"] == ["3", "7"]
    assert data["material_names"] == ["silicon", ""]
    assert data["material_counts"] == {"3": 6, "7": 6}
    ranks = np.frombuffer(base64.b64decode(data["materials"]), dtype="<u4")
    assert [["3", "7"][r] for r in ranks] == [str(m) for m in materials]
    assert "materials" not in payload3(mesh)
    assert payload3(mesh, materials=materials)["options"]["colour"] == "quality"
    with pytest.raises(ValueError, match="colour must be one of"):
        payload3(mesh, colour="material")
    page = viewer_html_3d(mesh, colour="material", materials=materials)
    assert '"material_ids":["3","7"]' in page and 'value="material"' in page


def _mos_like(tmp_path: Path) -> Path:
    """Two materials in a mixed-cell file written the way ``octree --device`` writes."""
    mesh = box_grid_mesh(Box((0, 0, 0), (2, 1, 1)), 2, 1, 1)
    path = tmp_path / "two.vtu"
    io.write(path, MixedMeshData(mesh, {"material": _by_x(mesh)}))
    return path


def test_view_colours_a_files_materials(tmp_path: Path,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    path = _mos_like(tmp_path)
    code, _, err = run(capsys, "view", path, "-o", tmp_path / "two.png", "--color-by",
                       "material")
    assert code == 0, err
    assert (tmp_path / "two.png").stat().st_size > 1000
    code, _, err = run(capsys, "view", path, "-o", tmp_path / "two.html", "--color-by",
                       "material")
    assert code == 0, err
    text = (tmp_path / "two.html").read_text()
    start = text.index('id="geomexact-data">') + len('id="geomexact-data">')
    data = json.loads(text[start:text.index("</script>", start)])
    assert data["options"]["colour"] == "material"
    assert data["material_ids"] == ["3", "7"]
    # the default colouring stays; the page still carries the materials to choose
    code, _, _ = run(capsys, "view", path, "-o", tmp_path / "plain.html")
    assert code == 0
    assert '"colour":"kind"' in (tmp_path / "plain.html").read_text()
    assert '"material_ids"' in (tmp_path / "plain.html").read_text()


def test_view_refuses_files_without_materials(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    grid = tmp_path / "grid.vtu"
    io.write(grid, cube_grid(1, 1, 1))
    code, _, err = run(capsys, "view", grid, "-o", tmp_path / "grid.png", "--color-by",
                       "material")
    assert code == 2
    assert str(grid) in err and "material" in err
    assert not (tmp_path / "grid.png").exists()
    flat = tmp_path / "flat.off"
    flat.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    code, _, err = run(capsys, "view", flat, "-o", tmp_path / "flat.png", "--color-by",
                       "material")
    assert code == 2 and str(flat) in err
