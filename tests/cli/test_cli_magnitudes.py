"""Every command at magnitudes beyond the doubles (issue 11): ``geomexact info`` reports
right angles and areas for tiny and huge meshes (edges near 1e-272 used to report a
minimum angle of 0; areas beyond the doubles made the command fail); ``info``, ``check``,
``triangulate``, ``refine``, ``polylla`` and ``view`` on coordinates of 1e309, 1e-400,
1e999, 200,001 digits and 1/(100,000 digits) give the unscaled results, scaled."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import attrs
import gmpy2
import pytest

from geomexact import io
from geomexact.cli import main
from geomexact.kernel.numbers import Rational, format_rational, mpq, parse_rational
from geomexact.kernel.points import point2
from geomexact.kernel.predicate_results import Orientation
from geomexact.kernel.predicates2d import orient2d, orient2d_exact
from geomexact.mesh2d.measures import total_area, triangle_area

TRIANGLE = [(0, 0), (3, 1), (1, 4)]  # angles 47.726…°, 57.528…°, 74.744…°


@pytest.mark.parametrize("exponent", [-272, -150, 0, 150, 200])
def test_info_reports_the_angles_of_a_scaled_triangle(
    exponent: int, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    lines = [f"{x}e{exponent} {y}e{exponent} 0" for x, y in TRIANGLE]
    (tmp_path / "t.off").write_text("OFF\n3 1 0\n" + "\n".join(lines) + "\n3 0 1 2\n")
    assert main(["info", str(tmp_path / "t.off"), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert round(report["min_angle_deg"], 9) == 47.726310994
    assert round(report["max_angle_deg"], 9) == 74.744881297
    if exponent == 200:  # the area, 5.5e400, is beyond the doubles: exact text
        assert report["min_area"] == report["total_area"]


# ---- every command at magnitudes beyond the doubles (issue 11) -----------------------------
# The quadrilateral QUAD, two triangles (each of area 11/2 before scaling), scaled by s.
# Each command must succeed with the output of the unscaled run scaled by s (exactly, for
# every exact number), or stop with one clear line (exit 2): never a traceback.

QUAD = [(0, 0), (3, 1), (1, 4), (4, 5)]
_DENOMINATOR = "1" + "0" * 99_998 + "7"  # 100,000 digits, not a finite decimal


@attrs.frozen
class Scale:
    """Coordinates ``v * s`` written as ``text(v)``."""

    name: str
    s: Rational
    text: Callable[[int], str]


SCALES = [
    Scale("1e309", mpq(10) ** 309, lambda v: f"{v}e309"),
    Scale("1e-400", mpq(10) ** -400, lambda v: f"{v}e-400"),
    Scale("1e999", mpq(10) ** 999, lambda v: f"{v}e999"),
    Scale("200001-digit", mpq(10) ** 200_000, lambda v: f"{v}{'0' * 200_000}" if v else "0"),
    Scale("1/100000-digit", mpq(1, gmpy2.mpz(_DENOMINATOR)), lambda v: f"{v}/{_DENOMINATOR}"),
    # a finite decimal: its text took minutes (a digit-by-digit loop over the denominator)
    Scale("1/10^99999", mpq(1, gmpy2.mpz(10) ** 99_999), lambda v: f"{v}/1{'0' * 99_999}"),
]
UNIT = Scale("1", mpq(1), str)


def _files(directory: Path, scale: Scale) -> tuple[Path, Path]:
    """The mesh (OFF) and its points (Triangle .node) at ``scale``."""
    rows = [(scale.text(x), scale.text(y)) for x, y in QUAD]
    off = directory / "quad.off"
    off.write_text("OFF\n4 2 0\n" + "".join(f"{x} {y} 0\n" for x, y in rows)
                   + "3 0 1 2\n3 1 3 2\n")
    node = directory / "quad.node"
    node.write_text("4 2 0 0\n" + "".join(f"{i} {x} {y}\n" for i, (x, y) in enumerate(rows)))
    return off, node


@pytest.fixture(scope="module", params=SCALES, ids=[scale.name for scale in SCALES])
def scaled(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory,
           ) -> tuple[Scale, Path, Path]:
    scale: Scale = request.param
    directory = tmp_path_factory.mktemp("scaled")
    return (scale, *_files(directory, scale))


@pytest.fixture(scope="module")
def unit(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    return _files(tmp_path_factory.mktemp("unit"), UNIT)


def _run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, Any, str]:
    """Exit code, the JSON report (None when stdout is not one) and stderr."""
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    try:
        report = json.loads(captured.out)
    except ValueError:
        report = None
    return code, report, captured.err


def _area_text(area: object, scale: Scale) -> object:
    """An area of the unit run as the scaled run reports it: the exact text of the
    scaled value (it is beyond the normal doubles at every scale here)."""
    return format_rational(parse_rational(str(area)) * scale.s * scale.s)


def _same_angles(report: dict[str, Any], expected: dict[str, Any]) -> None:
    for key in ("min_angle_deg", "max_angle_deg"):
        assert round(report[key], 9) == round(expected[key], 9)


def test_info_and_check_at_every_magnitude(
    scaled: tuple[Scale, Path, Path], unit: tuple[Path, Path],
    capsys: pytest.CaptureFixture[str],
) -> None:
    scale, off, _ = scaled
    code, report, _ = _run(capsys, "info", off, "--json")
    _, expected, _ = _run(capsys, "info", unit[0], "--json")
    assert code == 0
    _same_angles(report, expected)
    assert report["total_area"] == format_rational(11 * scale.s * scale.s)
    for key in ("min_area", "max_area", "mean_area"):
        assert report[key] == _area_text(expected[key], scale)
    assert report["is_delaunay"] is True
    code, report, _ = _run(capsys, "check", off, "--json")
    assert code == 0 and report["valid"] is True


def test_triangulate_at_every_magnitude(
    scaled: tuple[Scale, Path, Path], unit: tuple[Path, Path],
    capsys: pytest.CaptureFixture[str], tmp_path: Path,
) -> None:
    scale, _, node = scaled
    code, report, _ = _run(capsys, "triangulate", node, "-o", tmp_path / "t.ele", "--exact",
                           "--json")
    _, expected, _ = _run(capsys, "triangulate", unit[1], "-o", tmp_path / "u.ele", "--json")
    assert code == 0
    assert report["triangles"] == expected["triangles"] == 2
    assert report["total_area"] == format_rational(11 * scale.s * scale.s)
    written = io.read(tmp_path / "t.ele")
    again = io.read(tmp_path / "u.ele")
    assert sorted(written.triangles()) == sorted(again.triangles())
    assert [written.point(v) for v in range(4)] == [
        point2(again.point(v).x * scale.s, again.point(v).y * scale.s) for v in range(4)]


def test_refine_at_every_magnitude(
    scaled: tuple[Scale, Path, Path], unit: tuple[Path, Path],
    capsys: pytest.CaptureFixture[str], tmp_path: Path,
) -> None:
    """--max-area s^2 on the mesh scaled by s runs the steps of --max-area 1 unscaled."""
    scale, off, _ = scaled
    limit = scale.s * scale.s
    code, report, _ = _run(capsys, "refine", off, "--max-area", format_rational(limit),
                           "-o", tmp_path / "r.ele", "--exact", "--json")
    _, expected, _ = _run(capsys, "refine", unit[0], "--max-area", "1",
                          "-o", tmp_path / "u.ele", "--json")
    assert code == 0 and report["status"] == "complete"
    for key in ("steps", "bisections", "flips", "vertices", "triangles"):
        assert report[key] == expected[key]
    _same_angles(report, expected)
    refined = io.read(tmp_path / "r.ele")
    assert total_area(refined) == 11 * limit
    assert max(triangle_area(refined, t) for t in refined.triangles()) <= limit


def test_polylla_at_every_magnitude(
    scaled: tuple[Scale, Path, Path], unit: tuple[Path, Path],
    capsys: pytest.CaptureFixture[str], tmp_path: Path,
) -> None:
    scale, off, _ = scaled
    code, report, _ = _run(capsys, "polylla", off, "-o", tmp_path / "p.off", "--exact",
                           "--picture", tmp_path / "p.png", "--check", "--json")
    _, expected, _ = _run(capsys, "polylla", unit[0], "-o", tmp_path / "u.off", "--json")
    assert code == 0 and report["valid"] is True
    assert report["polygons"] == expected["polygons"]
    _same_angles(report["stats"], expected["stats"])
    assert report["stats"]["total_area"] == format_rational(11 * scale.s * scale.s)
    # (triangles only: the OFF files read back as triangle meshes)
    assert sorted(io.read(tmp_path / "p.off").triangles()) == sorted(
        io.read(tmp_path / "u.off").triangles())
    assert (tmp_path / "p.png").stat().st_size > 0


def test_view_at_every_magnitude(
    scaled: tuple[Scale, Path, Path], capsys: pytest.CaptureFixture[str], tmp_path: Path,
) -> None:
    """The page and the picture are drawn scaled exactly by a power of two (said on
    both); the page's exact coordinates are the file's."""
    scale, off, node = scaled
    for source, output in ((off, "v.html"), (node, "n.html"), (off, "v.png")):
        code, report, _ = _run(capsys, "view", source, "-o", tmp_path / output, "--json")
        assert code == 0 and report["bytes"] > 0
    page = (tmp_path / "v.html").read_text()
    data = json.loads(page.split('id="geomexact-data">', 1)[1].split("</script>", 1)[0])
    exponent = data["scene"]["scale_exponent"]
    assert mpq(2) ** exponent <= scale.s * 5 < mpq(2) ** (exponent + 1)  # drawn: 5 -> [1, 2)
    assert any("2^" in note for note in data["notes"])
    assert data["scene"]["exact"][3] == format_rational(4 * scale.s) + " " + format_rational(
        5 * scale.s)


@pytest.mark.parametrize("command", ["triangulate", "refine", "polylla"])
def test_numbers_beyond_the_doubles_are_written_losslessly(
    command: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Files are lossless by default: 3e309 (no double holds it) is written as itself, and
    the file read back is the mesh reported; ``--float`` keeps such a number too (there is
    no nearest double to round it to) instead of writing inf or failing."""
    off, node = _files(tmp_path, SCALES[0])
    source = node if command == "triangulate" else off
    extra = ["--max-area", "1e618"] if command == "refine" else []
    for flags, name in (([], "out.off"), (["--float"], "float.off")):
        code, _, err = _run(capsys, command, source, *extra, "-o", tmp_path / name, *flags)
        assert code == 0, err
        assert "Traceback" not in err
        assert "3e309" in (tmp_path / name).read_text()
        assert io.read(tmp_path / name) == io.read(tmp_path / "out.off")


def test_a_far_vertex_that_turns_a_triangle_is_reported_exactly(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Vertex 0 moved to (1e999, 0) really makes triangle 0 clockwise (the exact
    orientation, no filter involved) while triangle 1 stays counter-clockwise: the mixed
    orientations error is right, not a float artefact."""
    rows = ["1e999 0", "3 1", "1 4", "4 5"]
    path = tmp_path / "far.off"
    path.write_text("OFF\n4 2 0\n" + "".join(f"{row} 0\n" for row in rows)
                    + "3 0 1 2\n3 1 3 2\n")
    points = [point2(*row.split()) for row in rows]
    assert orient2d_exact(points[0], points[1], points[2]) == Orientation.CLOCKWISE
    assert orient2d_exact(points[1], points[3], points[2]) == Orientation.COUNTERCLOCKWISE
    assert orient2d(points[0], points[1], points[2]) == Orientation.CLOCKWISE
    code, _, err = _run(capsys, "info", path)
    assert code == 2 and "mixed orientations" in err and "triangle 0" in err
