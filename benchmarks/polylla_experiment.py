"""Polylla and its convex decomposition on Delaunay meshes of growing point sets.

For each kind of point set (uniform random, semi-uniform, Poisson-disk) and size, the
Delaunay triangulation is built
(``geomexact.mesh2d.delaunay.triangulation.triangulate``), then Polylla, then
the convex decomposition with and without criterion 1.  One table row per mesh: points,
triangles, polygons, non-convex polygons, edges inserted (criterion 1 on / off), polygons
after, and the seconds of Polylla and of the decomposition (criterion 1 on).  The shared
``polylla-refinement`` meshes follow when ``../shared/data`` exists.

    .venv/bin/python benchmarks/polylla_experiment.py            # 500 … 30,000 points (~1 min)
    .venv/bin/python benchmarks/polylla_experiment.py --full     # … and 50,000, 100,000
    .venv/bin/python benchmarks/polylla_experiment.py --quick    # 500 … 5,000 (seconds)
    .venv/bin/python benchmarks/polylla_experiment.py --big      # the 10^5-triangle timing

Semi-uniform points are the vertices of a quality mesh of the unit square made by Shewchuk's
Triangle (``triangle`` package, the ``bench`` extra: minimum angle 30°, maximum area chosen
for the size), or, without that package, a jittered triangular lattice.  Poisson-disk
points come from Bridson's dart throwing.  All coordinates are doubles, read exactly.
Results and timings depend on the seed (``--seed``), never on anything else.
"""

from __future__ import annotations

import argparse
import math
import random
import statistics
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from geomexact import Mesh2, io, point2
from geomexact.kernel.points import Point2
from geomexact.mesh2d.delaunay.triangulation import triangulate
from geomexact.mesh2d.polygonal.convex import convex_decomposition
from geomexact.mesh2d.polygonal.polylla_meshing import polylla_run

PROJECT = Path(__file__).resolve().parent.parent
SHARED = PROJECT.parent / "shared" / "data" / "polylla-refinement"
DEFAULT_SIZES = (500, 1000, 2000, 5000, 10000, 20000, 30000)
FULL_SIZES = (*DEFAULT_SIZES, 50000, 100000)
QUICK_SIZES = (500, 1000, 2000, 5000)


# -----------------------------------------------------------------------------------------
# point sets in the unit square
# -----------------------------------------------------------------------------------------
def random_points(count: int, seed: int) -> list[Point2]:
    rng = random.Random(seed)
    return [point2(rng.random(), rng.random()) for _ in range(count)]


def _triangle_quality_points(count: int) -> list[Point2] | None:
    try:
        import triangle  # type: ignore[import-untyped]
    except ImportError:
        return None
    square = {"vertices": [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
              "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
    area = 1.0 / count  # a first guess; the count of points scales like 1 / area
    vertices: list[list[float]] = []
    for _ in range(4):
        vertices = triangle.triangulate(square, f"pq30a{area:.12f}Q")["vertices"].tolist()
        if abs(len(vertices) - count) <= 0.03 * count:
            break
        area *= len(vertices) / count
    return [point2(x, y) for x, y in vertices]


def semi_uniform_points(count: int, seed: int) -> tuple[list[Point2], str]:
    """Quality-mesh vertices (Triangle), else a jittered triangular lattice."""
    points = _triangle_quality_points(count)
    if points is not None:
        return points, "Triangle -q30"
    rng = random.Random(seed)
    rows = max(2, round(math.sqrt(count * math.sqrt(3) / 2)))
    columns = max(2, round(count / rows))
    step_x, step_y = 1.0 / columns, 1.0 / rows
    points = []
    for row in range(rows):
        for column in range(columns):
            shift = 0.5 * step_x if row % 2 else 0.0
            x = (column + shift / step_x + rng.uniform(-0.15, 0.15)) * step_x
            y = (row + rng.uniform(-0.15, 0.15)) * step_y
            points.append(point2(min(max(x, 0.0), 1.0), min(max(y, 0.0), 1.0)))
    return points, "jittered lattice"


def poisson_disk_points(count: int, seed: int) -> list[Point2]:
    """Bridson's Poisson-disk sampling of the unit square with a radius giving about
    ``count`` points (maximal samplings cover about 0.7 of the square with r/2 disks)."""
    rng = random.Random(seed)
    radius = math.sqrt(0.7 / (count * math.pi / 4)) * 0.85
    cell = radius / math.sqrt(2)
    size = math.ceil(1.0 / cell)
    grid: dict[tuple[int, int], tuple[float, float]] = {}
    samples: list[tuple[float, float]] = []

    def fits(x: float, y: float) -> bool:
        gx, gy = int(x / cell), int(y / cell)
        for i in range(max(gx - 2, 0), min(gx + 3, size)):
            for j in range(max(gy - 2, 0), min(gy + 3, size)):
                other = grid.get((i, j))
                if other is not None and (other[0] - x) ** 2 + (other[1] - y) ** 2 < radius**2:
                    return False
        return True

    first = (rng.random(), rng.random())
    samples.append(first)
    grid[int(first[0] / cell), int(first[1] / cell)] = first
    active = [first]
    while active:
        index = rng.randrange(len(active))
        x0, y0 = active[index]
        for _ in range(30):
            angle = rng.random() * 2 * math.pi
            distance = radius * (1 + rng.random())
            x, y = x0 + distance * math.cos(angle), y0 + distance * math.sin(angle)
            if 0.0 <= x < 1.0 and 0.0 <= y < 1.0 and fits(x, y):
                samples.append((x, y))
                grid[int(x / cell), int(y / cell)] = (x, y)
                active.append((x, y))
                break
        else:
            active[index] = active[-1]
            active.pop()
    return [point2(x, y) for x, y in samples]


# -----------------------------------------------------------------------------------------
# one row
# -----------------------------------------------------------------------------------------
COLUMNS = ("input", "points", "triangles", "polygons", "nonconvex", "inserted",
           "inserted_no_c1", "polygons_after", "polylla_s", "convex_s")


def measure(name: str, mesh: Mesh2) -> dict[str, object]:
    started = time.perf_counter()
    run = polylla_run(mesh)
    middle = time.perf_counter()
    with_one = convex_decomposition(run.mesh)
    ended = time.perf_counter()
    without_one = convex_decomposition(run.mesh, criterion_one=False)
    used = len({v for t in mesh.iter_triangles() for v in t})
    return {
        "input": name,
        "points": used,
        "triangles": mesh.triangle_count,
        "polygons": len(run.mesh.polygons),
        "nonconvex": with_one.nonconvex_before,
        "inserted": len(with_one.inserted_edges),
        "inserted_no_c1": len(without_one.inserted_edges),
        "polygons_after": len(with_one.mesh.polygons),
        "polylla_s": round(middle - started, 3),
        "convex_s": round(ended - middle, 3),
    }


def print_row(row: dict[str, object], widths: Sequence[int]) -> None:
    cells = [str(row[column]).rjust(width) if column != "input" else
             str(row[column]).ljust(width) for column, width in zip(COLUMNS, widths, strict=True)]
    print("  ".join(cells), flush=True)


def experiment(sizes: Sequence[int], seed: int) -> None:
    widths = [26, 7, 9, 8, 9, 8, 14, 14, 9, 8]
    print_row({column: column for column in COLUMNS}, widths)
    kinds: list[tuple[str, Callable[[int], tuple[list[Point2], str]]]] = [
        ("random", lambda n: (random_points(n, seed), "")),
        ("semi-uniform", lambda n: semi_uniform_points(n, seed)),
        ("poisson-disk", lambda n: (poisson_disk_points(n, seed), "")),
    ]
    notes = set()
    for kind, make in kinds:
        for size in sizes:
            points, note = make(size)
            if note:
                notes.add(f"semi-uniform points: {note}")
            mesh = triangulate(points, merge_duplicates=True).mesh
            print_row(measure(f"{kind} {size}", mesh), widths)
    for name in ("500poisson.off", "1500random.off"):
        path = SHARED / name
        if path.exists():
            value = io.read(path)
            assert isinstance(value, Mesh2)
            print_row(measure(name, value), widths)
        else:
            notes.add(f"{path} not found: skipped")
    for note in sorted(notes):
        print(f"({note})")


def big(seed: int, repeats: int) -> None:
    """Polylla + convex decomposition of a Delaunay mesh of about 10^5 triangles."""
    started = time.perf_counter()
    mesh = triangulate(random_points(50_000, seed)).mesh
    print(f"Delaunay triangulation of 50,000 random points: {mesh.triangle_count} "
          f"triangles in {time.perf_counter() - started:.2f} s")
    totals = []
    for attempt in range(repeats):
        row = measure("random 50000", mesh)
        total = float(row["polylla_s"]) + float(row["convex_s"])  # type: ignore[arg-type]
        totals.append(total)
        print(f"run {attempt + 1}: polylla {row['polylla_s']} s ({row['polygons']} polygons), "
              f"convex {row['convex_s']} s ({row['inserted']} edges inserted, "
              f"{row['polygons_after']} polygons): total {total:.2f} s")
    print(f"best {min(totals):.2f} s, median {statistics.median(totals):.2f} s "
          f"(target: 10 s)")


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--full", action="store_true", help="also 50,000 and 100,000 points")
    parser.add_argument("--quick", action="store_true", help="only 500 … 5,000 points")
    parser.add_argument("--sizes", type=int, nargs="+", metavar="N", help="explicit sizes")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    parser.add_argument("--big", action="store_true",
                        help="only time Polylla + convex decomposition of ~10^5 triangles")
    parser.add_argument("--repeats", type=int, default=3, help="runs of --big (default 3)")
    args = parser.parse_args(argv)
    if args.big:
        big(args.seed, args.repeats)
        return 0
    sizes = args.sizes or (FULL_SIZES if args.full else
                           QUICK_SIZES if args.quick else DEFAULT_SIZES)
    experiment(sizes, args.seed)
    return 0


if __name__ == "__main__":
    sys.exit(main())
