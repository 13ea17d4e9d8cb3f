"""``geomexact cuboid`` and ``geomexact census``: JSON keys, the trace written and
replayed, CSV rows in pattern order, refusing to overwrite, the summary object, and the
exit codes of bad input."""

from __future__ import annotations

import csv
import importlib.util
import json
from pathlib import Path
from typing import Any

import pytest

from geomexact.cli import main
from geomexact.io.trace_file import read_trace
from geomexact.mesh3d.cuboid.boxes import box_of_extents
from geomexact.mesh3d.cuboid.census import CENSUS_COLUMNS
from geomexact.mesh3d.cuboid.partition import initial_mesh
from geomexact.trace.playback import replay


def run_json(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, Any]:
    code = main(list(argv))
    out = capsys.readouterr().out
    return code, json.loads(out) if out.strip().startswith("{") else out


def test_cuboid_json(capsys: pytest.CaptureFixture[str]) -> None:
    code, report = run_json(capsys, "cuboid", "70688", "--json")
    assert code == 0
    for key in ("tetrahedra", "volume", "valid", "delaunay", "flips", "configurations",
                "faces"):
        assert key in report
    assert report["bits"] == [5, 10, 12, 16] and report["volume"] == "1"
    assert report["valid"] is True and report["flips"] is None
    assert set(report["faces"]) == {"x=0", "x=1", "y=0", "y=1", "z=0", "z=1"}
    assert report["faces"]["x=0"] == [["c0", "c4", "f12"], ["c0", "f12", "c2"],
                                      ["c2", "f12", "c6"], ["c4", "c6", "f12"]]
    assert report["configurations"]["T23"]["total"] >= report["configurations"]["T23"][
        "failing"]


def test_cuboid_improved_on_a_box_writes_a_trace_that_replays(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    trace_path = tmp_path / "run.trace"
    code, report = run_json(capsys, "cuboid", "262143", "--shape", "1", "2", "4",
                            "--order", "index", "--improve", "--trace", str(trace_path),
                            "--json")
    assert code == 0 and report["volume"] == "8" and report["flips"]["total"] >= 0
    trace = read_trace(trace_path)
    box = box_of_extents(1, 2, 4)
    assert replay(initial_mesh(box, 0), trace).digest_text == report["digest"]
    assert trace.parameter("pattern") == 262143 and trace.parameter("order") == "index"
    assert main(["cuboid", "1", "--trace", str(trace_path)]) == 2  # exists: no --force
    assert "refusing to overwrite" in capsys.readouterr().err
    assert main(["cuboid", "1", "--trace", str(trace_path), "--force"]) == 0


def test_cuboid_text_and_bad_input(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["cuboid", "4096", "--shape", "1/3", "0.5", "2", "--template", "1"]) == 0
    out = capsys.readouterr().out
    assert "box faces" in out and "volume" in out
    assert main(["cuboid", "262144"]) == 2
    assert main(["cuboid", "5", "--shape", "1", "0", "1"]) == 2
    assert main(["cuboid", "5", "--order", "random"]) == 2


def test_census_writes_rows_in_pattern_order(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "census.csv"
    code, summary = run_json(capsys, "census", "--patterns", "4090-4105", "--improve",
                             "--workers", "2", "--chunk-size", "5", "-o", str(out),
                             "--no-parquet", "--json")
    assert code == 0
    with out.open() as handle:
        rows = list(csv.DictReader(handle))
    assert list(rows[0]) == list(CENSUS_COLUMNS)
    assert [int(r["pattern"]) for r in rows] == list(range(4090, 4106))
    assert all(r["valid"] == "1" and r["valid_improved"] == "1" for r in rows)
    (group,) = summary["summaries"]
    assert group["patterns"] == 16 and group["shape"] == "1x1x1"
    assert summary["written"] == [str(out)]
    assert main(["census", "--patterns", "1-3", "-o", str(out)]) == 2  # no --force
    assert "refusing to overwrite" in capsys.readouterr().err
    assert main(["census", "--patterns", "1,5", "-o", str(out), "--force",
                 "--no-parquet"]) == 0
    text = capsys.readouterr().out
    assert "census of 2 patterns" in text
    assert out.read_text().count("\n") == 3


def test_census_same_rows_for_both_engines_and_bad_input(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    files = []
    for engine in ("reference", "compiled"):
        path = tmp_path / f"{engine}.csv"
        assert main(["census", "--patterns", "4100-4110", "--shape", "1", "2", "4",
                     "--order", "index", "--improve", "--workers", "1", "--engine", engine,
                     "-o", str(path), "--no-parquet"]) == 0
        files.append(path.read_text())
    assert files[0] == files[1]
    capsys.readouterr()
    assert main(["census", "--patterns", "9-3"]) == 2
    assert main(["census", "--workers", "0"]) == 2


@pytest.mark.skipif(importlib.util.find_spec("pyarrow") is None, reason="no pyarrow")
def test_census_writes_parquet_beside_the_csv(tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    import pyarrow.parquet as parquet

    out = tmp_path / "c.csv"
    assert main(["census", "--patterns", "1-20", "-o", str(out), "--workers", "1"]) == 0
    table = parquet.read_table(tmp_path / "c.parquet")
    assert table.column_names == list(CENSUS_COLUMNS)
    assert table.column("pattern").to_pylist() == list(range(1, 21))
