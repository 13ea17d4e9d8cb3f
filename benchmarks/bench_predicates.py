"""Calls per second of the adaptive predicates against plain-float Python and Shewchuk's C.

Usage::

    .venv/bin/python benchmarks/bench_predicates.py [--n 2000] [--repeat 7] [--json]

Workloads (fixed seed, so runs are comparable):

* ``filtered``: random points in the unit square/cube plus an offset of 0..1000, coordinates
  exact rationals p/q (so their floats are *not* exact): almost every call is settled by
  the float filter.
* ``degenerate``: collinear / cocircular / coplanar / cospherical inputs built from exact
  rationals: every call falls back to exact rational arithmetic.

Competitors, in the same run, on the same points:

* ``plain``: the determinant written inline in Python on the cached floats
  (``(a[2] - c[2]) * (b[3] - c[3]) - ...``), returning the float -- the cost floor of any
  Python predicate; ``plain_sign`` also turns it into -1/0/1 like a predicate must.
* ``shewchuk``: the ``shewchuk`` package (C, robust adaptive; 2D only: ``orientation``,
  ``incircle_test``) called with the six/eight floats unpacked from the points.

Timing: each function is timed on the whole list of argument tuples, ``--repeat`` times,
interleaved with its competitors; the minimum is reported (the usual ``timeit`` practice).
The target is adaptive <= 2x ``plain`` on the filtered workload.
"""

from __future__ import annotations

import argparse
import json
import platform
import random
import sys
import time
from collections.abc import Callable, Sequence
from fractions import Fraction
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from geomexact.kernel.filter_bounds import filter_counters, reset_filter_counters
from geomexact.kernel.points import Point2, Point3, point2, point3
from geomexact.kernel.predicates2d import incircle, orient2d
from geomexact.kernel.predicates3d import insphere, orient3d

TARGET_RATIO = 2.0


# --- plain-float competitors --------------------------------------------------------------


def plain_orient2d(a: Point2, b: Point2, c: Point2) -> float:
    return (a[2] - c[2]) * (b[3] - c[3]) - (a[3] - c[3]) * (b[2] - c[2])


def plain_sign_orient2d(a: Point2, b: Point2, c: Point2) -> int:
    det = (a[2] - c[2]) * (b[3] - c[3]) - (a[3] - c[3]) * (b[2] - c[2])
    return (det > 0) - (det < 0)


def plain_incircle(a: Point2, b: Point2, c: Point2, d: Point2) -> float:
    dx = d[2]
    dy = d[3]
    adx = a[2] - dx
    ady = a[3] - dy
    bdx = b[2] - dx
    bdy = b[3] - dy
    cdx = c[2] - dx
    cdy = c[3] - dy
    return (
        (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy)
        + (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy)
        + (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady)
    )


def plain_orient3d(a: Point3, b: Point3, c: Point3, d: Point3) -> float:
    dx = d[3]
    dy = d[4]
    dz = d[5]
    adx = a[3] - dx
    ady = a[4] - dy
    adz = a[5] - dz
    bdx = b[3] - dx
    bdy = b[4] - dy
    bdz = b[5] - dz
    cdx = c[3] - dx
    cdy = c[4] - dy
    cdz = c[5] - dz
    return (
        adz * (cdx * bdy - bdx * cdy)
        + bdz * (adx * cdy - cdx * ady)
        + cdz * (bdx * ady - adx * bdy)
    )


def plain_insphere(a: Point3, b: Point3, c: Point3, d: Point3, e: Point3) -> float:
    ex = e[3]
    ey = e[4]
    ez = e[5]
    aex = a[3] - ex
    aey = a[4] - ey
    aez = a[5] - ez
    bex = b[3] - ex
    bey = b[4] - ey
    bez = b[5] - ez
    cex = c[3] - ex
    cey = c[4] - ey
    cez = c[5] - ez
    dex = d[3] - ex
    dey = d[4] - ey
    dez = d[5] - ez
    ab = aex * bey - bex * aey
    bc = bex * cey - cex * bey
    cd = cex * dey - dex * cey
    da = dex * aey - aex * dey
    ac = aex * cey - cex * aey
    bd = bex * dey - dex * bey
    abc = aez * bc - bez * ac + cez * ab
    bcd = bez * cd - cez * bd + dez * bc
    cda = cez * da + dez * ac + aez * cd
    dab = dez * ab + aez * bd + bez * da
    return (
        (cex * cex + cey * cey + cez * cez) * dab - (dex * dex + dey * dey + dez * dez) * abc
    ) + ((aex * aex + aey * aey + aez * aez) * bcd - (bex * bex + bey * bey + bez * bez) * cda)


def shewchuk_functions() -> tuple[Callable[..., Any], Callable[..., Any]] | None:
    try:
        import shewchuk  # type: ignore[import-not-found]
    except ImportError:
        return None
    orientation = shewchuk.orientation
    incircle_test = shewchuk.incircle_test

    def shewchuk_orient2d(a: Point2, b: Point2, c: Point2) -> int:
        return orientation(a[2], a[3], b[2], b[3], c[2], c[3])  # type: ignore[no-any-return]

    def shewchuk_incircle(a: Point2, b: Point2, c: Point2, d: Point2) -> int:
        return incircle_test(  # type: ignore[no-any-return]
            d[2], d[3], a[2], a[3], b[2], b[3], c[2], c[3]
        )

    return shewchuk_orient2d, shewchuk_incircle


# --- workloads ----------------------------------------------------------------------------


def _coordinate(rng: random.Random, offset: int) -> Fraction:
    return offset + Fraction(rng.randrange(1, 10**9), 3 * 10**9 + 1 + 2 * rng.randrange(10**6))


def filtered_points2(rng: random.Random, count: int) -> list[Point2]:
    offset = rng.randrange(1000)
    return [point2(_coordinate(rng, offset), _coordinate(rng, offset)) for _ in range(count)]


def filtered_points3(rng: random.Random, count: int) -> list[Point3]:
    offset = rng.randrange(1000)
    return [
        point3(_coordinate(rng, offset), _coordinate(rng, offset), _coordinate(rng, offset))
        for _ in range(count)
    ]


def workloads(n: int, seed: int) -> dict[str, dict[str, list[tuple[Any, ...]]]]:
    """``{predicate: {"filtered": [args...], "degenerate": [args...]}}``."""
    rng = random.Random(seed)
    p2 = filtered_points2(rng, n + 4)
    p3 = filtered_points3(rng, n + 5)
    result: dict[str, dict[str, list[tuple[Any, ...]]]] = {
        "orient2d": {"filtered": [tuple(p2[i : i + 3]) for i in range(n)]},
        "incircle": {"filtered": [tuple(p2[i : i + 4]) for i in range(n)]},
        "orient3d": {"filtered": [tuple(p3[i : i + 4]) for i in range(n)]},
        "insphere": {"filtered": [tuple(p3[i : i + 5]) for i in range(n)]},
    }
    # Degenerate: points on a line / circle / plane / sphere with rational coordinates.
    collinear, cocircular, coplanar, cospherical = [], [], [], []
    for _ in range(n):
        a, b = p2[rng.randrange(n)], p2[rng.randrange(n)]
        t = Fraction(rng.randrange(-50, 50), rng.randrange(1, 50))
        c = point2(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))
        collinear.append((a, b, c))
        center = (Fraction(rng.randrange(1000), 7), Fraction(rng.randrange(1000), 7))
        circle = []
        for _ in range(4):  # rational points on a circle: (1 - s^2, 2s) / (1 + s^2)
            s = Fraction(rng.randrange(-40, 40), rng.randrange(1, 40))
            radius = Fraction(5, 3)
            circle.append(
                point2(
                    center[0] + radius * (1 - s * s) / (1 + s * s),
                    center[1] + radius * 2 * s / (1 + s * s),
                )
            )
        cocircular.append(tuple(circle))
        q = p3[rng.randrange(n)]
        u = (Fraction(rng.randrange(-9, 9), 7), Fraction(rng.randrange(-9, 9), 5), 1)
        v = (Fraction(rng.randrange(-9, 9), 3), 1, Fraction(rng.randrange(-9, 9), 11))
        plane = []
        for _ in range(4):
            s, r = Fraction(rng.randrange(-99, 99), 13), Fraction(rng.randrange(-99, 99), 17)
            plane.append(point3(*(q[i] + s * u[i] + r * v[i] for i in range(3))))
        coplanar.append(tuple(plane))
        sphere = []
        for _ in range(5):  # inverse stereographic projection of rational (s, r)
            s, r = Fraction(rng.randrange(-30, 30), 7), Fraction(rng.randrange(-30, 30), 11)
            w = 1 + s * s + r * r
            sphere.append(point3(q.x + 2 * s / w, q.y + 2 * r / w, q.z + (s * s + r * r - 1) / w))
        cospherical.append(tuple(sphere))
    result["orient2d"]["degenerate"] = collinear  # type: ignore[assignment]
    result["incircle"]["degenerate"] = cocircular
    result["orient3d"]["degenerate"] = coplanar
    result["insphere"]["degenerate"] = cospherical
    return result


# --- timing -------------------------------------------------------------------------------


def _loop(function: Callable[..., Any], arguments: Sequence[tuple[Any, ...]]) -> float:
    start = time.perf_counter()
    for args in arguments:
        function(*args)
    return time.perf_counter() - start


def time_functions(
    functions: dict[str, Callable[..., Any]],
    arguments: Sequence[tuple[Any, ...]],
    repeat: int,
) -> dict[str, float]:
    """Best-of-``repeat`` nanoseconds per call, competitors interleaved.

    The time includes the loop and the ``function(*args)`` call, the same for every
    competitor.
    """
    best = {name: float("inf") for name in functions}
    for _ in range(repeat):
        for name, function in functions.items():
            best[name] = min(best[name], _loop(function, arguments))
    return {name: seconds / len(arguments) * 1e9 for name, seconds in best.items()}


def run(n: int, repeat: int, seed: int) -> dict[str, Any]:
    loads = workloads(n, seed)
    shew = shewchuk_functions()
    plain: dict[str, Callable[..., Any]] = {
        "orient2d": plain_orient2d,
        "incircle": plain_incircle,
        "orient3d": plain_orient3d,
        "insphere": plain_insphere,
    }
    adaptive: dict[str, Callable[..., Any]] = {
        "orient2d": orient2d,
        "incircle": incircle,
        "orient3d": orient3d,
        "insphere": insphere,
    }
    report: dict[str, Any] = {
        "python": platform.python_version(),
        "machine": platform.machine(),
        "n": n,
        "repeat": repeat,
        "seed": seed,
        "target_ratio": TARGET_RATIO,
        "predicates": {},
    }
    for name in adaptive:
        functions: dict[str, Callable[..., Any]] = {
            "adaptive": adaptive[name],
            "plain": plain[name],
        }
        if name == "orient2d":
            functions["plain_sign"] = plain_sign_orient2d
        if shew is not None and name in ("orient2d", "incircle"):
            functions["shewchuk"] = shew[0] if name == "orient2d" else shew[1]
        reset_filter_counters()
        filtered = time_functions(functions, loads[name]["filtered"], repeat)
        hits, misses = filter_counters()[name]
        degenerate = time_functions(
            {"adaptive": adaptive[name]}, loads[name]["degenerate"], max(1, repeat // 2)
        )
        reset_filter_counters()
        for args in loads[name]["degenerate"]:
            adaptive[name](*args)
        _, degenerate_misses = filter_counters()[name]
        entry: dict[str, Any] = {
            "filtered_ns": {key: round(value, 1) for key, value in filtered.items()},
            "filtered_calls_per_second": {
                key: round(1e9 / value) for key, value in filtered.items() if value > 0
            },
            "filter_hit_rate": hits / max(1, hits + misses),
            "ratio_vs_plain": round(filtered["adaptive"] / filtered["plain"], 3),
            "target_met": filtered["adaptive"] <= TARGET_RATIO * filtered["plain"],
            "degenerate_ns": round(degenerate["adaptive"], 1),
            "degenerate_calls_per_second": round(1e9 / degenerate["adaptive"]),
            "degenerate_exact_rate": degenerate_misses / len(loads[name]["degenerate"]),
            "degenerate_ratio_vs_filtered": round(degenerate["adaptive"] / filtered["adaptive"], 1),
        }
        if "plain_sign" in filtered:
            entry["ratio_vs_plain_sign"] = round(filtered["adaptive"] / filtered["plain_sign"], 3)
        if "shewchuk" in filtered:
            entry["ratio_vs_shewchuk"] = round(filtered["adaptive"] / filtered["shewchuk"], 3)
        report["predicates"][name] = entry
    return report


def print_report(report: dict[str, Any]) -> None:
    print(
        f"Python {report['python']} ({report['machine']}), {report['n']} calls per workload, "
        f"best of {report['repeat']}"
    )
    for name, entry in report["predicates"].items():
        ns = entry["filtered_ns"]
        parts = ", ".join(f"{key} {value:.0f} ns" for key, value in ns.items())
        print(f"\n{name}: filtered workload (hit rate {entry['filter_hit_rate']:.4f}): {parts}")
        line = f"  adaptive / plain = {entry['ratio_vs_plain']:.2f}"
        if "ratio_vs_plain_sign" in entry:
            line += f", / plain_sign = {entry['ratio_vs_plain_sign']:.2f}"
        if "ratio_vs_shewchuk" in entry:
            line += f", / shewchuk = {entry['ratio_vs_shewchuk']:.2f}"
        met = "met" if entry["target_met"] else "NOT met"
        print(f"{line}   target <= {report['target_ratio']:.0f}x plain: {met}")
        print(
            f"  degenerate workload (exact rate {entry['degenerate_exact_rate']:.2f}): "
            f"{entry['degenerate_ns']:.0f} ns/call = {entry['degenerate_calls_per_second']:,} "
            f"calls/s, {entry['degenerate_ratio_vs_filtered']:.0f}x the filtered cost"
        )


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--n", type=int, default=2000, help="calls per workload")
    parser.add_argument("--repeat", type=int, default=7, help="timing repetitions (best of)")
    parser.add_argument("--seed", type=int, default=20240601)
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args(argv)
    if args.n < 1 or args.repeat < 1:
        parser.error("--n and --repeat must be positive")
    report = run(args.n, args.repeat, args.seed)
    if args.json:
        print(json.dumps(report, sort_keys=True))
    else:
        print_report(report)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
