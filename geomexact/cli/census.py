"""``geomexact census``: the census of 1-irregular cuboid patterns (one CSV row per
pattern, Parquet beside it when pyarrow is importable, and a summary), on a local
process pool or a Dask cluster."""

from __future__ import annotations

import argparse
import csv
import importlib
import io
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from geomexact.cli.arguments import (
    Subcommands,
    add_command,
    add_engine_option,
    add_force_flag,
    add_json_flag,
    add_output_option,
    positive_int,
)
from geomexact.cli.cuboid import add_cuboid_options, shape_box
from geomexact.cli.errors import UsageProblem
from geomexact.cli.exit_codes import EXIT_FAILED, EXIT_OK
from geomexact.cli.progress import add_progress_flags, progress_bar
from geomexact.cli.reporting import print_json
from geomexact.errors import OverwriteError
from geomexact.io.files import write_lines_atomic
from geomexact.mesh3d.cuboid.census import CENSUS_COLUMNS, CensusRow, CensusSummary, summarize


def csv_lines(rows: Sequence[CensusRow]) -> Iterator[str]:
    """The CSV file's lines: the header, then one line per row (None as empty)."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="")
    writer.writerow(CENSUS_COLUMNS)
    yield buffer.getvalue()
    for row in rows:
        buffer.seek(0)
        buffer.truncate()
        record = row.record()
        writer.writerow(["" if record[c] is None else record[c] for c in CENSUS_COLUMNS])
        yield buffer.getvalue()


def _pyarrow() -> Any:
    try:  # optional, found at run time (no stubs: imported by name)
        pyarrow = importlib.import_module("pyarrow")
        importlib.import_module("pyarrow.parquet")
    except ImportError:
        return None
    return pyarrow


def write_parquet(path: Path, rows: Sequence[CensusRow], pyarrow: Any) -> None:
    """The rows as a Parquet table with the CSV's columns (written to a temporary file,
    then renamed)."""
    records = [row.record() for row in rows]
    table = pyarrow.table({column: [r[column] for r in records] for column in CENSUS_COLUMNS})
    partial = path.with_name(path.name + ".partial")
    pyarrow.parquet.write_table(table, partial)
    partial.replace(path)


def summary_lines(summary: CensusSummary, seconds: float) -> list[str]:
    """The summary as a text table."""
    def pct(count: int) -> str:
        return f"{summary.percent(count):6.2f} %"

    lines = [
        f"census of {summary.patterns} patterns: shape {summary.shape}, order "
        f"{summary.order}, template {summary.template}"
        + (", improved" if summary.improved else "") + f" ({seconds:.1f} s)",
        f"  valid (exact volume)           {summary.valid:>7}  {pct(summary.valid)}",
        f"  Delaunay as partitioned        {summary.delaunay:>7}  {pct(summary.delaunay)}",
        f"  tetrahedra                     mean {summary.tetrahedra / summary.patterns:.3f}, "
        f"{summary.tetrahedra_min} .. {summary.tetrahedra_max}" if summary.patterns else "",
        "  configuration   has one           has a failing one",
    ]
    for kind in ("T22", "T23", "T32", "T44", "N32", "N44", "N40", "N30", "N20"):
        present, failing = summary.present[kind], summary.failing[kind]
        if present or kind.startswith("T"):
            lines.append(f"    {kind}          {present:>7} {pct(present)}  "
                         f"{failing:>7} {pct(failing)}")
    if summary.improved:
        flips = ", ".join(f"{name} {count}" for name, count in summary.flips.items())
        lines += [
            f"  improvement flips              {flips}",
            f"  tetrahedra improved            mean "
            f"{summary.tetrahedra_improved / summary.improved:.3f}",
            f"  Delaunay after improvement     {summary.delaunay_improved:>7}  "
            f"{pct(summary.delaunay_improved)}",
            "  still failing across           "
            + ", ".join(f"{kind} {count} ({summary.percent(count):.2f} %)"
                        for kind, count in summary.failing_improved.items() if count),
            f"  rounds (max)                   {summary.rounds_max}",
        ]
    return [line for line in lines if line]


def _cells_chunk(patterns: Sequence[int], box: Any) -> Any:
    from geomexact.mesh3d.cuboid.polyhedral_census import polyhedral_census

    return polyhedral_census(patterns, box)


def command_cells(args: argparse.Namespace, box: Any, patterns: Sequence[int]) -> int:
    """``census --cells``: the polyhedral Delaunay cells of the patterns, counted by shape
    up to the cuboid's symmetries (docs/polyhedral-cells.md); -o writes one CSV row per
    shape."""
    from concurrent.futures import ProcessPoolExecutor

    from geomexact.mesh3d.cuboid.polyhedral_census import merged

    if args.output and Path(args.output).suffix.lower() != ".csv":
        raise UsageProblem(f"{args.output}: census --cells -o writes CSV; give a name ending "
                           "in .csv")
    if args.output and Path(args.output).exists() and not args.force:
        raise OverwriteError(args.output)
    size = 2048
    chunks = [list(patterns[start:start + size]) for start in range(0, len(patterns), size)]
    bar = progress_bar(args, f"census --cells {box.describe()}")
    started = time.perf_counter()
    result = None
    with ProcessPoolExecutor(args.workers) as pool:
        for done, part in enumerate(pool.map(_cells_chunk, chunks, [box] * len(chunks)), 1):
            result = part if result is None else merged(result, part)
            if bar is not None:
                bar(done, len(chunks))
    seconds = time.perf_counter() - started
    if result is None:
        raise UsageProblem("census --cells: no pattern to count")
    table = result.by_vertex_count()
    cospherical = sum(shapes for size, (shapes, _) in table.items() if size > 4)
    if args.output:
        lines = ["vertices,count,shape"] + [
            f"{len(shape)},{count},\"{' '.join('/'.join(map(str, p)) for p in shape)}\""
            for shape, count in result.shapes.items()]
        write_lines_atomic(args.output, lines, overwrite=args.force)
    if args.json:
        print_json({"patterns": result.patterns, "tetrahedra": result.tetrahedra,
                    "cells": result.cells, "shapes": len(result.shapes),
                    "cospherical_shapes": cospherical,
                    "by_vertices": {str(k): {"shapes": v[0], "cells": v[1]}
                                    for k, v in table.items()},
                    "cells_per_pattern": {str(k): v
                                          for k, v in result.cells_per_pattern.items()},
                    "seconds": round(seconds, 3), "output": args.output})
        return EXIT_OK
    print(f"polyhedral cells of {result.patterns:,} patterns on {box.describe()}: "
          f"{result.tetrahedra:,} tetrahedra grouped into {result.cells:,} cells, "
          f"{len(result.shapes)} distinct shapes ({cospherical} of five or more vertices)")
    print("  vertices  shapes       cells")
    for size, (shapes, cells) in table.items():
        print(f"  {size:8d}  {shapes:6d}  {cells:10,d}")
    if args.output:
        print(f"wrote {args.output}")
    return EXIT_OK


def command_census(args: argparse.Namespace) -> int:
    """Run the census of the chosen patterns, write the rows, print the summary."""
    from geomexact.mesh3d.cuboid.census_runs import CensusJob, parse_patterns, run_census

    box = shape_box(args)
    patterns = parse_patterns(args.patterns)
    if args.cells:
        return command_cells(args, box, list(patterns))
    outputs: list[Path] = []
    pyarrow = None
    if args.output:
        if Path(args.output).suffix.lower() != ".csv":
            raise UsageProblem(
                f"{args.output}: census -o writes CSV rows to a .csv file (and the same rows "
                "as Parquet beside it when pyarrow is installed); give a name ending in .csv")
        outputs.append(Path(args.output))
        pyarrow = None if args.no_parquet else _pyarrow()
        if pyarrow is not None:
            outputs.append(Path(args.output).with_suffix(".parquet"))
        for path in outputs:
            if path.exists() and not args.force:
                raise OverwriteError(str(path))
    job = CensusJob(box, args.order, args.template, args.improve, args.allow_boundary_flips,
                    args.engine)
    bar = progress_bar(args, f"census {box.describe()} {args.order}")
    started = time.perf_counter()
    rows = run_census(patterns, job, workers=args.workers, dask_address=args.dask,
                      chunk_size=args.chunk_size, on_progress=bar)
    seconds = time.perf_counter() - started
    if args.output:
        write_lines_atomic(outputs[0], csv_lines(rows), overwrite=args.force)
        if pyarrow is not None:
            write_parquet(outputs[1], rows, pyarrow)
    summaries = summarize(rows)
    valid = all(s.valid == s.patterns for s in summaries)
    if args.json:
        print_json({
            "patterns": len(rows),
            "engine": job.resolved_engine(),
            "workers": "dask" if args.dask else args.workers,
            "seconds": round(seconds, 3),
            "rate": round(len(rows) / seconds, 1) if seconds > 0 else None,
            "summaries": [s.report() for s in summaries],
            "written": [str(path) for path in outputs],
        })
    else:
        for summary in summaries:
            print("\n".join(summary_lines(summary, seconds)))
        for path in outputs:
            print(f"wrote {path}")
    return EXIT_OK if valid else EXIT_FAILED


def add_parser(commands: Subcommands) -> None:
    """Add the ``census`` command."""
    census = add_command(commands, "census", command_census)
    add_cuboid_options(census)
    census.add_argument("--patterns", default="all", metavar="all|A-B|N,M,...",
                        help="which patterns: all (1..262143, the default), A-B "
                        "(inclusive) or a list")
    census.add_argument("--workers", type=positive_int, metavar="N",
                        help="local worker processes (default: every core)")
    census.add_argument("--dask", metavar="ADDRESS",
                        help="run on the Dask cluster at ADDRESS (tcp://host:port; needs "
                        "the 'cluster' extra)")
    add_engine_option(census, ("auto", "compiled", "reference"),
                      "compiled kernel or exact reference (auto: the kernel where it applies)")
    census.add_argument("--chunk-size", type=positive_int, metavar="N",
                        help="patterns per task (default: a few tasks per worker)")
    add_output_option(census, "write one CSV row per pattern (and OUT.parquet when pyarrow "
                      "is installed)", metavar="OUT.csv")
    census.add_argument("--cells", action="store_true",
                        help="count the polyhedral Delaunay cells instead (co-spherical "
                        "tetrahedra of each pattern's Delaunay tessellation grouped, "
                        "exactly), by shape up to the cuboid's symmetries; -o writes one "
                        "CSV row per shape")
    census.add_argument("--no-parquet", action="store_true",
                        help="do not write the Parquet file beside the CSV")
    add_progress_flags(census)
    add_force_flag(census, "existing output files")
    add_json_flag(census)
