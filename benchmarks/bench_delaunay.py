"""Delaunay triangulation time of geomexact against Triangle (C) and sect (pure Python, exact).

Usage::

    .venv/bin/python benchmarks/bench_delaunay.py [--sizes 10000 100000] [--repeat 3]
        [--sect-max 10000] [--sect-repeat 1] [--json]

Workloads (fixed seed, so runs are comparable):

* ``points-N``: N uniform random points of the unit square; coordinates are random doubles
  taken exactly (each is an exact dyadic rational), so the three programs triangulate the
  very same points and their results are compared (same triangles, by vertex index).
* ``superior``: the Lake Superior PSLG shipped in the package (518 vertices, 518 segments,
  6 islands as holes): constrained Delaunay triangulation with holes removed.
* ``cdt-N`` (``--cdt-segments N``, default 30,000; 0 skips it): constrained Delaunay with
  many segments — a star-shaped polygon of N vertices at random radii 0.3–0.45 around the
  centre of the unit square (N segments, many of them crossing several Delaunay edges, so
  segment recovery flips a lot), N random points of the unit square (those outside the
  polygon are carved away with the exterior) and a square hole with its seed: segment
  recovery, the Lawson pass and carving all run (in the compiled kernel when built).
  Triangle runs ``pQ`` on the same input.
* ``cdt-smooth-N``: the same with a smooth polygon (radius 0.4 + 0.05 sin 5θ plus noise
  below 0.002): its segments are mostly Delaunay edges already, so the time goes to the
  point triangulation, the Lawson pass, carving and the trace rather than to recovery.

Competitors, in the same run, on the same points:

* ``geomexact``: :func:`geomexact.mesh2d.delaunay.triangulation.triangulate_points` /
  :func:`triangulate`, the
  whole construction (snapshot *and* replayable trace).  Turning the input floats into exact
  points is not timed (every competitor gets its input ready-made).
* ``triangle``: the ``triangle`` package (Shewchuk's Triangle): ``"Q"`` for points, ``"pQ"``
  with segments and holes for Superior.
* ``sect``: ``sect.triangulation.Triangulation.delaunay(points, context=...)`` then
  ``.triangles()`` (and ``constrained_delaunay`` for Superior) in ground's default exact
  mode, on ``cfractions.Fraction`` coordinates.  sect takes about 16 s for 1e4 points here
  and grows as n log n, so by default it runs only for N <= ``--sect-max`` (1e4).

Timing: best (minimum) of ``--repeat`` runs, after ``gc.collect()``; the programs take turns
within each repeat.  Timing noise on this VM is about +-20% between runs: read the target
verdicts with that margin.  Targets (issue 3): 1e4 points in <= 0.4 s and >= 25x faster
than sect; 1e5 points <= 30x Triangle.
"""

from __future__ import annotations

import argparse
import gc
import importlib.resources
import json
import math
import platform
import random
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from geomexact import __version__, io
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import Point2, point2
from geomexact.mesh2d.delaunay.triangulation import triangulate, triangulate_points
from geomexact.mesh2d.pslg import PSLG

TARGET_SECONDS_1E4 = 0.4
TARGET_SECT_SPEEDUP_1E4 = 25.0
TARGET_TRIANGLE_RATIO_1E5 = 30.0
TARGET_CDT_SECONDS = 1.5  # issue 15: the 30,000-segment CDT
TARGET_TRIANGLE_RATIO_1E6 = 20.0  # issue 15: 1e6 points in-process


# --- inputs -----------------------------------------------------------------------------------


def random_doubles(count: int, seed: int = 1) -> list[tuple[float, float]]:
    rng = random.Random(seed)
    return [(rng.random(), rng.random()) for _ in range(count)]


def superior() -> PSLG:
    path = importlib.resources.files("geomexact") / "data" / "superior.poly"
    with importlib.resources.as_file(path) as real:
        value = io.read(real)
    assert isinstance(value, PSLG)
    return value


def pslg_loops(pslg: PSLG) -> list[list[int]]:
    """The closed loops of the PSLG's segments (each vertex on two segments)."""
    neighbours: dict[int, list[int]] = {}
    for u, v, _ in pslg.segments:
        neighbours.setdefault(u, []).append(v)
        neighbours.setdefault(v, []).append(u)
    seen: set[int] = set()
    loops = []
    for start in sorted(neighbours):
        if start in seen:
            continue
        loop, previous, current = [start], -1, start
        seen.add(start)
        while True:
            a, b = neighbours[current]
            following = b if a == previous else a
            if following == start:
                break
            loop.append(following)
            seen.add(following)
            previous, current = current, following
        loops.append(loop)
    return loops


def star_pslg(count: int, free: int, seed: int = 5, *, smooth: bool = False) -> PSLG:
    """The ``cdt-N`` workload: a star-shaped polygon of ``count`` vertices (random radii,
    or with ``smooth`` a wavy curve), ``free`` random points of the unit square and a
    square hole with its seed."""
    rng = random.Random(seed)
    angles = sorted(rng.random() * 2 * math.pi for _ in range(count))
    doubles = []
    for angle in angles:
        if smooth:
            radius = 0.4 + 0.05 * math.sin(5 * angle) + 0.002 * rng.random()
        else:
            radius = 0.3 + 0.15 * rng.random()
        doubles.append((0.5 + radius * math.cos(angle), 0.5 + radius * math.sin(angle)))
    doubles += [(rng.random(), rng.random()) for _ in range(free)]
    segments = [(i, (i + 1) % count, 1) for i in range(count)]
    m = len(doubles)
    doubles += [(0.45, 0.45), (0.55, 0.45), (0.55, 0.55), (0.45, 0.55)]
    segments += [(m + i, m + (i + 1) % 4, 2) for i in range(4)]
    return PSLG(vertices=tuple(point2(mpq(x), mpq(y)) for x, y in doubles),
                segments=tuple(segments), holes=(point2(mpq(1, 2), mpq(1, 2)),))


def twice_area(points: list[Point2]) -> Any:
    return sum((p.x * q.y - q.x * p.y for p, q in zip(points, points[1:] + points[:1],
                                                        strict=True)), mpq(0))


# --- competitors ------------------------------------------------------------------------------


def best_of(repeat: int, run: Callable[[], Any]) -> tuple[float, Any]:
    best, result = float("inf"), None
    for _ in range(repeat):
        gc.collect()
        start = time.perf_counter()
        result = run()
        best = min(best, time.perf_counter() - start)
    return best, result


def triangle_module() -> Any:
    try:
        import numpy
        import triangle  # type: ignore[import-untyped]
    except ImportError:
        return None
    return triangle, numpy


def sect_module() -> Any:
    try:
        from cfractions import Fraction
        from ground.base import get_context  # type: ignore[import-untyped]
        from sect.triangulation import Triangulation  # type: ignore[import-untyped]
    except ImportError:
        return None
    return Fraction, get_context(), Triangulation


def index_triangles(triangles: Any) -> set[tuple[int, ...]]:
    return {tuple(sorted(t)) for t in triangles}


def bench_points(count: int, repeat: int, sect_max: int, sect_repeat: int) -> dict[str, Any]:
    doubles = random_doubles(count)
    points = [point2(mpq(x), mpq(y)) for x, y in doubles]
    row: dict[str, Any] = {"workload": f"points-{count}", "n": count}
    ours_time, run = best_of(repeat, lambda: triangulate_points(points))
    ours = index_triangles(run.mesh.triangles())
    row.update(geomexact=ours_time, triangles=len(ours), trace_steps=len(run.trace))
    tri = triangle_module()
    if tri is not None:
        triangle, numpy = tri
        array = numpy.array(doubles, dtype=float)
        row["triangle"], result = best_of(
            repeat, lambda: triangle.triangulate({"vertices": array}, "Q"))
        row["same_as_triangle"] = index_triangles(result["triangles"].tolist()) == ours
    sect = sect_module()
    if sect is not None and count <= sect_max:
        fraction, context, triangulation = sect
        sect_points = [context.point_cls(fraction(x), fraction(y)) for x, y in doubles]
        index = {(x, y): i for i, (x, y) in enumerate(doubles)}
        row["sect"], contours = best_of(
            sect_repeat,
            lambda: triangulation.delaunay(sect_points, context=context).triangles())
        row["same_as_sect"] = index_triangles(
            [index[(float(p.x), float(p.y))] for p in contour.vertices]
            for contour in contours) == ours
    return row


def bench_superior(repeat: int, sect_repeat: int) -> dict[str, Any]:
    pslg = superior()
    row: dict[str, Any] = {"workload": "superior", "n": len(pslg.vertices)}
    ours_time, run = best_of(repeat, lambda: triangulate(pslg))
    ours = index_triangles(run.mesh.triangles())
    row.update(geomexact=ours_time, triangles=len(ours), trace_steps=len(run.trace))
    tri = triangle_module()
    if tri is not None:
        triangle, numpy = tri
        data = {
            "vertices": numpy.array([[p.fx, p.fy] for p in pslg.vertices]),
            "segments": numpy.array([[u, v] for u, v, _ in pslg.segments]),
            "holes": numpy.array([[p.fx, p.fy] for p in pslg.holes]),
        }
        row["triangle"], result = best_of(repeat, lambda: triangle.triangulate(data, "pQ"))
        row["same_as_triangle"] = index_triangles(result["triangles"].tolist()) == ours
    sect = sect_module()
    if sect is not None:
        fraction, context, triangulation = sect
        loops = sorted(pslg_loops(pslg), key=lambda loop: abs(
            twice_area([pslg.vertices[v] for v in loop])), reverse=True)

        def contour(loop: list[int], counterclockwise: bool) -> Any:
            if (twice_area([pslg.vertices[v] for v in loop]) > 0) != counterclockwise:
                loop = loop[::-1]
            return context.contour_cls([
                context.point_cls(exact(pslg.vertices[v].x), exact(pslg.vertices[v].y))
                for v in loop])

        def exact(value: Any) -> Any:
            return fraction(int(value.numerator), int(value.denominator))

        polygon = context.polygon_cls(contour(loops[0], True),
                                      [contour(loop, False) for loop in loops[1:]])
        row["sect"], contours = best_of(
            sect_repeat,
            lambda: triangulation.constrained_delaunay(polygon, context=context).triangles())
        row["sect_triangles"] = len(contours)
        index = {(exact(p.x), exact(p.y)): i for i, p in enumerate(pslg.vertices)}
        row["same_as_sect"] = index_triangles(
            [index[(p.x, p.y)] for p in triangle_contour.vertices]
            for triangle_contour in contours) == ours
    return row


def bench_cdt(count: int, repeat: int, smooth: bool = False) -> dict[str, Any]:
    pslg = star_pslg(count, count, smooth=smooth)
    name = f"cdt-smooth-{count}" if smooth else f"cdt-{count}"
    row: dict[str, Any] = {"workload": name, "n": len(pslg.vertices),
                           "segments": len(pslg.segments)}
    ours_time, run = best_of(repeat, lambda: triangulate(pslg))
    ours = index_triangles(run.mesh.triangles())
    row.update(geomexact=ours_time, triangles=len(ours), trace_steps=len(run.trace))
    tri = triangle_module()
    if tri is not None:
        triangle, numpy = tri
        data = {
            "vertices": numpy.array([[p.fx, p.fy] for p in pslg.vertices]),
            "segments": numpy.array([[u, v] for u, v, _ in pslg.segments]),
            "holes": numpy.array([[p.fx, p.fy] for p in pslg.holes]),
        }
        row["triangle"], result = best_of(repeat, lambda: triangle.triangulate(data, "pQ"))
        row["same_as_triangle"] = index_triangles(result["triangles"].tolist()) == ours
    return row


# --- report -----------------------------------------------------------------------------------


def verdicts(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    by_n = {row["n"]: row for row in rows if row["workload"].startswith("points-")}
    found = []
    if 10_000 in by_n:
        row = by_n[10_000]
        found.append({"target": "1e4 points <= 0.4 s", "value": row["geomexact"],
                      "met": row["geomexact"] <= TARGET_SECONDS_1E4})
        if "sect" in row:
            speedup = row["sect"] / row["geomexact"]
            found.append({"target": "1e4 points >= 25x faster than sect", "value": speedup,
                          "met": speedup >= TARGET_SECT_SPEEDUP_1E4})
    if 100_000 in by_n and "triangle" in by_n[100_000]:
        row = by_n[100_000]
        ratio = row["geomexact"] / row["triangle"]
        found.append({"target": "1e5 points <= 30x Triangle", "value": ratio,
                      "met": ratio <= TARGET_TRIANGLE_RATIO_1E5})
    if 1_000_000 in by_n and "triangle" in by_n[1_000_000]:
        row = by_n[1_000_000]
        ratio = row["geomexact"] / row["triangle"]
        found.append({"target": "1e6 points <= 20x Triangle", "value": ratio,
                      "met": ratio <= TARGET_TRIANGLE_RATIO_1E6})
    for row in rows:
        if row["workload"] == "cdt-30000":
            found.append({"target": "30,000-segment CDT <= 1.5 s", "value": row["geomexact"],
                          "met": row["geomexact"] <= TARGET_CDT_SECONDS})
    return found


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000])
    parser.add_argument("--repeat", type=int, default=3, help="runs of geomexact/Triangle")
    parser.add_argument("--sect-max", type=int, default=10_000,
                        help="largest point count given to sect (it is slow)")
    parser.add_argument("--sect-repeat", type=int, default=1, help="runs of sect")
    parser.add_argument("--no-superior", action="store_true")
    parser.add_argument("--cdt-segments", type=int, default=30_000,
                        help="segments (and free points) of the cdt-N workload; 0 skips it")
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    options = parser.parse_args(argv)

    rows = [bench_points(n, options.repeat, options.sect_max, options.sect_repeat)
            for n in options.sizes]
    if not options.no_superior:
        rows.append(bench_superior(options.repeat, options.sect_repeat))
    if options.cdt_segments:
        rows.append(bench_cdt(options.cdt_segments, options.repeat))
        rows.append(bench_cdt(options.cdt_segments, options.repeat, smooth=True))
    for row in rows:
        if "triangle" in row:
            row["geomexact_over_triangle"] = row["geomexact"] / row["triangle"]
        if "sect" in row:
            row["sect_over_geomexact"] = row["sect"] / row["geomexact"]
    report = {
        "benchmark": "delaunay",
        "geomexact": __version__,
        "python": platform.python_version(),
        "machine": platform.machine(),
        "repeat": options.repeat,
        "sect_repeat": options.sect_repeat,
        "noise": "about +-20% between runs on this VM",
        "rows": rows,
        "targets": verdicts(rows),
    }
    if options.json:
        print(json.dumps(report, sort_keys=True))
        return 0

    def seconds(value: float | None) -> str:
        return "-" if value is None else f"{value:9.4f}"

    def ratio(value: float | None) -> str:
        return "-" if value is None else f"{value:7.1f}x"

    print(f"geomexact {__version__}, Python {platform.python_version()}, best of "
          f"{options.repeat} (sect: {options.sect_repeat}); timing noise on this VM ~+-20%")
    header = (f"{'workload':<18}{'triangles':>10}{'geomexact s':>13}{'Triangle s':>12}"
              f"{'sect s':>11}{'ours/Tri':>10}{'sect/ours':>11}  same result")
    print(header)
    print("-" * len(header))
    for row in rows:
        same = [name for name in ("triangle", "sect") if row.get(f"same_as_{name}")]
        differs = [name for name in ("triangle", "sect") if row.get(f"same_as_{name}") is False]
        note = ", ".join([*(f"= {n}" for n in same), *(f"DIFFERS from {n}" for n in differs)])
        print(f"{row['workload']:<18}{row['triangles']:>10}{seconds(row['geomexact']):>13}"
              f"{seconds(row.get('triangle')):>12}{seconds(row.get('sect')):>11}"
              f"{ratio(row.get('geomexact_over_triangle')):>10}"
              f"{ratio(row.get('sect_over_geomexact')):>11}  {note}")
    skipped = [n for n in options.sizes if n > options.sect_max]
    if skipped:
        print(f"sect not run for n = {', '.join(map(str, skipped))} (> --sect-max "
              f"{options.sect_max}: about 16 s per 1e4 points here, n log n)")
    print()
    for verdict in report["targets"]:
        value = verdict["value"]
        shown = f"{value:.3f} s" if verdict["target"].endswith(" s") else f"{value:.1f}x"
        print(f"target {verdict['target']:<38} {shown:>10}  "
              f"{'met' if verdict['met'] else 'NOT met'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
