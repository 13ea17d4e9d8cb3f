"""The cuboid census: partitions per second, against the target of the issue (the full
census of both shapes, both orders, with the improvement: 4 x 262,143 partitions in
<= 5 minutes on a 2-core machine, i.e. ~3,500 partitions per second in all).

Usage::

    .venv/bin/python benchmarks/bench_census.py [--sample 20000] [--workers N]
        [--reference 200] [--full [--out DIR]] [--dask-patterns all | --no-dask]
        [--repeat 2] [--json]

* the sample (default): ``--sample`` patterns drawn at random from 1 .. 262,143 (not the
  first ones: patterns below 4096 have no face centre and are the cheapest), for each of
  the four (shape, order) pairs, with the improvement, on one process and on the pool;
  the full run's time is extrapolated from the pool's rate; the exact reference engine is
  timed on ``--reference`` patterns for comparison;
* ``--full``: the full census itself (every pattern, all four pairs, on the pool),
  timed, writing one CSV per pair into ``--out`` when given, and printing the summaries
  (``docs/cuboid.md`` quotes them);
* Dask against the pool (unless ``--no-dask``, or when ``dask[distributed]`` is not
  installed): the census of ``--dask-patterns`` (default all 262,143) of the unit cube,
  plain (the command's default) and improved, on the local pool of ``--workers`` processes
  and on a ``distributed.LocalCluster`` of as many worker processes of one thread each,
  best of ``--repeat``, with the ratio Dask / pool (target <= 2) and a check that both give
  the same rows.  The cluster is started once, before the timed runs; its start and its
  first census on fresh workers (each imports geomexact) are reported apart.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import random
import sys
import time
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from geomexact.mesh3d.cuboid import compiled
from geomexact.mesh3d.cuboid.boxes import box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.census import summarize
from geomexact.mesh3d.cuboid.census_runs import CensusJob, parse_patterns, run_census
from geomexact.mesh3d.cuboid.numbering import PATTERN_COUNT

TARGET_SECONDS = 300.0
TARGET_DASK_RATIO = 2.0
FULL = 4 * (PATTERN_COUNT - 1)
PAIRS = [(box, order) for box in (unit_cube(), box_of_extents(1, 2, 4))
         for order in ("conforming", "index")]


def timed(patterns: Any, job: CensusJob, workers: int) -> tuple[float, list[Any]]:
    started = time.perf_counter()
    rows = run_census(patterns, job, workers=workers)
    return time.perf_counter() - started, rows


def dask_against_pool(patterns: Any, workers: int, repeat: int) -> dict[str, Any]:
    """The census of ``patterns`` on the pool and on a local Dask cluster: times, ratios
    and whether the rows are the same."""
    import distributed

    started = time.perf_counter()
    with distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        address = cluster.scheduler_address
        cluster_start = time.perf_counter() - started
        cold_job = CensusJob(unit_cube())
        started = time.perf_counter()
        run_census(patterns, cold_job, dask_address=address)
        first = time.perf_counter() - started
        runs = []
        for name, job in (("plain", cold_job), ("improved", CensusJob(unit_cube(),
                                                                      improve=True))):
            pool_best = dask_best = float("inf")
            same = True
            for _ in range(repeat):
                seconds, pool_rows = timed(patterns, job, workers)
                pool_best = min(pool_best, seconds)
                began = time.perf_counter()
                dask_rows = run_census(patterns, job, dask_address=address)
                dask_best = min(dask_best, time.perf_counter() - began)
                same = same and dask_rows == pool_rows
                del pool_rows, dask_rows
            runs.append({"census": name, "patterns": len(patterns),
                         "pool_seconds": round(pool_best, 3),
                         "dask_seconds": round(dask_best, 3),
                         "ratio_dask_to_pool": round(dask_best / pool_best, 3),
                         "same_rows": same})
    return {"cluster": f"LocalCluster: {workers} worker processes x 1 thread",
            "cluster_start_seconds": round(cluster_start, 3),
            "first_census_seconds": round(first, 3),
            "runs": runs, "target_ratio": TARGET_DASK_RATIO,
            "within_target": all(r["ratio_dask_to_pool"] <= TARGET_DASK_RATIO
                                 and r["same_rows"] for r in runs)}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sample", type=int, default=20000)
    parser.add_argument("--reference", type=int, default=200)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--full", action="store_true")
    parser.add_argument("--out", type=Path)
    parser.add_argument("--dask-patterns", default="all", metavar="all|A-B|N,M,...",
                        help="the patterns of the Dask / pool comparison (default all)")
    parser.add_argument("--no-dask", action="store_true",
                        help="skip the Dask / pool comparison")
    parser.add_argument("--repeat", type=int, default=2,
                        help="runs of each Dask / pool census (the best is kept)")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    report: dict[str, Any] = {"kernel": compiled.AVAILABLE, "workers": args.workers,
                              "cores": os.cpu_count(), "target_seconds": TARGET_SECONDS}
    rng = random.Random(12)
    sample = sorted(rng.sample(range(1, PATTERN_COUNT), args.sample))
    one = pool = 0.0
    for box, order in PAIRS:
        job = CensusJob(box, order, improve=True)
        one += timed(sample, job, 1)[0]
        pool += timed(sample, job, args.workers)[0]
    reference_sample = sample[:: max(1, len(sample) // args.reference)][: args.reference]
    reference = sum(timed(reference_sample, CensusJob(box, order, improve=True,
                                                      engine="reference"), 1)[0]
                    for box, order in PAIRS)
    count = 4 * len(sample)
    report["sample"] = {
        "patterns_per_pair": len(sample),
        "rate_one_process": round(count / one, 1),
        "rate_pool": round(count / pool, 1),
        "full_census_seconds_extrapolated": round(FULL / (count / pool), 1),
        "reference_rate_one_process": round(4 * len(reference_sample) / reference, 1),
    }
    if args.full:
        started = time.perf_counter()
        summaries = []
        for box, order in PAIRS:
            job = CensusJob(box, order, improve=True)
            rows = run_census(range(1, PATTERN_COUNT), job, workers=args.workers)
            summaries += [s.report() for s in summarize(rows)]
            if args.out:
                from geomexact.cli.census import csv_lines
                from geomexact.io.files import write_lines_atomic

                args.out.mkdir(parents=True, exist_ok=True)
                name = f"census-{box.describe()}-{order}.csv"
                write_lines_atomic(args.out / name, csv_lines(rows), overwrite=True)
        seconds = time.perf_counter() - started
        report["full"] = {"partitions": FULL, "seconds": round(seconds, 1),
                          "rate": round(FULL / seconds, 1),
                          "within_target": seconds <= TARGET_SECONDS,
                          "summaries": summaries}
    if not args.no_dask:
        if importlib.util.find_spec("distributed") is None:
            report["dask"] = {"skipped": "dask[distributed] is not installed"}
        else:
            report["dask"] = dask_against_pool(parse_patterns(args.dask_patterns),
                                               args.workers, args.repeat)
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        s = report["sample"]
        print(f"kernel built: {report['kernel']}; {args.workers} workers on "
              f"{report['cores']} cores")
        print(f"sample of {s['patterns_per_pair']} patterns x 4 pairs, improved: "
              f"{s['rate_one_process']:,.0f}/s on one process, {s['rate_pool']:,.0f}/s on "
              f"the pool -> full census ~{s['full_census_seconds_extrapolated']} s "
              f"(target {TARGET_SECONDS:.0f} s); reference engine "
              f"{s['reference_rate_one_process']:,.0f}/s")
        if "full" in report:
            f = report["full"]
            print(f"full census: {f['partitions']:,} partitions in {f['seconds']} s "
                  f"({f['rate']:,.0f}/s), within target: {f['within_target']}")
            for summary in f["summaries"]:
                print(json.dumps({k: summary[k] for k in (
                    "shape", "order", "patterns", "valid", "delaunay_percent",
                    "failing_percent", "present_percent", "delaunay_improved_percent",
                    "failing_improved_percent", "flips", "tetrahedra_mean",
                    "tetrahedra_improved_mean", "rounds_max")}))
        d = report.get("dask")
        if d and "runs" in d:
            print(f"dask: {d['cluster']}, started in {d['cluster_start_seconds']} s, "
                  f"first census on fresh workers {d['first_census_seconds']} s")
            for r in d["runs"]:
                print(f"  {r['census']:<9} {r['patterns']:,} patterns: pool "
                      f"{r['pool_seconds']} s, dask {r['dask_seconds']} s, dask / pool "
                      f"{r['ratio_dask_to_pool']} (target <= {d['target_ratio']:g}), "
                      f"same rows: {r['same_rows']}")
            print(f"  within target: {d['within_target']}")
        elif d:
            print(f"dask: skipped ({d['skipped']})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
