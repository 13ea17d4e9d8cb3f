"""Where Lepp-centroid's extra triangles come from: triangle counts at a minimum angle θ,
geomexact against Shewchuk's Triangle (issue 15, item 6; the report is
``docs/triangle-count.md``).

Usage (from the repository's root)::

    .venv/bin/python benchmarks/count_study.py [--json] [--quick]
        [--sections baseline,rules,points,attribution] [--triangle-c PATH/triangle.c]

Sections:

* ``baseline``: every input × θ ∈ {20, 25, 30, 33}: ``refine(mesh, MinAngle(θ),
  method=m)`` for m = centroid and quasi (default rules), against Triangle ``rq<θ>``
  refining the same vertices and triangles (its boundary edges become segments), ``pq<θ>``
  from the PSLG where there is one, and — with ``--triangle-c`` — ``rq<θ>`` by a copy of
  Triangle whose off-center rule is switched off (plain circumcenters).
* ``rules``: 1500random and Superior at 25° and 30°: one rule changed at a time
  (centroid kind, order, second-longest rule, presets), both methods.
* ``points``: 1500random at 25°, 30°, 33°: other points of the terminal quadrilateral
  in place of its rounded area centroid (an experiment: the Python engine's point
  function is swapped; each point is still recorded as ``insert_in_quadrilateral``, so the
  traces replay).
* ``attribution``: 1500random at 30°: where the vertices of each mesh are (distance to the
  convex hull, a 4 × 4 grid), how many are on the hull, the edge lengths and the triangle
  shapes, geomexact against Triangle with and without off-centers.

Inputs: the bundled Lake Superior PSLG (its constrained Delaunay triangulation by
``geomexact.mesh2d.delaunay.triangulation.triangulate``) and, when ``../shared/data``
exists, ``polylla-refinement/{1500random,500poisson,pikachu_triangle}.off``,
``polylla-unified/pikachu_poly.poly`` (its CDT; Triangle ``pq`` from the PSLG),
``polylla-dcel/points50.1`` and ``lepp-delaunay-course/Triangles1..4.txt``; absent files
are skipped with a note.

Triangle without off-centers: Triangle 1.6 has no switch for it (``offconstant`` is set
from the angle in ``parsecommandline``, ``0.475 sqrt((1 + cos θ) / (1 - cos θ))``, and used
by ``findcircumcenter`` whenever it is positive).  ``--triangle-c`` takes a ``triangle.c``
(Shewchuk's, or the copy in the ``triangle`` wheel's source tree), patches that line to
read the environment variable ``TRI_NO_OFFCENTER`` (set: offconstant 0, plain
circumcenters) and builds it with ``cc -O2 -DLINUX``; the same binary with the variable
unset gives the off-center counts (checked against the ``triangle`` package's).
"""

from __future__ import annotations

import argparse
import importlib.resources
import itertools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from geomexact import io
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.refinement.api import refine
from geomexact.mesh2d.refinement.criteria import MinAngle
from geomexact.mesh2d.snapshot import Mesh2
from geomexact.mesh2d.transient import mesh_from_triangles
from geomexact.trace.playback import replay

SHARED = Path(__file__).resolve().parent.parent.parent / "shared" / "data"
ANGLES = (20, 25, 30, 33)
STEP_CAP = 40_000  # rules that do not end (specs/refine.md) are stopped here


# --- inputs -------------------------------------------------------------------------------
class Input:
    """A mesh to refine, and the PSLG it came from (None for a point-set triangulation)."""

    def __init__(self, name: str, mesh: Mesh2, pslg: Any = None) -> None:
        self.name, self.mesh, self.pslg = name, mesh, pslg


def superior() -> Input:
    source = importlib.resources.files("geomexact") / "data" / "superior.poly"
    with importlib.resources.as_file(source) as path:
        pslg = io.read(path, format="poly")
    return Input("superior", triangulate(pslg).mesh, pslg)


def _course(path: Path) -> Mesh2:
    """``x1 y1 x2 y2 x3 y3`` per line: the triangles, corners merged by coordinates."""
    index: dict[tuple[int, int], int] = {}
    triangles = []
    for line in path.read_text().split("\n"):
        numbers = [int(word) for word in line.split()]
        if len(numbers) != 6:
            continue
        corners = []
        for k in range(0, 6, 2):
            corners.append(index.setdefault((numbers[k], numbers[k + 1]), len(index)))
        triangles.append(tuple(corners))
    return mesh_from_triangles(list(index), triangles)


def inputs(notes: list[str], quick: bool) -> list[Input]:
    found = [superior()]
    optional: list[tuple[str, Path, Callable[[Path], Input]]] = [
        ("1500random", SHARED / "polylla-refinement" / "1500random.off",
         lambda p: Input("1500random", io.read(p))),
        ("500poisson", SHARED / "polylla-refinement" / "500poisson.off",
         lambda p: Input("500poisson", io.read(p))),
        ("pikachu-off", SHARED / "polylla-refinement" / "pikachu_triangle.off",
         lambda p: Input("pikachu-off", io.read(p))),
        ("pikachu-poly", SHARED / "polylla-unified" / "pikachu_poly.poly",
         lambda p: Input("pikachu-poly", triangulate(io.read(p)).mesh, io.read(p))),
        ("points50", SHARED / "polylla-dcel" / "points50.1.ele",
         lambda p: Input("points50", io.read(p))),
    ]
    if not quick:
        optional += [
            (f"course-{k}", SHARED / "lepp-delaunay-course" / f"Triangles{k}.txt",
             lambda p, k=k: Input(f"course-{k}", _course(p)))
            for k in range(1, 5)
        ]
    for name, path, load in optional:
        if path.exists():
            found.append(load(path))
        else:
            notes.append(f"{name}: {path} not found, skipped")
    return found


def by_name(found: list[Input], name: str) -> Input | None:
    return next((item for item in found if item.name == name), None)


# --- measures -----------------------------------------------------------------------------
def angles_of(points: Any, triangle: Any) -> list[float]:
    result = []
    for i in range(3):
        p, q, r = points[triangle[i]], points[triangle[(i + 1) % 3]], points[triangle[(i + 2) % 3]]
        ux, uy, vx, vy = q[0] - p[0], q[1] - p[1], r[0] - p[0], r[1] - p[1]
        result.append(math.degrees(math.atan2(abs(ux * vy - uy * vx), ux * vx + uy * vy)))
    return result


def min_angle(points: Any, triangles: Any) -> float:
    return min((min(angles_of(points, t)) for t in triangles), default=180.0)


def float_points(mesh: Mesh2) -> dict[int, tuple[float, float]]:
    return {v: (float(p.x), float(p.y)) for v, p in mesh.vertices.items()}


def run_geomexact(mesh: Mesh2, degrees: int, **options: Any) -> dict[str, Any]:
    began = time.perf_counter()
    result = refine(mesh, MinAngle(degrees), **options)
    seconds = time.perf_counter() - began
    points = float_points(result.mesh)
    left = set(result.stats.left)
    return {
        "triangles": result.mesh.triangle_count,
        "vertices": result.mesh.vertex_count,
        "status": result.status,
        "bisections": result.stats.bisections,
        "centroids": result.stats.centroids,
        "flips": result.stats.flips,
        "targets": result.stats.targets,
        "left": len(left),
        "min_angle": round(min_angle(points, [t for t in result.mesh.iter_triangles()
                                              if t not in left]), 3),
        "seconds": round(seconds, 2),
        "_result": result,
    }


def triangle_data(item: Input, poly: bool) -> dict[str, Any]:
    import numpy as np

    if poly:
        pslg = item.pslg
        data = {"vertices": np.array([[float(p.x), float(p.y)] for p in pslg.vertices]),
                "segments": np.array([[u, v] for u, v, _ in pslg.segments])}
        if len(pslg.holes):
            data["holes"] = np.array([[float(h.x), float(h.y)] for h in pslg.holes])
        return data
    mesh = item.mesh
    order = sorted(mesh.vertices)
    number = {v: i for i, v in enumerate(order)}
    data = {"vertices": np.array([[float(mesh.point(v).x), float(mesh.point(v).y)]
                                  for v in order]),
            "triangles": np.array([[number[v] for v in t] for t in mesh.triangles()])}
    segments = [(number[u], number[v]) for (u, v) in mesh_segments(mesh)]
    if segments:
        data["segments"] = np.array(segments)
    return data


def mesh_segments(mesh: Mesh2) -> list[tuple[int, int]]:
    """The mesh's segment edges (the PSLG's segments of a CDT)."""
    return sorted(mesh.segments.keys())


def run_triangle(item: Input, degrees: int, poly: bool) -> dict[str, Any] | None:
    try:
        import triangle  # type: ignore[import-untyped]
    except ImportError:
        return None
    data = triangle_data(item, poly)
    switches = f"{'p' if poly else 'r'}q{degrees}Q" + ("" if poly or "segments" not in data
                                                      else "p")
    try:
        output = triangle.triangulate(data, switches)
    except RuntimeError:
        return None
    points = output["vertices"].tolist()
    return {"triangles": len(output["triangles"]), "vertices": len(points),
            "min_angle": round(min_angle(points, output["triangles"].tolist()), 3),
            "switches": switches, "_output": output}


class CircumcenterTriangle:
    """Triangle 1.6 built from ``triangle.c`` with the off-center rule switchable."""

    def __init__(self, source: Path) -> None:
        self.folder = Path(tempfile.mkdtemp(prefix="count-study-"))
        text = source.read_text(encoding="latin-1")
        pattern = r"b->offconstant = 0\.475 \* sqrt"
        if not re.search(pattern, text):
            raise SystemExit(f"{source}: no offconstant line to patch")
        text = re.sub(pattern, 'b->offconstant = getenv("TRI_NO_OFFCENTER") ? 0.0 : '
                      "0.475 * sqrt", text)
        flags = ["-O2", "-DLINUX"]
        if '#include "triangle.h"' in text:  # the python wheel's copy: a library build
            text = text.replace('#include "triangle.h"', "")
            text = text.replace("longjmp(buf, 1);", "exit(1);")
            flags.append("-DVOID=void")
        (self.folder / "triangle.c").write_text(text, encoding="latin-1")
        compiler = shutil.which("cc") or shutil.which("gcc")
        if compiler is None:
            raise SystemExit("--triangle-c needs a C compiler")
        subprocess.run([compiler, *flags, "-o", str(self.folder / "triangle"),
                        str(self.folder / "triangle.c"), "-lm"], check=True,
                       capture_output=True)

    def run(self, item: Input, degrees: int, offcenters: bool) -> dict[str, Any]:
        data = triangle_data(item, poly=False)
        stem = self.folder / "in"
        with open(f"{stem}.node", "w") as out:
            out.write(f"{len(data['vertices'])} 2 0 0\n")
            out.writelines(f"{i} {x!r} {y!r}\n" for i, (x, y) in
                           enumerate(data["vertices"].tolist()))
        with open(f"{stem}.ele", "w") as out:
            out.write(f"{len(data['triangles'])} 3 0\n")
            out.writelines(f"{i} {a} {b} {c}\n" for i, (a, b, c) in
                           enumerate(data["triangles"].tolist()))
        switches = f"rq{degrees}Q"
        if "segments" in data:
            with open(f"{stem}.poly", "w") as out:
                out.write("0 2 0 0\n")
                out.write(f"{len(data['segments'])} 0\n")
                out.writelines(f"{i} {a} {b}\n" for i, (a, b) in
                               enumerate(data["segments"].tolist()))
                out.write("0\n")
            switches = f"prq{degrees}Q"
        environment = dict(os.environ)
        environment.pop("TRI_NO_OFFCENTER", None)
        if not offcenters:
            environment["TRI_NO_OFFCENTER"] = "1"
        try:
            subprocess.run([str(self.folder / "triangle"), f"-{switches}", str(stem)],
                           env=environment, check=True, capture_output=True, timeout=120)
        except (subprocess.CalledProcessError, subprocess.TimeoutExpired) as error:
            return {"triangles": 0, "vertices": 0, "min_angle": 0.0,
                    "failed": type(error).__name__}
        points = [tuple(map(float, line.split()[1:3])) for line in
                  (self.folder / "in.1.node").read_text().split("\n")[1:] if
                  line.strip() and not line.startswith("#")]
        triangles = [tuple(int(w) for w in line.split()[1:4]) for line in
                     (self.folder / "in.1.ele").read_text().split("\n")[1:] if
                     line.strip() and not line.startswith("#")]
        return {"triangles": len(triangles), "vertices": len(points),
                "min_angle": round(min_angle(points, triangles), 3),
                "_points": points, "_triangles": triangles}


def public(row: dict[str, Any]) -> dict[str, Any]:
    return {k: v for k, v in row.items() if not k.startswith("_")}


# --- sections -----------------------------------------------------------------------------
def baseline(found: list[Input], angles: tuple[int, ...],
             builder: CircumcenterTriangle | None) -> list[dict[str, Any]]:
    rows = []
    for item in found:
        for degrees in angles:
            row: dict[str, Any] = {"input": item.name, "theta": degrees,
                                   "input_triangles": item.mesh.triangle_count}
            for method in ("centroid", "quasi"):
                row[method] = public(run_geomexact(item.mesh, degrees, method=method))
            rq = run_triangle(item, degrees, poly=False)
            if rq is not None:
                row["triangle_r"] = public(rq)
            if item.pslg is not None and rq is not None:
                pq = run_triangle(item, degrees, poly=True)
                assert pq is not None
                row["triangle_p"] = public(pq)
            if builder is not None:
                row["triangle_r_circumcenters"] = public(builder.run(item, degrees, False))
            rows.append(row)
            print_baseline(row)
    return rows


def print_baseline(row: dict[str, Any]) -> None:
    def cell(key: str) -> str:
        if key not in row:
            return f"{'-':>15}"
        value = row[key]
        if value.get("failed"):
            return f"{'failed':>15}"
        return f"{value['triangles']:>7,} {value['min_angle']:>6.2f}°"

    ratio = ""
    if "triangle_r" in row:
        ratio = f"  centroid/rq {row['centroid']['triangles'] / row['triangle_r']['triangles']:.2f}"
    print(f"{row['input']:<13}{row['theta']:>3}°  centroid {cell('centroid')}  quasi "
          f"{cell('quasi')}  rq {cell('triangle_r')}  pq {cell('triangle_p')}  "
          f"rq-circ {cell('triangle_r_circumcenters')}{ratio}", flush=True)


RULES: list[tuple[str, dict[str, Any]]] = [
    ("default (area, worst-first, bisect-second)", {}),
    ("centroid='vertices'", {"centroid": "vertices"}),
    ("centroid='midpoint'", {"centroid": "midpoint"}),
    ("order='passes'", {"order": "passes"}),
    ("second_longest_rule='centroid'", {"second_longest_rule": "centroid"}),
    ("second_longest_rule='bisect-longest'", {"second_longest_rule": "bisect-longest"}),
    ("preset='pineda'", {"preset": "pineda"}),
    ("preset='mellado'", {"preset": "mellado"}),
]


def rules(found: list[Input], angles: tuple[int, ...]) -> list[dict[str, Any]]:
    rows = []
    for name in ("1500random", "superior"):
        item = by_name(found, name)
        if item is None:
            continue
        for degrees in angles:
            for method in ("centroid", "quasi"):
                for label, options in RULES:
                    run = run_geomexact(item.mesh, degrees, method=method,
                                        max_steps=STEP_CAP, **options)
                    row = {"input": name, "theta": degrees, "method": method,
                           "rule": label, **public(run)}
                    rows.append(row)
                    ended = "" if row["status"] == "complete" else \
                        f"  (no end: stopped at {STEP_CAP:,} steps)"
                    print(f"{name:<11}{degrees:>3}° {method:<9}{label:<44}"
                          f"{row['triangles']:>8,}  {row['min_angle']:6.2f}°  "
                          f"bisections {row['bisections']:>5,} centroids "
                          f"{row['centroids']:>6,}{ended}", flush=True)
    return rows


def point_rules() -> dict[str, Callable[..., Any]]:
    """Points of the terminal quadrilateral u, x, v, w (terminal edge u-v; w the apex in
    the path's last triangle), each rounded as the area centroid is and kept strictly
    inside the quadrilateral (else the area centroid)."""
    from geomexact.kernel.points import point2
    from geomexact.mesh2d.refinement import centroids

    area = centroids.rounded_area_centroid

    def rounded(exact: Any, pu: Any, pv: Any, pw: Any, px: Any) -> Any:
        corners = (pu, px, pv, pw)
        shortest = min((q.x - p.x) ** 2 + (q.y - p.y) ** 2
                       for p, q in ((pu, px), (px, pv), (pv, pw), (pw, pu)))
        exponent = centroids.floor_log2(shortest) // 2 - centroids.CENTROID_BITS
        for _ in range(8):
            candidate = point2(centroids._round_to(exact.x, exponent),
                               centroids._round_to(exact.y, exponent))
            if centroids._strictly_inside(corners, candidate):
                return candidate
            exponent -= centroids.CENTROID_BITS
        return area(pu, pv, pw, px)

    def triangle_centroid(pu: Any, pv: Any, pw: Any, px: Any) -> Any:
        exact = point2((pu.x + pv.x + pw.x) / 3, (pu.y + pv.y + pw.y) / 3)
        return rounded(exact, pu, pv, pw, px)

    def circumcenter(pu: Any, pv: Any, pw: Any, px: Any) -> Any:
        bx, by, cx, cy = pv.x - pu.x, pv.y - pu.y, pw.x - pu.x, pw.y - pu.y
        d, b2, c2 = 2 * (bx * cy - by * cx), bx * bx + by * by, cx * cx + cy * cy
        exact = point2(pu.x + (cy * b2 - by * c2) / d, pu.y + (bx * c2 - cx * b2) / d)
        return rounded(exact, pu, pv, pw, px)

    def toward_midpoint(share: Any) -> Callable[..., Any]:
        def point(pu: Any, pv: Any, pw: Any, px: Any) -> Any:
            c = area(pu, pv, pw, px)
            mx, my = (pu.x + pv.x) / 2, (pu.y + pv.y) / 2
            return rounded(point2(mx + share * (c.x - mx), my + share * (c.y - my)),
                           pu, pv, pw, px)
        return point

    def larger_triangle_centroid(pu: Any, pv: Any, pw: Any, px: Any) -> Any:
        first = abs((pv.x - pu.x) * (pw.y - pu.y) - (pv.y - pu.y) * (pw.x - pu.x))
        second = abs((pu.x - pv.x) * (px.y - pv.y) - (pu.y - pv.y) * (px.x - pv.x))
        if second > first:
            exact = point2((pu.x + pv.x + px.x) / 3, (pu.y + pv.y + px.y) / 3)
            return rounded(exact, pu, pv, pw, px)
        return triangle_centroid(pu, pv, pw, px)

    from geomexact.kernel.numbers import mpq

    return {
        "area centroid (default)": area,
        "circumcenter of the last terminal triangle": circumcenter,
        "centroid of the last terminal triangle": triangle_centroid,
        "centroid of the larger terminal triangle": larger_triangle_centroid,
        "half-way from e's midpoint to the area centroid": toward_midpoint(mpq(1, 2)),
        "area centroid pushed 1.5x away from e's midpoint": toward_midpoint(mpq(3, 2)),
        "area centroid pushed 2x away from e's midpoint": toward_midpoint(mpq(2)),
    }


def points_section(found: list[Input], angles: tuple[int, ...]) -> list[dict[str, Any]]:
    from geomexact.mesh2d.refinement.engines import reference

    item = by_name(found, "1500random")
    if item is None:
        return []
    rows = []
    original = reference.rounded_area_centroid
    try:
        for label, function in point_rules().items():
            reference.rounded_area_centroid = function
            for degrees in angles:
                run = run_geomexact(item.mesh, degrees, method="centroid", engine="reference",
                                    max_steps=STEP_CAP)
                result = run.pop("_result")
                assert replay(result.start, result.trace).digest == result.mesh.digest
                rows.append({"point": label, "theta": degrees, **run})
                ended = "" if run["status"] == "complete" else \
                    f"  (no end: stopped at {STEP_CAP:,} steps)"
                print(f"{label:<50}{degrees:>3}°  {run['triangles']:>8,}  "
                      f"{run['min_angle']:6.2f}°{ended}", flush=True)
    finally:
        reference.rounded_area_centroid = original
    return rows


def attribution(found: list[Input], degrees: int,
                builder: CircumcenterTriangle | None) -> dict[str, Any]:
    import numpy as np

    item = by_name(found, "1500random")
    if item is None:
        return {}
    meshes: dict[str, tuple[list[tuple[float, float]], list[tuple[int, int, int]]]] = {}
    run = run_geomexact(item.mesh, degrees, method="centroid")
    result = run["_result"]
    order = sorted(result.mesh.vertices)
    number = {v: i for i, v in enumerate(order)}
    meshes["geomexact centroid"] = (
        [(float(result.mesh.point(v).x), float(result.mesh.point(v).y)) for v in order],
        [tuple(number[v] for v in t) for t in result.mesh.triangles()])
    rq = run_triangle(item, degrees, poly=False)
    if rq is not None:
        meshes["Triangle rq"] = ([tuple(p) for p in rq["_output"]["vertices"].tolist()],
                                 [tuple(t) for t in rq["_output"]["triangles"].tolist()])
    if builder is not None:
        plain = builder.run(item, degrees, offcenters=False)
        meshes["Triangle rq, circumcenters"] = (plain["_points"], plain["_triangles"])
    # the convex hull: the input's boundary edges
    start = item.mesh
    hull = [(start.point(u), start.point(v)) for u, v in boundary_edges(start)]
    hull_f = np.array([[float(a.x), float(a.y), float(b.x), float(b.y)] for a, b in hull])
    inputs_n = start.vertex_count
    report: dict[str, Any] = {"theta": degrees, "meshes": {}}
    bands = (0.0, 0.005, 0.02, 0.05, 0.1, 1.0)
    for label, (points, triangles) in meshes.items():
        p = np.array(points)
        distance = hull_distance(p, hull_f)
        band_counts = [int(((distance >= lo) & (distance < hi)).sum())
                       for lo, hi in itertools.pairwise(bands)]
        grid = np.zeros((4, 4), dtype=int)
        for x, y in points:
            grid[min(3, int(y * 4)), min(3, int(x * 4))] += 1
        edges = {tuple(sorted((t[i], t[(i + 1) % 3]))) for t in triangles for i in range(3)}
        lengths = np.array([math.dist(points[a], points[b]) for a, b in edges])
        smallest = np.array([min(angles_of(points, t)) for t in triangles])
        areas = np.array([abs((points[t[1]][0] - points[t[0]][0])
                              * (points[t[2]][1] - points[t[0]][1])
                              - (points[t[1]][1] - points[t[0]][1])
                              * (points[t[2]][0] - points[t[0]][0])) / 2 for t in triangles])
        report["meshes"][label] = {
            "triangles": len(triangles),
            "vertices": len(points),
            "steiner": len(points) - inputs_n,
            "on_hull": int((distance < 1e-12).sum()),
            "distance_bands": dict(zip([f"{lo}-{hi}" for lo, hi in
                                        itertools.pairwise(bands)],
                                       band_counts, strict=True)),
            "grid_4x4_vertices": grid.tolist(),
            "edge_length_quantiles": [float(f"{q:.3g}") for q in
                                      np.quantile(lengths, [0.05, 0.25, 0.5, 0.75, 0.95])],
            "area_quantiles": [float(f"{q:.3g}") for q in
                               np.quantile(areas, [0.05, 0.25, 0.5, 0.75, 0.95])],
            "min_angle_quantiles": [round(float(q), 2) for q in
                                    np.quantile(smallest, [0.05, 0.25, 0.5, 0.75, 0.95])],
            "share_min_angle_below_theta_plus_5": round(
                float((smallest < degrees + 5).mean()), 3),
            "mean_min_angle": round(float(smallest.mean()), 2),
        }
    # geomexact's own record: what each step inserted, and the bad triangles left by each
    ops: dict[str, int] = {}
    for step in result.trace.steps:
        ops[step.op] = ops.get(step.op, 0) + 1
    report["geomexact_steps"] = ops
    report["geomexact_stats"] = {k: v for k, v in result.stats.as_dict().items()
                                 if k != "seconds"}
    for label, value in report["meshes"].items():
        print(f"{label}: {json.dumps(value)}", flush=True)
    print(f"geomexact steps: {ops}", flush=True)
    return report


LFS_BINS = (0.0, 0.004, 0.008, 0.016, 0.032, 1.0)


def steiner_by_feature_size(found: list[Input], angles: tuple[int, ...],
                            builder: CircumcenterTriangle | None) -> list[dict[str, Any]]:
    """1500random: the Steiner points of each mesh binned by the local feature size of the
    input points at them (the distance to the second-nearest input point)."""
    import numpy as np

    item = by_name(found, "1500random")
    if item is None:
        return []
    start = item.mesh
    given = np.array([[float(start.point(v).x), float(start.point(v).y)]
                      for v in sorted(start.vertices)])

    def feature_size(points: Any) -> Any:
        parts = []
        for i in range(0, len(points), 500):
            block = points[i:i + 500]
            d = np.sqrt(((block[:, None, :] - given[None, :, :]) ** 2).sum(-1))
            d.sort(axis=1)
            parts.append(d[:, 1])
        return np.concatenate(parts) if parts else np.zeros(0)

    rows = []
    for degrees in angles:
        added: dict[str, Any] = {}
        result = run_geomexact(start, degrees, method="centroid")["_result"]
        added["geomexact centroid"] = np.array(
            [[float(p.x), float(p.y)] for v, p in sorted(result.mesh.vertices.items())
             if v >= start.vertex_count])
        rq = run_triangle(item, degrees, poly=False)
        if rq is not None:
            added["Triangle rq"] = rq["_output"]["vertices"][len(given):]
        if builder is not None:
            plain = builder.run(item, degrees, offcenters=False)
            added["Triangle rq, circumcenters"] = np.array(plain["_points"][len(given):])
        row: dict[str, Any] = {"theta": degrees, "bins": [f"{lo}-{hi}" for lo, hi in
                                                         itertools.pairwise(LFS_BINS)]}
        for label, points in added.items():
            size = feature_size(points)
            row[label] = [int(((size >= lo) & (size < hi)).sum())
                          for lo, hi in itertools.pairwise(LFS_BINS)]
        rows.append(row)
        print(f"{degrees}° Steiner points by feature size {row['bins']}: "
              + "; ".join(f"{k} {row[k]}" for k in added), flush=True)
    return rows


def boundary_edges(mesh: Mesh2) -> list[tuple[int, int]]:
    edges = []
    for a, b, c in mesh.iter_triangles():
        for u, v in ((a, b), (b, c), (c, a)):
            if mesh.apex(v, u) is None:
                edges.append((u, v))
    return edges


def hull_distance(points: Any, hull: Any) -> Any:
    import numpy as np

    best = np.full(len(points), np.inf)
    for x0, y0, x1, y1 in hull:
        dx, dy = x1 - x0, y1 - y0
        t = np.clip(((points[:, 0] - x0) * dx + (points[:, 1] - y0) * dy)
                    / (dx * dx + dy * dy), 0.0, 1.0)
        d = np.hypot(points[:, 0] - (x0 + t * dx), points[:, 1] - (y0 + t * dy))
        best = np.minimum(best, d)
    return best


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--json", action="store_true", help="print one JSON object at the end")
    parser.add_argument("--quick", action="store_true",
                        help="θ = 30° only, and the rules at 30° only")
    parser.add_argument("--sections", default="baseline,rules,points,attribution")
    parser.add_argument("--triangle-c", type=Path, default=None,
                        help="Triangle's triangle.c, to build it without off-centers")
    options = parser.parse_args(argv)
    sections = set(options.sections.split(","))
    notes: list[str] = []
    found = inputs(notes, options.quick)
    builder = CircumcenterTriangle(options.triangle_c) if options.triangle_c else None
    if builder is None:
        notes.append("no --triangle-c: Triangle without off-centers not measured")
    report: dict[str, Any] = {"notes": notes}
    angles = (30,) if options.quick else ANGLES
    if "baseline" in sections:
        report["baseline"] = baseline(found, angles, builder)
    if "rules" in sections:
        report["rules"] = rules(found, (30,) if options.quick else (25, 30))
    if "points" in sections:
        report["points"] = points_section(found, (30,) if options.quick else (25, 30, 33))
    if "attribution" in sections:
        report["attribution"] = attribution(found, 30, builder)
        report["feature_size"] = steiner_by_feature_size(
            found, (30,) if options.quick else (20, 30), builder)
    for note in notes:
        print(f"({note})")
    if options.json:
        print(json.dumps(report, default=str))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
