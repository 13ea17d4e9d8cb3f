"""Write ``digests.json``: the golden results of the regression cases (see README.md).

Run from the project root: ``python tests/data/regression/make_digests.py``.  It uses only
the public facade, so the same script ran on the code before a change and after it."""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path
from typing import Any

import geomexact
from geomexact import io

HERE = Path(__file__).resolve().parent
PROJECT = HERE.parents[2]
SHARED = PROJECT.parent / "shared" / "data"
PACKAGE_DATA = Path(geomexact.__file__).resolve().parent / "data"

# (case name, input: "package:<file>" or "shared:<path>", run)
CASES: list[tuple[str, str, str]] = [
    ("superior-cdt", "package:superior.poly", "triangulate"),
    ("superior-bisection-area", "package:superior.poly", "bisection-area"),
    ("superior-bisection-plain", "package:superior.poly", "bisection-no-delaunay"),
    ("superior-centroid-25", "package:superior.poly", "centroid-25"),
    ("superior-quasi-factor", "package:superior.poly", "quasi-factor"),
    ("superior-circle", "package:superior.poly", "bisection-circle"),
    ("pikachu-cdt", "shared:polylla-unified/pikachu_poly.poly", "triangulate"),
    ("pikachu-centroid-25", "shared:polylla-unified/pikachu_poly.poly", "centroid-25"),
    ("poisson-bisection-area", "shared:polylla-refinement/500poisson.off", "bisection-area"),
    ("random-quasi-factor", "shared:polylla-refinement/1500random.off", "quasi-factor"),
    ("points50-delaunay", "shared:polylla-dcel/points50.1.node", "triangulate"),
    ("qlepp-a-centroid-50-once", "shared:qlepp2d/A.off", "centroid-50-once"),
    ("course-3-centroid-30", "shared:lepp-delaunay-course/Triangles3.txt", "centroid-30"),
]


def source(spec: str) -> Path:
    kind, _, name = spec.partition(":")
    return (PACKAGE_DATA if kind == "package" else SHARED) / name


def run(value: Any, kind: str) -> tuple[Any, Any, Any]:
    """(start mesh, final mesh, trace) of one run."""
    if kind == "triangulate":
        if isinstance(value, geomexact.PSLG):
            built = geomexact.triangulate(value)
        else:
            points = [value.point(v) for v in range(value.vertex_count)]
            built = geomexact.triangulate_points(points)
        return built.start, built.mesh, built.trace
    mesh = geomexact.triangulate(value).mesh if isinstance(value, geomexact.PSLG) else value
    mpq = geomexact.mpq
    small = geomexact.MaxArea(mpq(1, 2000))
    options: dict[str, Any] = {
        "bisection-area": {"criterion": small},
        "bisection-no-delaunay": {"criterion": small, "delaunay": False},
        "centroid-25": {"criterion": geomexact.MinAngle(25), "method": "centroid"},
        "centroid-30": {"criterion": geomexact.MinAngle(30), "method": "centroid"},
        "centroid-50-once": {"criterion": geomexact.MinAngle(50), "method": "centroid",
                             "max_steps": 1},
        "quasi-factor": {"criterion": geomexact.AverageAreaFactor(mpq(1, 4)), "method": "quasi"},
        "bisection-circle": {"criterion": geomexact.MaxArea(mpq(1, 20000)),
                             "region": geomexact.Circle(mpq(1, 2), mpq(-1, 2), mpq(1, 10))},
    }[kind]
    result = geomexact.refine(mesh, **{"max_steps": 20000, **options})
    return result.start, result.mesh, result.trace


def trace_sha(trace: Any) -> str:
    """sha256 of the trace file's text."""
    try:
        from geomexact.io.trace_file import trace_lines
    except ImportError:  # the layout before the re-layout kept the file format in trace.py
        from geomexact.trace import trace_lines  # type: ignore[attr-defined,no-redef]
    digest = hashlib.sha256()
    for line in trace_lines(trace):
        digest.update(line.encode() + b"\n")
    return digest.hexdigest()


def case_result(spec: str, kind: str) -> dict[str, Any]:
    value = io.read(source(spec))
    _, mesh, trace = run(value, kind)
    return {
        "input": spec,
        "run": kind,
        "steps": len(trace),
        "vertices": mesh.vertex_count,
        "triangles": mesh.triangle_count,
        "final_digest": f"{mesh.digest:032x}",
        "trace_sha256": trace_sha(trace),
    }


def demo_result() -> dict[str, str]:
    """sha256 of every file ``geomexact demo`` writes, pictures and viewer page aside."""
    import contextlib
    import io as text_io
    import tempfile

    from geomexact.cli import main as command

    with tempfile.TemporaryDirectory() as folder:
        with contextlib.redirect_stdout(text_io.StringIO()):
            status = command(["demo", "-o", folder, "--force", "--json"])
        assert status == 0, status
        return {
            path.name: hashlib.sha256(_without_provenance(path)).hexdigest()
            for path in sorted(Path(folder).iterdir())
            if path.suffix not in (".png", ".html")
        }


def _without_provenance(path: Path) -> bytes:
    """The file's bytes; for a trace, without the header's ``command`` and ``options``
    parameters, which name the output folder (a temporary one here), nor its
    ``header_digest``, which covers them."""
    data = path.read_bytes()
    if not path.name.endswith(".trace.jsonl"):
        return data
    header, _, rest = data.partition(b"\n")
    record = json.loads(header)
    for key in ("command", "options"):
        record["parameters"].pop(key, None)
    record.pop("header_digest", None)
    return json.dumps(record, sort_keys=True, separators=(",", ":")).encode() + b"\n" + rest


def main() -> None:
    results = {name: case_result(spec, kind) for name, spec, kind in CASES
               if source(spec).exists()}
    results["demo"] = {"files": demo_result()}
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE / "digests.json"
    out.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n")


if __name__ == "__main__":
    main()
