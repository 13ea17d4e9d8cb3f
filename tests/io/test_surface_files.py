"""The surface readers (OBJ, STL ASCII and binary, PLY ASCII and binary, 3D OFF): exact
round trips of small surfaces, every bad input a FormatError naming the file and the
line, the shared surfaces read exactly, and a large OBJ read in bounded memory."""

from __future__ import annotations

import contextlib
import struct
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import gmpy2
import pytest
from helpers.surface_cases import (
    CASES,
    WRITERS,
    cube,
    geometric_triangles,
    tetrahedron,
    write_binary_ply,
    write_binary_stl,
)

from geomexact.errors import FormatError
from geomexact.io.surface_files import read_surface, surface_format


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("file_name", sorted(WRITERS))
def test_every_format_reads_back_the_same_surface(tmp_path: Path, case: str,
                                                  file_name: str) -> None:
    """Each small surface written in each format reads back with the same exact
    triangles (STL renumbers its welded vertices; the others keep the ids)."""
    surface = CASES[case]()
    read = read_surface(WRITERS[file_name](tmp_path / file_name, surface))
    assert geometric_triangles(read) == geometric_triangles(surface)
    assert read.enclosed_volume() == surface.enclosed_volume()
    assert read.name == file_name
    if not file_name.endswith(".stl"):
        assert read.points == surface.points
        assert read.triangles.tolist() == surface.triangles.tolist()
    else:
        assert read.vertex_count == surface.vertex_count  # welded exactly


def test_big_endian_ply_and_polygons_are_fan_triangulated(tmp_path: Path) -> None:
    """A big-endian PLY of the cube's six quads reads as the fans (v0, v1, v2),
    (v0, v2, v3)."""
    quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2],
             [1, 3, 7, 5]]
    read = read_surface(write_binary_ply(tmp_path / "q.ply", cube(), ">", quads))
    assert read.triangles.tolist() == cube().triangles.tolist()
    mixed = [[0, 2, 3, 1], [4, 5, 7], [4, 7, 6], *quads[2:]]
    read = read_surface(write_binary_ply(tmp_path / "m.ply", cube(), "<", mixed))
    assert read.triangle_count == 12


def test_decimals_are_read_exactly(tmp_path: Path) -> None:
    """0.1 is 1/10 in every text format, never the double nearest to it; 1e-3, p/q,
    and OBJ's negative indices and v/vt/vn references work."""
    path = tmp_path / "d.obj"
    path.write_text("v 0.1 0 0\nv 0 1e-3 0\nv 0 0 1/3\nv 0 0 0\n"
                    "f -4/1/1 -3//2 -2\nf 1 2 4 3\n")
    read = read_surface(path)
    assert read.points[0].x == gmpy2.mpq(1, 10)
    assert read.points[1].y == gmpy2.mpq(1, 1000)
    assert read.points[2].z == gmpy2.mpq(1, 3)
    assert read.triangles.tolist() == [[0, 1, 2], [0, 1, 3], [0, 3, 2]]


def test_binary_floats_are_their_exact_values(tmp_path: Path) -> None:
    """A binary STL's float32 0.1 is read as that float's exact binary value."""
    surface = tetrahedron()
    path = write_binary_stl(tmp_path / "t.stl", surface)
    data = bytearray(path.read_bytes())
    struct.pack_into("<f", data, 84 + 12, 0.1)  # first triangle, first corner, x
    path.write_bytes(bytes(data))
    read = read_surface(path)
    x = read.points[0].x
    assert x == gmpy2.mpq(struct.unpack("<f", struct.pack("<f", 0.1))[0]) != gmpy2.mpq(1, 10)


def test_stl_welds_identical_points_including_signed_zero(tmp_path: Path) -> None:
    """-0.0 and 0.0 are one value, so one vertex."""
    path = write_binary_stl(tmp_path / "t.stl", tetrahedron())
    data = bytearray(path.read_bytes())
    struct.pack_into("<f", data, 84 + 12, -0.0)
    path.write_bytes(bytes(data))
    assert read_surface(path).vertex_count == 4


BAD_TEXT = [
    ("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "not defined before"),
    ("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "not defined before"),
    ("number.obj", "v 0 0 0\nv 1 zero 0\n", 2, "cannot read 'zero' as a number"),
    ("nan.obj", "v 0 0 nan\n", 1, "NaN"),
    ("short.obj", "v 0 0\n", 1, "expected 'v x y z'"),
    ("face.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "at least 3 vertices"),
    ("word.obj", "v 0 0 0\nf 1 x 1\n", 2, "not an integer"),
    ("curve.obj", "v 0 0 0\ncurv 0 1 1 2\n", 2, "unknown OBJ statement 'curv'"),
    ("empty.obj", "# nothing\nv 0 0 0\n", 2, "no face"),
    ("counts.off", "OFF\n4\n", 2, "the counts"),
    ("faces.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 6, "expected 2 faces"),
    ("vertex.off", "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", 4, "vertex 1"),
    ("range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", 6, "out of range"),
    ("header.off", "4OFF\n3 1 0\n", 1, "a 3D OFF file starts with"),
    ("extra.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n7\n", 7, "unexpected data"),
    ("solid.stl", "solidity\nfacet normal 0 0 1\n", 1, "starts with 'solid'"),
    ("loop.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
     "vertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\nendsolid x\n", 7, "3 vertices"),
    ("coord.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0.5.1"
     "\n", 5, "cannot read '0.5.1'"),
    ("ends.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", 4,
     "the file ends before vertex 2"),
    ("noface.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
     "property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n", None,
     "no 'face' element"),
    ("count.ply", "ply\nformat ascii 1.0\nelement vertex\n", 3, "'element name count'"),
    ("format.ply", "ply\nformat text 1.0\n", 2, "expected 'format ascii"),
    ("short.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
     "property float y\nproperty float z\nelement face 1\n"
     "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
     "3 0 1\n", 13, "announces 3 items"),
    ("faces.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
     "property float y\nproperty float z\nelement face 2\n"
     "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
     "3 0 1 2\n", 13, "expected 2 'face' lines"),
]


@pytest.mark.parametrize(("name", "text", "line", "problem"), BAD_TEXT,
                         ids=[case[0] for case in BAD_TEXT])
def test_bad_text_inputs_name_file_and_line(tmp_path: Path, name: str, text: str,
                                            line: int | None, problem: str) -> None:
    """Each malformed text file is a FormatError at its file and line."""
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(FormatError) as caught:
        read_surface(path)
    assert caught.value.path == str(path)
    assert caught.value.line == line
    assert problem in caught.value.problem


def test_truncated_binary_files_are_refused(tmp_path: Path) -> None:
    """A binary STL or PLY cut short is a FormatError saying so (line None: binary)."""
    stl = write_binary_stl(tmp_path / "t.stl", cube())
    stl.write_bytes(stl.read_bytes()[:-7])
    with pytest.raises(FormatError, match="announces 12 triangles") as caught:
        read_surface(stl)
    assert caught.value.line is None
    ply = write_binary_ply(tmp_path / "t.ply", cube())
    ply.write_bytes(ply.read_bytes()[:-5])
    with pytest.raises(FormatError, match="ends inside the 'face' element"):
        read_surface(ply)
    tiny = tmp_path / "tiny.stl"
    tiny.write_bytes(b"\x00" * 10)
    with pytest.raises(FormatError, match="84-byte header"):
        read_surface(tiny)


def test_binary_problems_name_the_record(tmp_path: Path) -> None:
    """A NaN coordinate in a binary STL and a bad index in a binary PLY name the
    triangle or face."""
    stl = write_binary_stl(tmp_path / "t.stl", cube())
    data = bytearray(stl.read_bytes())
    struct.pack_into("<f", data, 84 + 50 * 5 + 12 + 4, float("nan"))
    stl.write_bytes(bytes(data))
    with pytest.raises(FormatError, match=r"triangle 5 .*not a finite number"):
        read_surface(stl)
    ply = write_binary_ply(tmp_path / "t.ply", tetrahedron(), "<", [[0, 1, 2], [0, 1, 9]])
    with pytest.raises(FormatError, match="face 1: vertex 9 is out of range"):
        read_surface(ply)


def test_unknown_extension_and_missing_file(tmp_path: Path) -> None:
    with pytest.raises(FormatError, match="names no surface format"):
        surface_format(tmp_path / "x.vtu")
    with pytest.raises(FormatError, match="no such file"):
        read_surface(tmp_path / "missing.obj")
    assert surface_format("A.OBJ") == "obj"


def test_random_bytes_are_format_errors(tmp_path: Path) -> None:
    """No reader lets another exception out on garbage (a fixed, seeded sample)."""
    import random

    chooser = random.Random(24)
    for index in range(60):
        blob = bytes(chooser.randrange(256) for _ in range(chooser.randrange(1, 300)))
        for suffix in (".obj", ".stl", ".ply", ".off"):
            path = tmp_path / f"g{index}{suffix}"
            path.write_bytes(blob if index % 2 else b"ply\nformat ascii 1.0\n" + blob)
            with contextlib.suppress(FormatError):
                read_surface(path)


def _surfaces(shared_data: Path) -> Path:
    folder = shared_data / "surfaces"
    if not folder.is_dir():
        pytest.skip(f"no surfaces in {shared_data}")
    return folder


def test_fandisk_and_spot_read_exactly(shared_data: Path) -> None:
    """The shared OBJ surfaces read with their counts, each coordinate the decimal in
    the file (checked against Fraction of the text)."""
    folder = _surfaces(shared_data)
    fandisk = read_surface(folder / "fandisk.obj")
    assert (fandisk.vertex_count, fandisk.triangle_count) == (6475, 12946)
    spot = read_surface(folder / "spot.obj")
    assert (spot.vertex_count, spot.triangle_count) == (2930, 5856)
    with open(folder / "fandisk.obj") as handle:
        first = next(line for line in handle if line.startswith("v "))
    assert [Fraction(text) for text in first.split()[1:]] == [
        Fraction(int(c.numerator), int(c.denominator)) for c in fandisk.points[0][:3]]


def _big_obj(path: Path, side: int) -> int:
    """An OBJ grid of ``side`` x ``side`` squares (2 side^2 triangles), written in
    blocks; returns the triangle count."""
    with open(path, "w") as handle:
        for row in range(side + 1):
            handle.write("".join(f"v {column}.25 {row}.5 0.1\n" for column in range(side + 1)))
        width = side + 1
        for row in range(side):
            block = []
            for column in range(side):
                a = row * width + column + 1
                block.append(f"f {a} {a + 1} {a + width + 1}\nf {a} {a + width + 1} "
                             f"{a + width}\n")
            handle.write("".join(block))
    return 2 * side * side


_PEAK_SCRIPT = """
import re, sys
from pathlib import Path
from geomexact.io.surface_files import read_surface
surface = read_surface(sys.argv[1])
# VmHWM, not ru_maxrss: the latter survives exec, so it would count the forked parent
peak = re.search(r"VmHWM:\\s+(\\d+) kB", Path("/proc/self/status").read_text()).group(1)
print(surface.triangle_count, peak)
"""


def _read_peak(path: Path) -> tuple[int, int]:
    """(triangles read, peak RSS in kB) of reading ``path`` in a fresh process."""
    output = subprocess.run([sys.executable, "-c", _PEAK_SCRIPT, str(path)], check=True,
                            capture_output=True, text=True).stdout.split()
    return int(output[0]), int(output[1])


def test_a_grid_obj_reads_in_a_fresh_process(tmp_path: Path) -> None:
    """A 20,000-triangle OBJ reads whole in a subprocess (the fast sibling of the slow
    10^6-face test)."""
    count = _big_obj(tmp_path / "grid.obj", 100)
    read, peak = _read_peak(tmp_path / "grid.obj")
    assert read == count
    assert peak < 400_000


@pytest.mark.slow
def test_a_million_face_obj_reads_in_bounded_memory(tmp_path: Path) -> None:
    """10^6 triangles (about 500,000 vertices) read with a peak RSS under 1 GB
    (measured: see specs/formats/surfaces.md, "Memory")."""
    count = _big_obj(tmp_path / "big.obj", 708)
    assert count >= 1_000_000
    read, peak = _read_peak(tmp_path / "big.obj")
    assert read == count
    assert peak < 1_000_000
