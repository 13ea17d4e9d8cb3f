"""Triangulations are deterministic: the same input and seed give the same mesh digest and
byte-identical trace files in processes with different string hash seeds; trace files of
constrained runs (rational step arguments) read back and replay."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from helpers.delaunay_checks import assert_sound

from geomexact import PSLG, mpq, point2, read_trace, replay, write_trace
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.pslg import RegionSeed

PROJECT = Path(__file__).resolve().parents[3]

# Runs in a fresh interpreter: prints {case: [mesh digest, sha256 of the trace file]}.
SCRIPT = r"""
import hashlib, importlib.resources, json, random, sys
from geomexact import PSLG, io, mpq, point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.io.trace_file import trace_text

def cases():
    path = importlib.resources.files("geomexact") / "data" / "superior.poly"
    with importlib.resources.as_file(path) as real:
        yield "superior", io.read(real), {}
    rng = random.Random(3)
    yield "random", [point2(mpq(rng.random()), mpq(rng.random())) for _ in range(1500)], {}
    grid = [point2(i, j) for j in range(12) for i in range(12)]
    yield "grid", grid, {"seed": 1}
    circle = []
    for k in range(-20, 21):
        s = mpq(k, 4)
        circle.append(point2((1 - s * s) / (1 + s * s), 2 * s / (1 + s * s)))
    yield "circle", circle + [point2(0, 0)], {"seed": 2}
    crossing = [point2(i, j) for j in range(5) for i in range(5)]
    segments = [(0, 24, 1), (4, 20, 2), (2, 22, 3), (10, 14, 4), (1, 23, 5), (5, 19, 6)]
    yield "crossing", PSLG(vertices=crossing, segments=segments), {
        "split_segments": True, "keep_convex_hull": True}

result = {}
for name, value, options in cases():
    run = triangulate(value, **options)
    text = trace_text(run.trace).encode()
    result[name] = [run.mesh.digest_text, hashlib.sha256(text).hexdigest(), len(run.trace)]
json.dump(result, sys.stdout, sort_keys=True)
"""


def _run(hash_seed: str) -> dict[str, list[object]]:
    environment = dict(os.environ, PYTHONHASHSEED=hash_seed)
    environment["PYTHONPATH"] = os.pathsep.join(
        [str(PROJECT), *filter(None, [environment.get("PYTHONPATH")])])
    done = subprocess.run([sys.executable, "-c", SCRIPT], cwd=PROJECT, env=environment,
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    result: dict[str, list[object]] = json.loads(done.stdout)
    return result


def test_same_digests_and_trace_files_under_different_hash_seeds() -> None:
    """Superior, 1500 random points, a 12x12 grid and 41 points on a circle (cocircular
    ties everywhere) and crossing segments split exactly: identical mesh digests and
    byte-identical trace files with PYTHONHASHSEED 0, 1 and 4242."""
    first = _run("0")
    assert set(first) == {"superior", "random", "grid", "circle", "crossing"}
    assert _run("1") == first
    assert _run("4242") == first


def test_trace_file_of_a_constrained_run_reads_back_and_replays(tmp_path: Path) -> None:
    """Crossings (insert_in_edge with rational coordinates), holes (carve), regions
    (set_region with rational attributes): written, read back, replayed to the mesh."""
    vertices = [point2(0, 0), point2(6, 0), point2(6, 6), point2(0, 6), point2(1, 1),
                point2(mpq(5), mpq(7, 3)), point2(mpq(1, 3), 5), point2(5, 5),
                point2(2, 2), point2(3, 2), point2(3, 3), point2(2, 3), point2(8, 3)]
    segments = [(0, 1, 1), (1, 2, 1), (2, 3, 1), (3, 0, 1), (4, 7, 2), (5, 6, 3),
                (8, 9, 4), (9, 10, 4), (10, 11, 4), (11, 8, 4)]
    pslg = PSLG(vertices=vertices, segments=segments, holes=[point2("2.5", "2.5")],
                regions=[RegionSeed(point2(1, 5), mpq(2, 7)), RegionSeed(point2(5, 1), mpq(3))])
    run = triangulate(pslg, split_segments=True)
    assert_sound(run)
    operations = {step.op for step in run.trace.steps}
    assert {"insert_in_edge", "carve", "carve_exterior", "set_region", "constrain"} <= operations
    path = tmp_path / "run.trace"
    write_trace(path, run.trace)
    again = read_trace(path)
    assert again == run.trace
    assert replay(run.start, again) == run.mesh
