"""The commands write the mesh they report (issue 11, part 1): lossless by default,
rounding counted and re-checked, dropped parts named, colliding outputs refused."""

from __future__ import annotations

import json
import math
import random
from decimal import Decimal, localcontext
from pathlib import Path

import pytest

from geomexact import io
from geomexact.cli import main
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.summary import mesh_summary


def _run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def _near_circle(directory: Path) -> Path:
    """12 points within 1e-17 of the unit circle, written with 18 significant digits:
    their Delaunay triangulation is not Delaunay once rounded to doubles (seed found by
    search; the check below keeps it honest)."""
    rng = random.Random(1)
    lines = ["12 2 0 0"]
    with localcontext() as context:
        context.prec = 40
        for index in range(12):
            angle = 2 * math.pi * index / 12
            x = Decimal(repr(math.cos(angle))) + rng.randint(-9, 9) * Decimal("1e-18")
            y = Decimal(repr(math.sin(angle))) + rng.randint(-9, 9) * Decimal("1e-18")
            lines.append(f"{index} {x} {y}")
    path = directory / "circle.node"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def test_the_default_file_is_the_reported_mesh(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Before: the file held the nearest doubles and `info` found it not Delaunay."""
    source = _near_circle(tmp_path)
    code, out, err = _run(capsys, "triangulate", source, "-o", tmp_path / "c.off", "--json")
    assert code == 0 and err == ""
    reported = json.loads(out)
    written = io.read(tmp_path / "c.off")
    assert isinstance(written, Mesh2)
    assert written.digest_text == reported["digest"]
    assert mesh_summary(written)["is_delaunay"] is reported["is_delaunay"] is True


def test_rounding_is_counted_and_rechecked(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    source = _near_circle(tmp_path)
    code, _, err = _run(capsys, "triangulate", source, "-o", tmp_path / "c.off", "--float")
    assert code == 0
    assert "numbers rounded to the nearest double (--float)" in err
    assert "is_delaunay is true in the mesh but false in the rounded file" in err
    assert "Traceback" not in err


def test_a_value_without_a_finite_decimal_is_rounded_with_a_warning_or_exact(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    source = tmp_path / "third.off"
    source.write_text("OFF\n3 1 0\n0 0 0\n1/3 0 0\n0 1 0\n3 0 1 2\n", encoding="utf-8")
    code, _, err = _run(capsys, "convert", source, tmp_path / "a.off")
    assert code == 0
    assert "1 number with no finite decimal expansion rounded" in err and "--exact" in err
    code, _, err = _run(capsys, "convert", source, tmp_path / "b.off", "--exact")
    # exact, and the only word is that other programs' OFF readers refuse p/q (issue 26)
    assert code == 0 and "number with no finite decimal" not in err and "OFF readers" in err
    assert "1/3" in (tmp_path / "b.off").read_text(encoding="utf-8")


def test_convert_names_what_the_format_drops(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Before: boundary markers were dropped silently."""
    (tmp_path / "m.node").write_text(
        "4 2 1 1\n0 0 0 5 1\n1 1 0 6 1\n2 1 1 7 0\n3 0 1 8 2\n", encoding="utf-8"
    )
    (tmp_path / "m.ele").write_text("2 3 0\n0 0 1 2\n1 0 2 3\n", encoding="utf-8")
    code, _, err = _run(capsys, "convert", tmp_path / "m.ele", tmp_path / "m.off")
    assert code == 0
    assert ("the off format cannot hold 3 nonzero vertex markers and 4 vertices with "
            "attributes; they were not written") in err
    code, _, err = _run(capsys, "convert", tmp_path / "m.ele", tmp_path / "n.pslg")
    assert code == 0 and err == ""


@pytest.mark.parametrize("force", [False, True])
def test_the_same_path_for_mesh_and_trace_is_refused_before_writing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], force: bool
) -> None:
    source = _near_circle(tmp_path)
    target = tmp_path / "x.off"
    extra = ["--force"] if force else []
    for command in (["triangulate", source], ["refine", source, "--max-area", "0.5"]):
        code, _, err = _run(capsys, *command, "-o", target, "--trace", target, *extra)
        assert code == 2
        assert "-o and --trace would both write" in err, err
        assert not target.exists()
    # a companion counts: x.ele also writes x.node
    code, _, err = _run(capsys, "triangulate", source, "-o", tmp_path / "x.ele",
                        "--trace", tmp_path / "x.node", *extra)
    assert code == 2 and "would both write" in err
    assert sorted(path.name for path in tmp_path.iterdir()) == ["circle.node"]


def test_exact_is_refused_for_a_float_only_format(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    source = _near_circle(tmp_path)
    code, _, err = _run(capsys, "triangulate", source, "-o", tmp_path / "x.vtu", "--exact")
    assert code == 2 and "cannot hold exact numbers" in err
    assert not (tmp_path / "x.vtu").exists()
    code, _, err = _run(capsys, "triangulate", source, "-o", tmp_path / "x.vtu")
    assert code == 0 and "the format stores doubles" in err


def test_exact_and_float_exclude_each_other(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["convert", "a.off", "b.off", "--exact", "--float"]) == 2
    assert "not allowed with argument" in capsys.readouterr().err


def test_rounding_that_merges_two_vertices_is_reported(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Before: a rounded file held two vertices at the same coordinates, which geomexact
    itself then refused to read; now the default keeps them apart, and --float says."""
    source = tmp_path / "close.off"
    source.write_text(
        "OFF\n4 2 0\n0 0 0\n1 0 0\n0.33333333333333333333 1 0\n0.33333333333333333334 1 0\n"
        "3 0 1 2\n3 0 3 2\n".replace("3 0 3 2", "3 1 3 2"),
        encoding="utf-8",
    )
    code, _, err = _run(capsys, "convert", source, tmp_path / "a.off")
    assert code == 0 and err == ""
    assert io.read(tmp_path / "a.off").digest == io.read(source).digest
    code, _, err = _run(capsys, "convert", source, tmp_path / "b.off", "--float")
    assert code == 0
    assert "the rounded file does not read back" in err and "Traceback" not in err
