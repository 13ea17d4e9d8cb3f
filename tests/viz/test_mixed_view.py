"""The 3D page's payload and the pictures of a mixed-cell mesh
(:mod:`geomexact.viz.scene3d`, :mod:`geomexact.viz.pictures3d`): every face of every cell
is in the payload once per side as its polygon, the cells are counted by kind, the clip
keeps whole cells decided exactly and opens exactly the faces between kept and removed
cells, quads and polygons are painted without diagonals, and a trace of splits and merges
gives each cell's birth and death."""

from __future__ import annotations

import base64
import random
from collections import Counter
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from helpers.mixed_cases import random_walk
from helpers.mixed_view_cases import every_kind_mesh
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.mixed.cells import CellKind, polygon_key, reversed_face, rotated_face
from geomexact.mesh3d.mixed.conversion import box_grid_mesh, from_tetrahedral
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, empty_mixed_mesh
from geomexact.trace.record import trace_of
from geomexact.viz.pictures3d import Drawing3, draw_mesh3, face_neighbours, plot_mesh3
from geomexact.viz.scene3d import (
    KIND_ORDER,
    KIND_PLURALS,
    cell_faces,
    clip_plane,
    kept_by_clip,
    payload3,
    viewer_html_3d,
)


@pytest.fixture(scope="module")
def mesh() -> MixedMesh3:
    return every_kind_mesh()


def _array(text: str, dtype: str) -> np.ndarray:
    return np.frombuffer(base64.b64decode(text), dtype=dtype)


def _payload_cells(data: dict) -> list[tuple[int, tuple[int, ...], list[tuple[int, ...]]]]:
    """(kind, vertices, faces) of every cell of a mixed payload, decoded from its CSR
    arrays."""
    kinds = _array(data["kinds"], "u1")
    cells, cell_offsets = _array(data["cells"], "<u4"), _array(data["cell_offsets"], "<u4")
    corners, corner_offsets = _array(data["faces"], "<u4"), _array(data["face_offsets"], "<u4")
    face_offsets = _array(data["cell_face_offsets"], "<u4")
    decoded = []
    for c, kind in enumerate(kinds):
        faces = [tuple(int(v) for v in corners[corner_offsets[f]:corner_offsets[f + 1]])
                 for f in range(face_offsets[c], face_offsets[c + 1])]
        vertices = tuple(int(v) for v in cells[cell_offsets[c]:cell_offsets[c + 1]])
        decoded.append((int(kind), vertices, faces))
    return decoded


def _kinds(cells: list) -> dict[str, int]:
    counts = Counter(cell.kind for cell in cells)
    return {KIND_PLURALS[kind]: counts[kind] for kind in KIND_ORDER if counts[kind]}


def _exactly_kept(mesh: MixedMesh3, axis: int, position: Fraction) -> list:
    return [cell for cell in mesh.cell_list()
            if sum(Fraction(mesh.point(v)[axis]) for v in cell.vertices)
            <= position * len(cell.vertices)]


def _drawing(mesh: MixedMesh3, **options: object) -> Drawing3:
    return draw_mesh3(Figure().add_subplot(), mesh, **options)  # type: ignore[arg-type]


def test_every_face_of_every_cell_is_in_the_payload_once_per_side(mesh: MixedMesh3) -> None:
    data = payload3(mesh)
    decoded = _payload_cells(data)
    assert [(k, v, sorted(rotated_face(f) for f in faces)) for k, v, faces in decoded] == [
        (int(c.kind), c.vertices, list(c.faces)) for c in mesh.cell_list()]
    sides = Counter(rotated_face(f) for _, _, faces in decoded for f in faces)
    assert set(sides.values()) == {1}  # each oriented polygon once
    keys = Counter(polygon_key(face) for face in sides)
    assert sorted(f for f in sides if keys[polygon_key(f)] == 1) == mesh.boundary_faces()
    assert sorted(polygon_key(f) for f in sides if keys[polygon_key(f)] == 2) == sorted(
        polygon_key(f) for face in mesh.interior_faces()
        for f in (face, reversed_face(face)))
    sizes = Counter(len(f) for _, _, faces in decoded for f in faces)
    assert sizes == Counter(len(f) for c in mesh.cell_list() for f in c.faces)
    assert sizes[4] > 0 and sizes[5] == 2  # quads and the prism's pentagons, whole


def test_payload_counts_kinds_and_states_the_exact_volume(mesh: MixedMesh3) -> None:
    data = payload3(mesh, title="every kind")
    assert data["format"] == "geomexact-view3d" and data["version"] == 2
    assert data["kind_counts"] == _kinds(mesh.cell_list()) == {
        "tetrahedra": 2, "pyramids": 1, "wedges": 1, "hexahedra": 11, "polyhedra": 6}
    assert Fraction(data["volume"]) == Fraction(37, 36)
    assert data["digests"] == [mesh.digest_text]
    assert data["options"]["colour"] == "kind"
    quality = _array(data["quality"], "u1")
    kinds = _array(data["kinds"], "u1")
    assert (quality[kinds != CellKind.TETRA] == 0).all() and (quality[kinds == 10] > 0).all()
    with pytest.raises(ValueError, match="colour"):
        payload3(mesh, colour="quality")
    page = viewer_html_3d(mesh, colour="plain", clip=clip_plane("z", "1/2"))
    assert page == viewer_html_3d(mesh, colour="plain", clip=clip_plane("z", "1/2"))
    assert "<script src" not in page


def test_a_tetrahedral_payload_has_no_mixed_fields() -> None:
    data = payload3(partition_cuboid(0b101101).mesh)
    assert not {"kinds", "faces", "kind_counts"} & set(data)


@pytest.mark.parametrize(("axis", "position"), [("x", "1/2"), ("z", "1/2"), ("y", "0.3"),
                                                ("z", "1")])
def test_the_clip_keeps_whole_cells_exactly(mesh: MixedMesh3, axis: str,
                                            position: str) -> None:
    clip = clip_plane(axis, position)
    faces = cell_faces(mesh)
    expected = _exactly_kept(mesh, clip.index, Fraction(position))
    kept = kept_by_clip(mesh, faces, clip)
    assert [c for c, k in zip(mesh.cell_list(), kept, strict=True) if k] == expected
    drawing = _drawing(mesh, clip=clip)
    assert drawing.kept == len(expected) and drawing.cells == mesh.cell_count
    # the faces opened are exactly those between a kept cell and a removed one
    kept_cells = set(expected)
    opened = {rotated_face(f) for cell in expected for f in cell.faces
              if any(n not in kept_cells for n in mesh.neighbours(cell, f))}
    assert drawing.cut == len(opened)
    assert drawing.surface == sum(1 for cell in expected for f in cell.faces
                                  if not mesh.neighbours(cell, f))


def test_neighbours_pair_polygons_of_any_size(mesh: MixedMesh3) -> None:
    faces = cell_faces(mesh)
    adjacency = face_neighbours(faces)
    cells = mesh.cell_list()
    for f, (owner, other) in enumerate(zip(adjacency.owners, adjacency.neighbours,
                                           strict=True)):
        face = tuple(faces.corners[faces.corner_offsets[f]:faces.corner_offsets[f + 1]])
        across = mesh.neighbours(cells[owner], face)
        assert ([cells[other]] if other >= 0 else []) == list(across)


def test_picture_paints_polygons_coloured_by_kind(mesh: MixedMesh3, tmp_path: Path) -> None:
    fig = Figure()
    ax = fig.add_subplot()
    drawing = draw_mesh3(ax, mesh)
    assert drawing.mixed and drawing.kinds == _kinds(mesh.cell_list())
    assert drawing.tetrahedra == 2
    collection = next(c for c in ax.collections if isinstance(c, PolyCollection))
    corners = Counter(len(path.vertices) - 1 for path in collection.get_paths())
    assert corners == Counter({int(k): n for k, n in drawing.sizes.items()})
    assert corners[4] > 0 and sum(corners.values()) == drawing.painted
    assert len(set(map(tuple, collection.get_facecolors()[:, :3].round(6)))) > 1
    legend = ax.get_legend()
    assert legend is not None
    assert [t.get_text() for t in legend.get_texts()] == list(drawing.kinds)
    shrunk = _drawing(mesh, shrink=0.3, clip=clip_plane("y", "1/3"))
    assert shrunk.sizes.get(5, 0) >= 1  # the prism's pentagon facing the viewer
    path = tmp_path / "mixed.png"
    fig = plot_mesh3(mesh, path, clip=clip_plane("x", "1/2"))
    assert path.read_bytes().startswith(b"\x89PNG")
    assert fig._suptitle.get_text().startswith("54 vertices, 21 cells\n2 tetrahedra, "
                                               "1 pyramid, 1 wedge, 11 hexahedra")
    assert fig._suptitle.get_text().endswith("\nclip x ≤ 0.5: 13 kept")
    with pytest.raises(ValueError, match="quality"):
        _drawing(mesh, colour="quality")


def test_a_tetrahedral_mesh_draws_the_same_as_mixed() -> None:
    tetrahedral = partition_cuboid(262143, improve=True).mesh
    as_mixed = from_tetrahedral(tetrahedral)
    for clip in (None, clip_plane("x", "1/2")):
        a = draw_mesh3(Figure().add_subplot(), tetrahedral, clip=clip)
        b = _drawing(as_mixed, clip=clip, colour="plain")
        assert (a.kept, a.surface, a.cut, a.painted, a.sizes) == (
            b.kept, b.surface, b.cut, b.painted, b.sizes)


def test_a_trace_of_splits_and_merges_gives_births_and_deaths() -> None:
    start = box_grid_mesh(Box((0, 0, 0), (1, 1, 1)), 2, 2, 1)
    transient = start.transient()
    applied = random_walk(transient, random.Random(7), 8)
    final = transient.seal()
    trace = trace_of(start, transient)
    assert applied > 2
    data = payload3(start, trace)
    assert data["steps"] == len(trace.steps) and data["kind_counts"] == _kinds(
        final.cell_list())
    birth, death = _array(data["birth"], "<i4"), _array(data["death"], "<i4")
    decoded = _payload_cells(data)
    for step, snapshot in ((0, start), (data["steps"], final)):
        alive = sorted((kind, vertices, sorted(rotated_face(f) for f in faces))
                       for c, (kind, vertices, faces) in enumerate(decoded)
                       if birth[c] <= step < death[c])
        assert alive == [(int(c.kind), c.vertices, list(c.faces))
                         for c in snapshot.cell_list()]


def test_empty_mixed_mesh() -> None:
    data = payload3(empty_mixed_mesh())
    assert data["kind_counts"] == {} and data["volume"] == "0"
    assert _drawing(empty_mixed_mesh()).painted == 0
