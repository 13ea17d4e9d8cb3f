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
from geomexact.mesh3d.cuboid.partition import initial_mesh, partition_cuboid
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


# -- replaying a cuboid trace from the command line ---------------------------------------
def _cuboid_files(tmp_path: Path, capsys: pytest.CaptureFixture[str], *options: str
                  ) -> tuple[dict[str, Path], Any]:
    paths = {name: tmp_path / f"{name}.ele" for name in ("start", "final")}
    paths["trace"] = tmp_path / "run.trace"
    code, report = run_json(capsys, "cuboid", *options, "-o", str(paths["final"]),
                            "--start", str(paths["start"]), "--trace", str(paths["trace"]),
                            "--json")
    assert code == 0
    return paths, report


def _same_files(one: Path, other: Path) -> None:
    for suffix in (".node", ".ele", ".face"):
        assert one.with_suffix(suffix).read_bytes() == other.with_suffix(suffix).read_bytes()


@pytest.mark.parametrize(("options", "volume"), [
    (("0",), "1"),
    (("70688", "--improve"), "1"),
    (("4096", "--template", "1", "--improve"), "1"),
    (("262143", "--improve", "--order", "index"), "1"),
    (("70688", "--shape", "1", "2", "4", "--improve"), "8"),
    (("262143", "--shape", "1", "2", "4", "--order", "index", "--template", "1",
      "--improve"), "8"),
])
def test_cuboid_trace_replays_from_the_start_file_and_from_the_trace_alone(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], options: tuple[str, ...], volume: str
) -> None:
    """cuboid -o FINAL --start START --trace T, then replay START T -o AGAIN: every digest
    checked, the same final digest and byte-identical files; replay T alone rebuilds the
    start from the trace's parameters and gives the same."""
    paths, report = _cuboid_files(tmp_path, capsys, *options)
    assert report["volume"] == volume
    assert read_trace(paths["trace"]).input_name == "start.ele"
    again = tmp_path / "again.ele"
    code, replayed = run_json(capsys, "replay", str(paths["start"]), str(paths["trace"]),
                              "-o", str(again), "--json")
    assert code == 0 and replayed["diverged"] is False and replayed["rebuilt_start"] is False
    assert replayed["final_digest"] == report["digest"]
    assert replayed["input_digest"] == report["start_digest"]
    assert replayed["trace_steps"] == replayed["steps_applied"] == report["steps"]
    assert replayed["tetrahedra"] == report["tetrahedra"] and replayed["dimension"] == 3
    assert "triangles" not in replayed
    _same_files(again, paths["final"])
    alone = tmp_path / "alone.ele"
    code, rebuilt = run_json(capsys, "replay", str(paths["trace"]), "-o", str(alone), "--json")
    assert code == 0 and rebuilt["input"] is None and rebuilt["rebuilt_start"] is True
    assert rebuilt["final_digest"] == report["digest"]
    _same_files(alone, paths["final"])


def test_cuboid_start_is_exact_on_a_box_of_thirds(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A box corner 1/3 has no decimal expansion: --start writes it as p/q anyway (the
    start must be the trace's input); the text output lists every file written."""
    start, trace = tmp_path / "s.ele", tmp_path / "t.trace"
    assert main(["cuboid", "70688", "--shape", "1/3", "1", "1", "--improve", "--start",
                 str(start), "--trace", str(trace)]) == 0
    out = capsys.readouterr().out
    assert f"wrote {start}" in out and f"wrote {trace}" in out
    assert "1/3" in start.with_suffix(".node").read_text()
    assert main(["replay", str(start), str(trace), "-o", str(tmp_path / "r.ele"),
                 "--exact"]) == 0
    assert "(all digests match)" in capsys.readouterr().out


def test_cuboid_start_as_vtu(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The unit cube's corners are doubles: a .vtu start replays; a box corner 1/3 is not
    one, so a .vtu start is refused (exit 2) and nothing is written."""
    pytest.importorskip("meshio")
    start, trace = tmp_path / "s.vtu", tmp_path / "t.trace"
    assert main(["cuboid", "70688", "--improve", "--start", str(start), "--trace",
                 str(trace)]) == 0
    capsys.readouterr()
    code, replayed = run_json(capsys, "replay", str(start), str(trace), "-o",
                              str(tmp_path / "r.ele"), "--json")
    assert code == 0 and replayed["final_digest"] == partition_cuboid(
        70688, improve=True).mesh.digest_text
    thirds = tmp_path / "thirds.vtu"
    assert main(["cuboid", "5", "--shape", "1/3", "1", "1", "--start", str(thirds),
                 "--trace", str(tmp_path / "t3.trace")]) == 2
    assert "stores doubles" in capsys.readouterr().err
    assert not thirds.exists() and not (tmp_path / "t3.trace").exists()


def test_replay_of_a_cuboid_trace_on_the_wrong_mesh(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The final mesh given as INPUT: exit 2, nothing on stdout or written, and the message
    names the trace, both digests and that the input is the mesh after the last step; the
    start of the other template is simply not the trace's input."""
    paths, report = _cuboid_files(tmp_path, capsys, "70688", "--improve")
    out = tmp_path / "r.ele"
    code = main(["replay", str(paths["final"]), str(paths["trace"]), "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "" and not out.exists()
    error = captured.err
    assert error.count("\n") == 1 and error.startswith("geomexact: error: ")
    assert f"{paths['trace']} was recorded on 'start.ele' (digest {report['start_digest']})"\
        in error
    assert f"{paths['final']} gives digest {report['digest']}" in error
    assert f"after step {report['steps']} of {report['steps']} (its final mesh)" in error
    assert "--start" in error
    other = tmp_path / "other"
    other.mkdir()
    assert main(["cuboid", "70688", "--template", "1", "--start", str(other / "s.ele")]) == 0
    capsys.readouterr()
    assert main(["replay", str(other / "s.ele"), str(paths["trace"]), "-o", str(out)]) == 2
    assert "not the trace's input" in capsys.readouterr().err and not out.exists()


def test_replay_of_a_tampered_cuboid_trace_reports_the_first_divergence(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A step digest changed in the file: exit 1, the trace file, the step number and the
    expected and found digests, on stderr and in the JSON object; nothing written."""
    paths, _ = _cuboid_files(tmp_path, capsys, "70688", "--improve")
    lines = paths["trace"].read_text().splitlines()
    step = json.loads(lines[3])
    true_digest = step["digest"]
    step["digest"] = "0" * 32
    lines[3] = json.dumps(step, sort_keys=True, separators=(",", ":"))
    paths["trace"].write_text("\n".join(lines) + "\n")
    out = tmp_path / "never.ele"
    code = main(["replay", str(paths["start"]), str(paths["trace"]), "-o", str(out),
                 "--json"])
    captured = capsys.readouterr()
    assert code == 1 and not out.exists() and not out.with_suffix(".node").exists()
    report = json.loads(captured.out)
    assert report["diverged"] is True and report["step"] == 3
    assert report["expected_digest"] == "0" * 32 and report["found_digest"] == true_digest
    assert f"geomexact: trace diverged: {paths['trace']}: step 3 (" in captured.err
    assert f"gave digest {true_digest}, the trace recorded {'0' * 32}" in captured.err


def test_replay_refuses_a_trace_of_the_other_dimension(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 3D trace on a triangle mesh, a 2D trace on a tetrahedral mesh, a 2D trace with no
    INPUT: exit 2 with a clear message, nothing on stdout, nothing written."""
    paths, _ = _cuboid_files(tmp_path, capsys, "70688", "--improve")
    square = tmp_path / "square.off"
    square.write_text("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n")
    out = tmp_path / "r.off"
    code = main(["replay", str(square), str(paths["trace"]), "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "" and not out.exists()
    assert (f"{paths['trace']} is a 3D trace (of a tetrahedral mesh), but {square} is a "
            "triangle mesh (2D)") in captured.err
    points, trace2d = tmp_path / "p.node", tmp_path / "p.trace"
    points.write_text("4 2 0 0\n0 0 0\n1 1 0\n2 1 1\n3 0 1\n")
    assert main(["triangulate", str(points), "--trace", str(trace2d)]) == 0
    capsys.readouterr()
    out3 = tmp_path / "r.ele"
    code = main(["replay", str(paths["start"]), str(trace2d), "-o", str(out3), "--json"])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "" and not out3.exists()
    assert (f"{trace2d} is a 2D trace (of a triangle mesh), but {paths['start']} is a "
            "tetrahedral mesh (3D)") in captured.err
    assert main(["replay", str(trace2d), "-o", str(out3)]) == 2
    assert "give the INPUT mesh" in capsys.readouterr().err and not out3.exists()


def test_cuboid_and_replay_never_overwrite_without_force(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every output is checked before anything is written: an existing --start (or a
    companion file of -o) refuses the whole run; replay refuses an existing OUT and leaves
    it unchanged; --force replaces both; two options naming one file are refused."""
    paths, _ = _cuboid_files(tmp_path, capsys, "70688", "--improve")
    fresh = tmp_path / "fresh.ele"
    code = main(["cuboid", "70688", "-o", str(fresh), "--start", str(paths["start"])])
    assert code == 2 and "refusing to overwrite" in capsys.readouterr().err
    assert not fresh.exists() and not fresh.with_suffix(".node").exists()
    lone_node = tmp_path / "lone.node"
    lone_node.write_text("keep\n")
    assert main(["cuboid", "1", "-o", str(tmp_path / "lone.ele")]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert lone_node.read_text() == "keep\n"
    before = paths["final"].read_bytes()
    code = main(["replay", str(paths["start"]), str(paths["trace"]), "-o",
                 str(paths["final"])])
    assert code == 2 and "refusing to overwrite" in capsys.readouterr().err
    assert paths["final"].read_bytes() == before
    assert main(["replay", str(paths["start"]), str(paths["trace"]), "-o",
                 str(paths["final"]), "--force"]) == 0
    assert paths["final"].read_bytes() == before
    assert main(["cuboid", "70688", "--improve", "-o", str(paths["final"]), "--start",
                 str(paths["start"]), "--trace", str(paths["trace"]), "--force"]) == 0
    capsys.readouterr()
    same = tmp_path / "same.ele"
    assert main(["cuboid", "1", "-o", str(same), "--start", str(same)]) == 2
    assert "would both write" in capsys.readouterr().err and not same.exists()
