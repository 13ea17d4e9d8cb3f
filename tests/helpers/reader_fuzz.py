"""The readers' fuzz contract, shared by ``tests/io/test_io_fuzz.py`` (hypothesis) and
``tests/io/fuzz_readers.py`` (atheris): valid seed files of every reader, mutations of
their bytes, and :func:`check_read`, which reads a (mutated) case and asserts the contract:

- either a :class:`FormatError` whose ``path`` is one of the case's files, whose ``line``
  (when not None: a file-level problem) is a line of that file, and whose message is
  short (a huge line is quoted in ~200 characters);
- or a well-formed value: a ``Mesh2`` whose snapshot invariants hold (``validate`` finds
  none of the structural kinds a reader guarantees; the geometric kinds — fold-over,
  overlap, boundary loops, non-manifold vertices, segments that are not edges — describe
  the file's own geometry, which ``geomexact check`` reports, so a reader reads them), a
  ``Mesh3`` likewise (``validate3``: faces, adjacency, positive orientation, counts,
  hints and digest hold; a non-manifold edge or vertex or an open boundary is the file's
  geometry), a ``PolygonMesh`` whose structure is sound, a ``PSLG`` with segments between
  distinct existing vertices and tables of the right sizes, or a ``Trace`` of steps with
  integer and rational arguments and 128-bit digests;
- never any other exception, and no hang (a read is stopped after 20 s: :class:`Hang`).

The 3D readers have their own seeds (:func:`seeds3d`, :func:`meshio_seeds`): TetGen
``.node``/``.ele``/``.face`` (0- and 1-based, attributes and markers), Geomview OFF
pictures of a ``Mesh3`` read back as OFF, and VTU/VTK tetrahedra, binary and ASCII.
"""

from __future__ import annotations

import contextlib
import functools
import random
import signal
import tempfile
from collections.abc import Callable, Iterator
from io import StringIO
from pathlib import Path
from typing import Any

import attrs

from geomexact import io, mesh_from_triangles
from geomexact.errors import FormatError
from geomexact.io.trace_file import read_trace, trace_text
from geomexact.kernel.numbers import mpq
from geomexact.kernel.numbers import mpq as EXACT  # the exact number type (gmpy2.mpq)
from geomexact.kernel.points import point2
from geomexact.mesh2d.polygonal.polygon_mesh import PolygonMesh, validate_polygon_mesh
from geomexact.mesh2d.pslg import PSLG, RegionSeed
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import Transient2
from geomexact.mesh2d.validation import validate
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.validation import validate3
from geomexact.trace.record import Trace

GEOMETRIC_KINDS = frozenset(
    {"fold-over", "overlap", "boundary-loop", "non-manifold-vertex", "segment",
     "isolated-vertex"}
)
"""``validate`` kinds about the file's geometry (reported by ``check``, read by readers)."""

GEOMETRIC_KINDS3 = frozenset(
    {"non-manifold-edge", "non-manifold-vertex", "boundary", "isolated-vertex"}
)
"""``validate3`` kinds about the file's geometry (a reader reads them)."""

MESSAGE_LIMIT = 1500
"""The longest problem text a reader may give (quotes are ~200 characters each)."""


@attrs.frozen
class Case:
    """Seed files (name -> bytes), the file read, its format, what reads it, and what the
    unmutated seed gives (``"value"``, or ``"error"`` for a file the reader refuses)."""

    name: str
    files: dict[str, bytes]
    main: str
    format: str | None = None
    trace: bool = False
    seed_gives: str = "value"


def _grid_mesh() -> Mesh2:
    points = [(x, y) for y in range(3) for x in range(3)]
    triangles = []
    for j in range(2):
        for i in range(2):
            a = 3 * j + i
            triangles += [(a, a + 1, a + 4), (a, a + 4, a + 3)]
    mesh = mesh_from_triangles(points, triangles)
    transient = Transient2(mesh)
    for u, v in ((0, 1), (1, 2), (2, 5)):
        transient.set_segment(u, v, 2)
    transient.set_triangle_attributes((0, 1, 4), (mpq(1, 3),))
    return transient.seal()


def _pslg() -> PSLG:
    square = [point2(0, 0), point2(4, 0), point2(4, 4), point2(0, 4)]
    inner = [point2(1, 1), point2(2, 1), point2(mpq(3, 2), 2)]
    segments = [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1), (4, 5, 0), (5, 6, 0), (6, 4, 0)]
    return PSLG(
        vertices=square + inner,
        segments=segments,
        holes=[point2(mpq(3, 2), mpq(3, 2))],
        regions=[RegionSeed(point2(3, 3), mpq(2), mpq(1, 2))],
        vertex_markers=[1, 1, 1, 1, 0, 0, 0],
    )


def _written(value: Any, name: str, format: str | None = None) -> dict[str, bytes]:
    with tempfile.TemporaryDirectory() as directory:
        io.write(Path(directory) / name, value, format=format)
        return {path.name: path.read_bytes() for path in sorted(Path(directory).iterdir())}


@functools.cache
def seeds() -> tuple[Case, ...]:
    """The valid seed files of every reader."""
    mesh, pslg = _grid_mesh(), _pslg()
    polygons = PolygonMesh(
        vertices=[point2(0, 0), point2(2, 0), point2(2, 2), point2(0, 2), point2(3, 1)],
        polygons=[(0, 1, 2, 3), (1, 4, 2)],
    )
    triangle_files = _written(mesh, "m.ele")
    geomview = (b"{ appearance {+edge +face linewidth 2} LIST\n{ "
                + _written(mesh, "m.off")["m.off"] + b"}\n}\n")
    node_beside = _written(pslg, "p.node") | {"p.poly": b"0 2 0 1\n7 1\n0 0 1 1\n1 1 2 1\n"
                                                         b"2 2 3 1\n3 3 0 1\n4 4 5 0\n"
                                                         b"5 5 6 0\n6 6 4 0\n1\n0 1.5 1.5\n"}
    one_based = (b"# a 1-based poly\n4 2 0 1\n1 0 0 1\n2 4 0 1\n3 4 4 1\n4 0 4 1\n"
                 b"4 1\n1 1 2 5\n2 2 3 5\n3 3 4 5\n4 4 1 5\n0\n1\n1 1 1 3 -1\n")
    from geomexact import triangulate

    construction = triangulate(pslg)
    cases = [
        Case("triangle", triangle_files, "m.ele"),
        Case("node", _written(pslg, "p.node"), "p.node"),
        Case("poly", _written(pslg, "p.poly"), "p.poly"),
        Case("poly-node-beside", node_beside, "p.poly"),
        Case("poly-one-based", {"o.poly": one_based}, "o.poly"),
        Case("off", _written(mesh, "m.off"), "m.off"),
        Case("off-polygons", _written(polygons, "q.off"), "q.off"),
        Case("off-geomview", {"g.off": geomview}, "g.off"),
        Case("pslg", _written(pslg, "p.pslg"), "p.pslg"),
        Case("pslg-mesh", _written(mesh, "m.pslg"), "m.pslg"),
        Case("trilist", _written(mesh, "m.txt"), "m.txt"),
        Case("trace", {"t.jsonl": trace_text(construction.trace).encode()}, "t.jsonl",
             trace=True),
    ]
    return tuple(cases)


ONE_BASED_TETGEN = {
    "t.node": b"# 1-based, an attribute and markers\n5 3 1 1\n1 0 0 0 0.5 1\n"
              b"2 1 0 0 1/3 1\n3 0 1 0 2 0\n4 0 0 1 -1 1\n5 1 1 1 7 2\n",
    "t.ele": b"2 4 1\n1 1 2 3 4 10\n2 2 3 4 5 20\n",
    "t.face": b"6 1\n1 1 2 3 1\n2 1 2 4 1\n3 1 3 4 1\n4 2 3 5 2\n5 2 4 5 2\n6 3 4 5 2\n",
}
"""Two tetrahedra sharing a face, 1-based, with node attributes, markers, a tetrahedron
attribute and face markers (every optional column of the TetGen reader)."""


def _cube() -> Mesh3:
    from helpers.mesh3d_cases import cube_grid

    return cube_grid(1, 1, 1)


@functools.cache
def seeds3d() -> tuple[Case, ...]:
    """The valid seed files of the 3D readers that need no meshio: TetGen (selected by
    the ``.node``'s dimension and named by ``format="tetgen"``) and the Geomview OFF
    pictures of a ``Mesh3``, read back by the OFF reader (whose vertices have z ≠ 0)."""
    cube = _cube()
    tetgen = _written(cube, "m.ele")
    return (
        Case("tetgen", tetgen, "m.ele"),
        Case("tetgen-named", tetgen, "m.ele", format="tetgen"),
        Case("tetgen-one-based", ONE_BASED_TETGEN, "t.ele"),
        # OFF is read as planar: a 3D picture is refused at its first vertex with z != 0
        Case("off-geomview3d", _written(cube, "g.off", "geomview3d"), "g.off",
             seed_gives="error"),
        Case("off-geomview3d-boundary", _written(cube, "b.off", "geomview3d-boundary"),
             "b.off", seed_gives="error"),
    )


def _meshio_text(value: Mesh2 | Mesh3, name: str) -> dict[str, bytes]:
    """``value`` written by meshio itself as text (``binary=False``): the ASCII forms
    of VTK and VTU, which geomexact's writer (binary) does not make."""
    import meshio
    import numpy

    if isinstance(value, Mesh3):
        cells = [("tetra", numpy.array(value.tetrahedra()))]
        points = [[float(c) for c in (p.x, p.y, p.z)] for p in value.point_list()]
    else:
        cells = [("triangle", numpy.array(value.triangles()))]
        points = [[float(p.x), float(p.y), 0.0] for p in value.point_list()]
    with tempfile.TemporaryDirectory() as directory:
        path = Path(directory) / name
        with contextlib.redirect_stdout(StringIO()), contextlib.redirect_stderr(StringIO()):
            meshio.write(path, meshio.Mesh(numpy.array(points), cells), binary=False,
                         **({"file_format": "gmsh"} if name.endswith(".msh") else {}))
        return {name: path.read_bytes()}


def meshio_seeds() -> tuple[Case, ...]:
    """meshio formats: VTK legacy (binary), Gmsh 2.2 and 4.1 text, VTU (zlib, base64) of a
    triangle mesh and of tetrahedra, and the ASCII VTK and VTU of tetrahedra; empty
    without meshio."""
    try:
        import meshio  # noqa: F401
    except ImportError:
        return ()
    mesh, cube = _grid_mesh(), _cube()
    return (
        Case("vtk", _written(mesh, "m.vtk"), "m.vtk"),
        Case("msh", _written(mesh, "m.msh"), "m.msh"),
        # Gmsh 4.1 text of the plain triangles (geomexact writes Gmsh 2.2, which holds
        # the segments and attributes): the files of tests/io/test_io_fuzz_found.py
        Case("msh41", _meshio_text(mesh, "m.msh"), "m.msh"),
        Case("vtu", _written(mesh, "m.vtu"), "m.vtu"),
        Case("vtk-tetra", _written(cube, "c.vtk"), "c.vtk"),
        Case("vtu-tetra", _written(cube, "c.vtu"), "c.vtu"),
        Case("vtk-tetra-ascii", _meshio_text(cube, "a.vtk"), "a.vtk"),
        Case("vtu-tetra-ascii", _meshio_text(cube, "a.vtu"), "a.vtu"),
    )


# -----------------------------------------------------------------------------------------
# mutations
# -----------------------------------------------------------------------------------------
NUMBERS = (
    b"-1", b"0", b"1", b"2", b"3", b"7", b"1e400", b"1e-400", b"9" * 5000, b"1/0", b"nan",
    b"inf", b"-0", b"0x10", b"1_0", b"\xd9\xa3", b"1.5", b"-2.25", b"1/3", b"99999999999",
    b"2147483648", b"18446744073709551616", b"1e99999999", b"",
)
INSERTS = (
    b"\x00", b"\xff", b"\xc3\xa9", b"\xe2\x80\xa8", b"\xef\xbb\xbf", b"\r", b"\t", b"#",
    b"{", b"}", b"appearance {", b"LIST", b"OFF", b"\n", b"\n\n", b" ", b"v 0 0", b"s 0 1",
    b"t 0 1 2", b"n -1 -1 -1", b"h 0 0", b"r 0 0 1", b'{"i": 1}', b"[" * 3000,
)


def mutate(data: bytes, rng: random.Random, count: int) -> bytes:
    """``count`` random mutations of ``data``: byte flips, line deletions, duplications
    and swaps, number replacements (huge, negative, malformed, non-ASCII digits),
    insertions (unicode, NUL, braces, records), truncation and very long lines."""
    for _ in range(count):
        lines = data.split(b"\n")
        kind = rng.randrange(9)
        if kind == 0 and data:  # flip a byte
            at = rng.randrange(len(data))
            data = data[:at] + bytes([rng.randrange(256)]) + data[at + 1:]
        elif kind == 1 and len(lines) > 1:  # delete a line
            del lines[rng.randrange(len(lines))]
            data = b"\n".join(lines)
        elif kind == 2:  # duplicate a line
            at = rng.randrange(len(lines))
            lines.insert(at, lines[at])
            data = b"\n".join(lines)
        elif kind == 3 and len(lines) > 1:  # swap two lines
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
            data = b"\n".join(lines)
        elif kind == 4:  # replace a token by a number
            at = rng.randrange(len(lines))
            tokens = lines[at].split(b" ")
            tokens[rng.randrange(len(tokens))] = rng.choice(NUMBERS)
            lines[at] = b" ".join(tokens)
            data = b"\n".join(lines)
        elif kind == 5:  # insert something
            at = rng.randrange(len(data) + 1)
            data = data[:at] + rng.choice(INSERTS) + data[at:]
        elif kind == 6 and data:  # truncate
            data = data[: rng.randrange(len(data))]
        elif kind == 7:  # a very long line
            at = rng.randrange(len(lines))
            lines[at] = lines[at] + b" " + b" ".join([b"1"] * rng.choice((10, 50_000)))
            data = b"\n".join(lines)
        else:  # a token made very long
            at = rng.randrange(len(lines))
            lines[at] = lines[at] + b"7" * rng.choice((300, 200_000))
            data = b"\n".join(lines)
    return data


# -----------------------------------------------------------------------------------------
# the contract
# -----------------------------------------------------------------------------------------
def _lines_of(path: Path) -> int:
    return path.read_bytes().count(b"\n") + 1


def check_value(value: Any) -> None:
    """Assert that a value a reader returned is well formed (module docstring)."""
    if isinstance(value, Mesh2):
        structural = [v for v in validate(value) if v.kind not in GEOMETRIC_KINDS]
        assert not structural, structural
    elif isinstance(value, Mesh3):
        structural3 = [v for v in validate3(value) if v.kind not in GEOMETRIC_KINDS3]
        assert not structural3, structural3
        for point in value.point_list():
            assert all(isinstance(c, EXACT) for c in (point.x, point.y, point.z))
    elif isinstance(value, PolygonMesh):
        assert all(len(polygon) >= 3 for polygon in value.polygons)
        count = len(value.vertices)
        assert all(0 <= v < count for polygon in value.polygons for v in polygon)
        validate_polygon_mesh(value, geometric=True)  # must not raise, whatever it finds
    elif isinstance(value, PSLG):
        count = len(value.vertices)
        assert all(0 <= u < count and 0 <= v < count and u != v
                   for u, v, _ in value.segments)
        assert len(value.vertex_markers) in (0, count)
        assert len(value.vertex_attributes) in (0, count)
        assert len({len(row) for row in value.vertex_attributes}) <= 1
        for point in (*value.vertices, *value.holes, *(r.point for r in value.regions)):
            assert isinstance(point.x, EXACT) and isinstance(point.y, EXACT)
    elif isinstance(value, Trace):
        assert len(value.steps) == len(value.digests)
        assert all(0 <= digest < 1 << 128 for digest in (value.input_digest, *value.digests))
        for step in value.steps:
            assert isinstance(step.op, str)
            assert all(isinstance(a, int | EXACT) and not isinstance(a, bool)
                       for a in step.args)
    else:  # pragma: no cover - a reader returned something else
        raise AssertionError(f"a reader returned a {type(value).__name__}")


class Hang(BaseException):
    """A read that took longer than its time limit (a BaseException: no reader's
    ``except Exception`` may turn it into a FormatError)."""


@contextlib.contextmanager
def time_limit(seconds: int) -> Iterator[None]:
    """Raise :class:`Hang` in the block after ``seconds`` (SIGALRM; no limit without it)."""
    if not hasattr(signal, "SIGALRM"):
        yield
        return

    def stop(signum: int, frame: object) -> None:
        raise Hang(f"the read took more than {seconds} s")

    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def check_read(directory: Path, case: Case, files: dict[str, bytes]) -> str:
    """Write ``files`` into ``directory``, read ``case.main`` and assert the contract;
    returns ``"value"`` or ``"error"`` (for statistics)."""
    for name, data in files.items():
        (directory / name).write_bytes(data)
    path = directory / case.main
    reader: Callable[[], Any] = (
        (lambda: read_trace(path)) if case.trace
        else (lambda: io.read(path, format=case.format))
    )
    try:
        with time_limit(20):
            value = reader()
    except FormatError as error:
        named = Path(error.path)
        assert named.name in files, f"the error names {error.path}, not a file of the case"
        if error.line is not None:
            assert 1 <= error.line <= _lines_of(named), (error.line, str(error)[:300])
        assert error.problem and len(error.problem) <= MESSAGE_LIMIT, error.problem[:300]
        assert str(error).startswith(str(error.path)), str(error)[:300]
        return "error"
    check_value(value)
    return "value"
