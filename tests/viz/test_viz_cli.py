"""``geomexact view`` and ``geomexact serve`` from the command line: outputs, JSON keys
and exit codes (0 ok, 2 bad input or usage)."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import urllib.request
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from matplotlib.image import imread

from geomexact.cli import main

SUPERIOR = Path(__file__).resolve().parents[2] / "geomexact" / "data" / "superior.poly"
SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"


def run(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def run_json(capsys: pytest.CaptureFixture[str], *argv: str | Path) -> tuple[int, Any]:
    code, out, err = run(capsys, *argv, "--json")
    assert code == 0, err
    return code, json.loads(out)


@pytest.fixture(scope="module")
def traced(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """superior.poly with its triangulation and trace (written by the CLI)."""
    folder = tmp_path_factory.mktemp("traced")
    (folder / "superior.poly").write_bytes(SUPERIOR.read_bytes())
    code = main(["triangulate", str(folder / "superior.poly"), "-o",
                 str(folder / "superior.1.ele"), "--trace",
                 str(folder / "superior.1.trace.jsonl")])
    assert code == 0
    return folder


def test_view_writes_a_viewer_page(capsys: pytest.CaptureFixture[str], traced: Path,
                                   tmp_path: Path) -> None:
    """view IN --trace T -o OUT.html: a page with the whole history; JSON keys."""
    out = tmp_path / "view.html"
    _, report = run_json(capsys, "view", traced / "superior.poly", "--trace",
                         traced / "superior.1.trace.jsonl", "-o", out, "--step", "10",
                         "--color-by", "min-angle")
    assert report == {
        "input": str(traced / "superior.poly"), "format": "poly", "kind": "pslg",
        "trace": str(traced / "superior.1.trace.jsonl"), "steps": 2517, "step": 10,
        "clip": None, "output": str(out), "bytes": out.stat().st_size,
    }
    page = out.read_text(encoding="utf-8")
    assert '"options":{"fill":"min_angle","step":10}' in page
    assert '"trace":"superior.1.trace.jsonl"' in page


def test_view_writes_pictures(capsys: pytest.CaptureFixture[str], traced: Path,
                              tmp_path: Path) -> None:
    """view -o OUT.png / .svg: pictures; with --trace and --step, that step's picture."""
    code, out, _ = run(capsys, "view", traced / "superior.1.ele", "-o", tmp_path / "m.png")
    assert code == 0 and out == f"wrote {tmp_path / 'm.png'}\n"
    assert imread(tmp_path / "m.png").shape[:2] == (600, 800)
    code, _, _ = run(capsys, "view", traced / "superior.1.ele", "-o", tmp_path / "m.svg",
                     "--color-by", "area", "--title", "by area")
    assert code == 0 and "by area" in (tmp_path / "m.svg").read_text(encoding="utf-8")
    code, _, err = run(capsys, "view", traced / "superior.poly", "--trace",
                       traced / "superior.1.trace.jsonl", "--step", "7",
                       "-o", tmp_path / "s.png")
    assert code == 0, err


@pytest.mark.parametrize(("extra", "fragment"), [
    (["-o", "x.jpg"], "must end in .html"),
    (["-o", "x.html", "--step", "3"], "--step needs --trace"),
])
def test_view_usage_errors(capsys: pytest.CaptureFixture[str], traced: Path, tmp_path: Path,
                           monkeypatch: pytest.MonkeyPatch, extra: list[str], fragment: str
                           ) -> None:
    """An output that is neither a page nor a picture, --step without a trace: exit 2."""
    monkeypatch.chdir(tmp_path)
    code, out, err = run(capsys, "view", traced / "superior.1.ele", *extra)
    assert code == 2 and out == ""
    assert err.startswith("geomexact: error: ") and fragment in err


def test_view_bad_trace_inputs(capsys: pytest.CaptureFixture[str], traced: Path,
                               tmp_path: Path) -> None:
    """A trace on another mesh, a step beyond the trace, a trace on a polygon mesh:
    exit 2 with one line on stderr, nothing written."""
    square = tmp_path / "square.off"
    square.write_text(SQUARE_OFF)
    trace = traced / "superior.1.trace.jsonl"
    cases = [
        ([square, "--trace", trace, "-o", tmp_path / "a.html"], "not the trace's input"),
        ([traced / "superior.poly", "--trace", trace, "--step", "9999",
          "-o", tmp_path / "b.png"], "outside"),
        ([traced / "superior.poly", "--trace", trace, "--step", "9999",
          "-o", tmp_path / "b.html"], "outside"),
    ]
    for argv, fragment in cases:
        code, out, err = run(capsys, "view", *argv)
        assert out == ""
        assert code == 2, argv
        assert len(err.strip().splitlines()) == 1 and fragment in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["square.off"]


def test_view_refuses_to_overwrite(capsys: pytest.CaptureFixture[str], traced: Path,
                                   tmp_path: Path) -> None:
    """An existing OUT is kept (exit 2) unless --force."""
    out = tmp_path / "x.html"
    out.write_text("keep")
    code, _, err = run(capsys, "view", traced / "superior.1.ele", "-o", out)
    assert code == 2 and "--force" in err and out.read_text() == "keep"
    code, _, _ = run(capsys, "view", traced / "superior.1.ele", "-o", out, "--force",
                     "--no-exact")
    assert code == 0 and '"exact":null' in out.read_text(encoding="utf-8")


def test_demo_draws_a_picture_and_a_page(capsys: pytest.CaptureFixture[str],
                                         tmp_path: Path) -> None:
    """The main job's draw step: superior.png (800 × 600) and superior.html replaying the
    last stage's trace, reported under "draw"."""
    _, report = run_json(capsys, "demo", "-o", tmp_path)
    assert report["steps"][-1] == "draw"
    draw = report["draw"]
    assert Path(draw["picture"]).name == "superior.png"
    assert imread(draw["picture"]).shape[:2] == (600, 800)
    assert draw["trace_steps"] > 0
    page = Path(draw["viewer"]).read_text(encoding="utf-8")
    assert '"history":{' in page


@pytest.mark.parametrize("argv", [["--port", "-1"], ["--time-limit", "0"],
                                  ["--max-upload-mb", "nan"], ["--jobs", "x"]])
def test_serve_bad_options(capsys: pytest.CaptureFixture[str], argv: list[str]) -> None:
    """Negative ports, non-positive limits: usage errors (exit 2)."""
    code, _, err = run(capsys, "serve", ".", *argv)
    assert code == 2 and "usage:" in err


def test_serve_defaults_are_the_servers(tmp_path: Path) -> None:
    """The CLI keeps its own copy of the server defaults (importing the server would load
    matplotlib at every start): they must agree with ServeOptions'."""
    from geomexact.cli.parser import build_parser
    from geomexact.server import ServeOptions

    args = build_parser().parse_args(["serve", str(tmp_path)])
    defaults = ServeOptions(tmp_path)
    assert (args.host, args.port, args.time_limit, args.jobs) == (
        defaults.host, defaults.port, defaults.time_limit, defaults.jobs)
    assert int(args.max_upload_mb * 1024 * 1024) == defaults.max_upload_bytes


def test_serve_missing_directory(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """A directory that does not exist: exit 2, one line."""
    code, _, err = run(capsys, "serve", tmp_path / "nope", "--port", "0")
    assert code == 2 and "not a directory" in err


def _sigint_as(disposition: signal.Handlers) -> Callable[[], None]:
    """A ``preexec_fn`` that starts the child with SIGINT set to ``disposition``: a test
    run as a background job of a non-interactive shell (``scripts/test &``) inherits
    SIGINT ignored, which a terminal's Ctrl-C never meets."""
    def start() -> None:
        signal.signal(signal.SIGINT, disposition)

    return start


@pytest.mark.parametrize(("stop", "sigint"), [
    (signal.SIGINT, signal.SIG_DFL),
    (signal.SIGTERM, signal.SIG_DFL),
    (signal.SIGTERM, signal.SIG_IGN),
], ids=["ctrl-c", "sigterm", "sigterm-in-background"])
def test_serve_runs_until_interrupted(tmp_path: Path, stop: signal.Signals,
                                      sigint: signal.Handlers) -> None:
    """`geomexact serve DIR --port 0` prints its address, answers there, and stops with
    exit code 0 on Ctrl-C (SIGINT) or SIGTERM, also when started as a background job
    (SIGINT ignored)."""
    (tmp_path / "square.off").write_text(SQUARE_OFF)
    process = subprocess.Popen(
        [sys.executable, "-m", "geomexact", "serve", str(tmp_path), "--port", "0"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=_sigint_as(sigint),
    )
    try:
        assert process.stdout is not None
        line = process.stdout.readline()
        assert line.startswith(f"serving {tmp_path} at http://127.0.0.1:"), line
        url = line.split(" at ")[1].split()[0]
        with urllib.request.urlopen(url, timeout=30) as response:
            assert "square.off" in response.read().decode("utf-8")
        with urllib.request.urlopen(url + "view?file=square.off", timeout=60) as response:
            assert response.status == 200
        process.send_signal(stop)
        assert process.wait(timeout=30) == 0
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
        for stream in (process.stdout, process.stderr):
            if stream is not None:
                stream.close()


def test_serve_warns_off_loopback(capsys: pytest.CaptureFixture[str], tmp_path: Path,
                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """--host other than loopback prints a warning that there is no authentication."""
    from geomexact import server as serve

    def refuse(options: serve.ServeOptions, **_: object) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(serve, "serve", refuse)
    code, _, err = run(capsys, "serve", tmp_path, "--host", "0.0.0.0", "--port", "0")
    assert code == 0
    assert "no authentication" in err and "stopped" in err


def test_serve_port_in_use(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    """A port that is taken: exit 2, one line naming the address."""
    import socket

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        code, _, err = run(capsys, "serve", tmp_path, "--port", str(port))
    assert code == 2
    assert err == f"geomexact: error: 127.0.0.1:{port}: Address already in use\n"


@pytest.fixture(scope="module")
def tetrahedra(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Pattern 262143 of the cuboid, improved, as TetGen ``x.node`` / ``x.ele``."""
    from geomexact import io
    from geomexact.mesh3d.cuboid.partition import partition_cuboid

    path = tmp_path_factory.mktemp("tetrahedra") / "x.ele"
    io.write(path, partition_cuboid(262143, improve=True).mesh)
    return path


def test_view_draws_a_tetrahedral_mesh(capsys: pytest.CaptureFixture[str], tetrahedra: Path,
                                       tmp_path: Path) -> None:
    out = tmp_path / "x.png"
    _, report = run_json(capsys, "view", tetrahedra, "-o", out)
    assert report["kind"] == "tetrahedral_mesh" and report["clip"] is None
    assert report["output"] == str(out) and report["bytes"] == out.stat().st_size
    assert imread(str(out)).shape[:2] == (600, 800)
    for suffix in (".svg", ".pdf"):
        assert run(capsys, "view", tetrahedra, "-o", tmp_path / f"x{suffix}")[0] == 0


def test_view_clip(capsys: pytest.CaptureFixture[str], tetrahedra: Path,
                   tmp_path: Path) -> None:
    whole, clipped = tmp_path / "whole.png", tmp_path / "clipped.png"
    assert run(capsys, "view", tetrahedra, "-o", whole)[0] == 0
    _, report = run_json(capsys, "view", tetrahedra, "-o", clipped, "--clip", "x", "1/2",
                         "--color-by", "min-angle")
    assert report["clip"] == {"axis": "x", "position": "1/2"}
    assert (imread(str(whole)) != imread(str(clipped))).any()
    page = tmp_path / "clipped.html"
    assert run(capsys, "view", tetrahedra, "-o", page, "--clip", "z", "0.25")[0] == 0
    assert '"clip":{"axis":"z","position":"0.25","value":0.25}' in page.read_text("utf-8")
    code, _, err = run(capsys, "view", tetrahedra, "-o", tmp_path / "bad.png",
                       "--clip", "w", "1")
    assert code == 2 and "clip axis" in err
    code, _, err = run(capsys, "view", tetrahedra, "-o", tmp_path / "bad.png",
                       "--clip", "x", "half")
    assert code == 2 and "half" in err
    code, _, err = run(capsys, "view", tetrahedra, "-o", tmp_path / "bad.png",
                       "--color-by", "area")
    assert code == 2 and "tetrahedral" in err
    square = tmp_path / "square.off"
    square.write_text(SQUARE_OFF)
    code, _, err = run(capsys, "view", square, "-o", tmp_path / "sq.png", "--clip", "x", "0")
    assert code == 2 and "--clip needs a tetrahedral mesh" in err


def test_view_picture_of_a_step_of_a_3d_trace(capsys: pytest.CaptureFixture[str],
                                              tmp_path: Path) -> None:
    from geomexact import io
    from geomexact.io.trace_file import write_trace
    from geomexact.mesh3d.cuboid.partition import partition_cuboid

    run3 = partition_cuboid(0b101101, improve=True)
    io.write(tmp_path / "start.ele", run3.start)
    write_trace(tmp_path / "run.trace.jsonl", run3.trace)
    _, report = run_json(capsys, "view", tmp_path / "start.ele", "-o", tmp_path / "s.png",
                         "--trace", tmp_path / "run.trace.jsonl", "--step", "2")
    assert report["step"] == 2 and report["steps"] == len(run3.trace)
    code, _, err = run(capsys, "view", tmp_path / "start.ele", "-o", tmp_path / "t.png",
                       "--trace", tmp_path / "run.trace.jsonl", "--step", "999")
    assert code == 2 and "999" in err
