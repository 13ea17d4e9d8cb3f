"""The io facade and registry: formats by extension, kinds, notes, overwrite refusal and
atomic writing."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from geomexact import Mesh2, io, mesh_from_triangles, point2
from geomexact.errors import FormatError, OverwriteError
from geomexact.io.registry import Format
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh
from geomexact.mesh2d.pslg import PSLG
from geomexact.mesh3d.mixed import MixedMesh3
from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.snapshot import Mesh3

MESH = mesh_from_triangles([(0, 0), (1, 0), (0, 1)], [(0, 1, 2)])


def test_registry_lists_every_format() -> None:
    """The registry's names, and every extension maps back to its format."""
    assert sorted(io.FORMATS) == ["geomview3d", "geomview3d-boundary", "mellado", "meshio",
                                  "node", "off", "poly", "pslg", "tetgen", "triangle", "trilist",
                                  "vect"]
    for name, fmt in io.FORMATS.items():
        assert isinstance(fmt, Format) and fmt.name == name and fmt.description
        assert fmt.kinds and all(kind in (Mesh2, PSLG, PolygonMesh, Mesh3, MixedMesh3,
                                          MixedMeshData) for kind in fmt.kinds)
        for extension in fmt.extensions:
            assert extension.startswith(".") and extension == extension.lower()
            assert io.detect_format(f"some/dir/file.1{extension.upper()}") == name
    with pytest.raises(TypeError):
        io.FORMATS["x"] = io.FORMATS["off"]  # type: ignore[index]


@pytest.mark.parametrize(
    ("path", "name"),
    [("a.ele", "triangle"), ("a.1.node", "node"), ("b.poly", "poly"), ("c.OFF", "off"),
     ("d.pslg", "pslg"), ("Triangles1.txt", "trilist"), ("e.vtu", "meshio"),
     ("f.msh", "meshio")],
)
def test_detect_format(path: str, name: str) -> None:
    """Formats are chosen by extension, case-insensitively."""
    assert io.detect_format(path) == name


def test_detect_format_without_extension() -> None:
    """No extension: a FormatError that says so."""
    with pytest.raises(FormatError, match="no extension names no known format"):
        io.detect_format("mesh")


def test_explicit_format_overrides_the_extension(tmp_path: Path) -> None:
    """format= reads and writes whatever the file is called."""
    io.write(tmp_path / "mesh.dat", MESH, format="off")
    assert (tmp_path / "mesh.dat").read_text().startswith("OFF\n")
    assert io.read(tmp_path / "mesh.dat", format="off") == MESH


def test_read_with_notes_and_read_agree(tmp_path: Path) -> None:
    """read is read_with_notes without the notes."""
    (tmp_path / "cw.off").write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 2 1\n")
    value, notes = io.read_with_notes(tmp_path / "cw.off")
    assert value == io.read(tmp_path / "cw.off") == MESH
    assert notes == ["the only triangle was clockwise; reversed it"]


def test_kinds_are_checked_before_writing(tmp_path: Path) -> None:
    """A format that cannot hold the value: TypeError, nothing written."""
    polygons = PolygonMesh(vertices=[point2(0, 0), point2(1, 0), point2(0, 1)],
                           polygons=[(0, 1, 2)])
    for name in ("m.ele", "m.node", "m.poly", "m.pslg", "m.txt", "m.vtu"):
        with pytest.raises(TypeError, match="format writes a"):
            io.write(tmp_path / name, polygons)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["m.ele", "m.off", "m.pslg", "m.txt", "m.vtk"])
def test_overwrite_is_refused_unless_asked(tmp_path: Path, name: str) -> None:
    """An existing file is never replaced without overwrite=True (and keeps its text)."""
    target = tmp_path / name
    written = io.write(target, MESH)
    assert target in written
    before = {path.name: path.read_bytes() for path in tmp_path.iterdir()}
    with pytest.raises(OverwriteError, match="refusing to overwrite"):
        io.write(target, MESH, numbers="float")
    assert {path.name: path.read_bytes() for path in tmp_path.iterdir()} == before
    assert io.write(target, MESH, overwrite=True) == written


def test_writing_leaves_no_temporary_files(tmp_path: Path) -> None:
    """Every writer goes through a temporary file and a rename: none is left behind."""
    pslg = PSLG(vertices=[point2(0, 0), point2(1, 0)], segments=[(0, 1, 0)])
    for name, value in (("t.ele", MESH), ("n.node", pslg), ("p.poly", pslg), ("o.off", MESH),
                        ("s.pslg", MESH), ("l.txt", MESH), ("v.vtu", MESH)):
        io.write(tmp_path / name, value)
        io.write(tmp_path / name, value, overwrite=True)
    assert sorted(path.name for path in tmp_path.iterdir()) == [
        "l.txt", "n.node", "o.off", "p.poly", "s.pslg", "t.ele", "t.neigh", "t.node", "v.vtu"
    ]


def test_failed_write_keeps_the_old_file_and_no_temporary(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """When the final rename fails, the old file stays whole and the temporary is gone."""
    target = tmp_path / "keep.off"
    io.write(target, MESH)
    old = target.read_bytes()

    def failing_replace(source: object, destination: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", failing_replace)
    with pytest.raises(OSError, match="disk full"):
        io.write(target, mesh_from_triangles([(0, 0), (2, 0), (0, 2)], [(0, 1, 2)]),
                 overwrite=True)
    assert target.read_bytes() == old
    assert sorted(path.name for path in tmp_path.iterdir()) == ["keep.off"]


def test_paths_may_be_strings(tmp_path: Path) -> None:
    """str paths work everywhere; written paths are Paths."""
    written = io.write(str(tmp_path / "s.off"), MESH)
    assert written == [tmp_path / "s.off"]
    assert io.read(str(tmp_path / "s.off")) == MESH


def test_reading_restores_the_garbage_collector(tmp_path: Path) -> None:
    """Readers pause the cyclic collector and restore its state, even on errors."""
    import gc

    (tmp_path / "bad.off").write_text("OFF\nnonsense\n")
    assert gc.isenabled()
    with pytest.raises(FormatError):
        io.read(tmp_path / "bad.off")
    assert gc.isenabled()
    gc.disable()
    try:
        io.write(tmp_path / "g.off", MESH)
        io.read(tmp_path / "g.off")
        assert not gc.isenabled()
    finally:
        gc.enable()
