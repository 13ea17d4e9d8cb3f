"""The performance report: run every benchmark of ``benchmarks/`` with its peers and write
``docs/performance.md`` (tables of ratios, the machine) and its plots
(``docs/images/performance/``).

Usage::

    .venv/bin/python -m benchmarks [--quick] [--only NAME ...] [--out docs/performance.md]
        [--images docs/images/performance] [--timeout SECONDS]

Each benchmark runs as its own script (``benchmarks/bench_*.py``, with ``--json``; the
Polylla experiment prints a table), in a child process, in the same run as its peers
(Triangle, ``sect``, ``shewchuk``, Gmsh, TetGen, fTetWild: the ``bench`` extra; a peer that
is not installed is skipped by its benchmark, and the page says which were present).  The Lepp
sweep (triangle count against max area, time against triangle count, geomexact against
Triangle) is run here, in a child process too.  ``--quick`` runs small sizes (a smoke run
of a minute or two); the default runs each benchmark's own default workloads (many minutes).
Read the ratios, not the absolute times: the page notes the machine and its load.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import importlib.metadata
import json
import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
PEERS = ("triangle", "shewchuk", "sect", "gmsh", "tetgen", "pytetwild")
"""The peers' distribution names (the ``bench`` extra)."""


@dataclass(frozen=True)
class Benchmark:
    """One benchmark script and its arguments for a quick and a full run."""

    name: str
    script: str
    title: str
    quick: tuple[str, ...]
    full: tuple[str, ...] = ()
    json: bool = True
    peers: tuple[str, ...] = ()


BENCHMARKS: tuple[Benchmark, ...] = (
    Benchmark("predicates", "bench_predicates.py", "Predicate throughput",
              ("--n", "500", "--repeat", "3"), (), peers=("shewchuk",)),
    Benchmark("delaunay", "bench_delaunay.py", "Delaunay construction",
              ("--sizes", "1000", "4000", "16000", "--repeat", "1", "--sect-max", "1000"),
              ("--sizes", "1000", "10000", "100000"), peers=("triangle", "sect")),
    Benchmark("refine", "bench_refine.py", "Lepp refinement against Triangle",
              ("--only", "superior-30", "--repeat", "1"), (),
              peers=("triangle",)),
    Benchmark("replay", "bench_replay.py", "Trace replay against the run",
              ("--only", "square-1e-5", "--repeat", "1"), ()),
    Benchmark("polylla", "polylla_experiment.py", "Polylla and its convex decomposition",
              ("--sizes", "500", "2000"), (), json=False, peers=("triangle",)),
    Benchmark("census", "bench_census.py", "Cuboid census",
              ("--sample", "500", "--reference", "20", "--dask-patterns", "1-20000",
               "--repeat", "1"), ()),
    Benchmark("octree", "bench_octree.py", "Octree meshing against Gmsh and TetGen",
              ("--variants", "surface", "--peers", "gmsh-hxt"), (),
              peers=("gmsh", "tetgen")),
    Benchmark("domain", "bench_domain.py",
              "Meshing real surfaces against Gmsh, TetGen and fTetWild",
              ("--surfaces", "spot", "--levels", "4", "5", "--peers", "gmsh-hxt"), (),
              peers=("gmsh", "tetgen", "pytetwild")),
    Benchmark("pictures3d", "bench_pictures3d.py", "Pictures of a tetrahedral mesh",
              ("--cubes", "8", "8", "8"), ()),
    Benchmark("commands", "bench_commands.py",
              "Whole commands against Triangle end to end (start, read, mesh, write)",
              ("--only", "import", "help", "info", "refine-1e-5", "--repeat", "1"), (),
              peers=("triangle",)),
    Benchmark("io", "bench_io.py", "Reading and writing mesh files", ("--repeat", "1"), ()),
)
"""Every benchmark, in the order of the page."""

SWEEP_QUICK = ("0.01", "0.003", "0.001", "0.0003", "0.0001")
SWEEP_FULL = (*SWEEP_QUICK, "0.00003", "0.00001", "0.000003")
"""Max areas of the Lepp sweep (unit square)."""


@dataclass
class Outcome:
    """What one child process did."""

    name: str
    command: list[str]
    seconds: float
    returncode: int | None
    stdout: str
    stderr: str
    data: Any = None
    notes: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.returncode == 0


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(ROOT), env.get("PYTHONPATH")) if p)
    return env


def run_child(name: str, command: list[str], timeout: float) -> Outcome:
    """Run ``command`` from the repository's root; time it; parse its JSON when it ends
    with one object."""
    began = time.perf_counter()
    try:
        done = subprocess.run(command, cwd=ROOT, env=_environment(), capture_output=True,
                              text=True, timeout=timeout, check=False)
        returncode: int | None = done.returncode
        stdout, stderr = done.stdout, done.stderr
    except subprocess.TimeoutExpired as expired:
        returncode = None
        stdout = expired.stdout.decode() if isinstance(expired.stdout, bytes) else ""
        stderr = f"timed out after {timeout:.0f} s"
    outcome = Outcome(name, command, time.perf_counter() - began, returncode, stdout, stderr)
    text = stdout.strip()
    if returncode == 0 and text.endswith("}"):
        start = text.find("{")
        try:
            outcome.data = json.loads(text[start:])
        except ValueError:
            outcome.notes.append("its output was not one JSON object")
    return outcome


def run_benchmark(bench: Benchmark, quick: bool, timeout: float) -> Outcome:
    """Run one benchmark script with its quick or full arguments."""
    args = list(bench.quick if quick else bench.full)
    if bench.json:
        args.append("--json")
    command = [sys.executable, str(HERE / bench.script), *args]
    return run_child(bench.name, command, timeout)


# --- the Lepp sweep (run in a child: python -m benchmarks --sweep AREAS) ----------------------


def sweep(areas: Sequence[str]) -> dict[str, Any]:
    """Refine the unit square to each max area by Lepp bisection (the default engine), and
    triangulate it by Triangle (``pa``, the same job) when installed; time both."""
    from geomexact import MaxArea, mesh_from_triangles, refine

    square = mesh_from_triangles([("0", "0"), ("1", "0"), ("1", "1"), ("0", "1")],
                                 [(0, 1, 2), (0, 2, 3)])
    try:
        import triangle  # type: ignore[import-untyped]
    except ImportError:
        triangle = None
    rows = []
    for area in areas:
        began = time.perf_counter()
        result = refine(square, MaxArea(area), method="bisection")
        row: dict[str, Any] = {"max_area": float(area), "geomexact_seconds":
                               time.perf_counter() - began,
                               "geomexact_triangles": result.mesh.triangle_count}
        if triangle is not None:
            pslg = {"vertices": [[0, 0], [1, 0], [1, 1], [0, 1]],
                    "segments": [[0, 1], [1, 2], [2, 3], [3, 0]]}
            began = time.perf_counter()
            out = triangle.triangulate(pslg, f"pQa{area}")
            row["triangle_seconds"] = time.perf_counter() - began
            row["triangle_triangles"] = len(out["triangles"])
        rows.append(row)
    return {"rows": rows, "triangle": triangle is not None}


# --- the machine --------------------------------------------------------------------------


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def _version(distribution: str) -> str | None:
    try:
        return importlib.metadata.version(distribution)
    except importlib.metadata.PackageNotFoundError:
        return None


def machine() -> dict[str, Any]:
    """The machine, the interpreter and the versions of geomexact, its kernels and peers."""
    from geomexact.cli.parser import version_text

    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    return {
        "cpu": _cpu_model(), "cores": os.cpu_count(), "load": load,
        "system": f"{platform.system()} {platform.release()}",
        "python": f"{platform.python_implementation()} {platform.python_version()}",
        "geomexact": version_text().splitlines(),
        "versions": {name: _version(name) for name in
                     ("gmpy2", "numpy", "immutables", "matplotlib", *PEERS)},
    }


# --- the page -----------------------------------------------------------------------------


def _cell(value: Any) -> str:
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        if value != 0 and (abs(value) >= 1e5 or abs(value) < 1e-3):
            return f"{value:.3g}"
        return f"{value:,.3f}".rstrip("0").rstrip(".")
    if isinstance(value, int):
        return f"{value:,}"
    if value is None:
        return "—"
    if isinstance(value, list) and all(not isinstance(v, dict | list) for v in value):
        return ", ".join(_cell(v) for v in value)
    return str(value).replace("|", "\\|").replace("\n", " ")


def table(rows: Sequence[dict[str, Any]], columns: Sequence[str] | None = None) -> list[str]:
    """A Markdown table of ``rows`` (their scalar keys, in first-seen order)."""
    if not rows:
        return []
    if columns is None:
        columns = []
        for row in rows:
            columns += [k for k, v in row.items()
                        if k not in columns and not isinstance(v, dict)
                        and not (isinstance(v, list) and v and isinstance(v[0], dict | list))]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(_cell(row.get(c)) for c in columns) + " |" for row in rows]
    return lines


def flatten(value: Any, prefix: str = "") -> Iterable[tuple[str, Any]]:
    """The scalar leaves of a JSON value as (dotted key, value)."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from flatten(item, f"{prefix}.{key}" if prefix else str(key))
    elif isinstance(value, list) and value and isinstance(value[0], dict | list):
        for index, item in enumerate(value):
            yield from flatten(item, f"{prefix}[{index}]")
    else:
        yield prefix, value


LONG_KEYS = frozenset({"argv", "command", "digest"})
"""Keys left out of the generic tables (long texts)."""


def generic_tables(data: Any) -> list[str]:
    """Tables of a benchmark's JSON: each list of objects as a table, the other scalars
    (ratios first) as a key/value table."""
    lines: list[str] = []
    scalars: list[tuple[str, Any]] = []
    if not isinstance(data, dict):
        return ["```text", json.dumps(data, indent=1)[:4000], "```"]
    for key, value in data.items():
        if isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            # a nested object becomes dotted columns ("geomexact.cpu", "peer.peak_bytes")
            rows = [{k: v for k, v in flatten(row) if k.split(".")[0] not in LONG_KEYS}
                    for row in value]
            lines += [f"**{key}**", "", *table(rows), ""]
        else:
            scalars += list(flatten(value, key))
    skip = {"geomexact", "python", "machine"}
    scalars = [(k, v) for k, v in scalars if k not in skip]
    scalars.sort(key=lambda kv: "ratio" not in kv[0])
    if scalars:
        lines += [*table([{"measure": k, "value": v} for k, v in scalars[:80]]), ""]
    return lines


def _delaunay_tables(data: dict[str, Any]) -> list[str]:
    rows = []
    for row in data.get("rows", []):
        out = {k: row.get(k) for k in ("workload", "n", "triangles", "trace_steps")}
        out["geomexact (s)"] = row.get("geomexact")
        for peer in ("triangle", "sect"):
            if isinstance(row.get(peer), int | float):
                out[f"{peer} (s)"] = row[peer]
                out[f"geomexact / {peer}"] = row["geomexact"] / row[peer]
        rows.append(out)
    lines = [*table(rows), ""]
    if data.get("targets"):
        lines += ["Targets: " + "; ".join(_cell(t) for t in data["targets"]), ""]
    return lines


def _refine_tables(data: dict[str, Any]) -> list[str]:
    runs = data.get("runs", [])
    triangle_wall: dict[str, float] = {}
    for run in runs:
        if run.get("program", "").startswith("triangle") and "wall" in run:
            triangle_wall.setdefault(run["workload"], run["wall"])
    rows = []
    for run in runs:
        row = {"workload": run.get("workload"), "program": run.get("program"),
               "wall (s)": run.get("wall"), "cpu (s)": run.get("cpu"),
               "triangles": run.get("triangles"),
               "peak MB": (run["max_rss_bytes"] / 1024**2 if "max_rss_bytes" in run
                           else None),
               "min angle": run.get("min_angle"), "status": run.get("status")}
        if run.get("workload") in triangle_wall and "wall" in run:
            row["/ Triangle's first"] = run["wall"] / triangle_wall[run["workload"]]
        rows.append(row)
    lines = [*table(rows), ""]
    if data.get("verdicts"):
        lines += ["```text", *data["verdicts"], "```", ""]
    return lines


FORMATTERS: dict[str, Callable[[dict[str, Any]], list[str]]] = {
    "delaunay": _delaunay_tables,
    "refine": _refine_tables,
}


def plots(images: Path, outcomes: dict[str, Outcome], sweep_data: dict[str, Any] | None,
          ) -> list[tuple[str, str]]:
    """Draw the plots into ``images``; return (file name, caption) of each drawn."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
    except ImportError:
        return []
    images.mkdir(parents=True, exist_ok=True)
    drawn = []
    if sweep_data and sweep_data.get("rows"):
        rows = sweep_data["rows"]
        fig = Figure(figsize=(10, 4), dpi=100)
        FigureCanvasAgg(fig)
        left, right = fig.add_subplot(1, 2, 1), fig.add_subplot(1, 2, 2)
        areas = [r["max_area"] for r in rows]
        left.loglog(areas, [r["geomexact_triangles"] for r in rows], "o-",
                    label="geomexact Lepp bisection")
        right.loglog([r["geomexact_triangles"] for r in rows],
                     [r["geomexact_seconds"] for r in rows], "o-",
                     label="geomexact Lepp bisection")
        if sweep_data.get("triangle"):
            left.loglog(areas, [r["triangle_triangles"] for r in rows], "s--",
                        label="Triangle -pa")
            right.loglog([r["triangle_triangles"] for r in rows],
                         [r["triangle_seconds"] for r in rows], "s--", label="Triangle -pa")
        left.set_xlabel("max area")
        left.set_ylabel("triangles")
        left.invert_xaxis()
        right.set_xlabel("triangles")
        right.set_ylabel("seconds")
        for ax in (left, right):
            ax.grid(True, which="both", alpha=0.3)
            ax.legend()
        fig.suptitle("unit square refined to a max area")
        fig.tight_layout()
        fig.savefig(images / "lepp-sweep.png", metadata={"Software": None})
        drawn.append(("lepp-sweep.png", "Triangle count against max area, and time against "
                      "triangle count, unit square (the classic Lepp vs Triangle comparison)."))
    delaunay = outcomes.get("delaunay")
    if delaunay is not None and delaunay.data:
        points = [r for r in delaunay.data.get("rows", [])
                  if str(r.get("workload", "")).startswith("points-")]
        if points:
            fig = Figure(figsize=(5.5, 4), dpi=100)
            FigureCanvasAgg(fig)
            ax = fig.add_subplot(1, 1, 1)
            for peer, style in (("geomexact", "o-"), ("triangle", "s--"), ("sect", "^:")):
                found = [(r["n"], r[peer]) for r in points
                         if isinstance(r.get(peer), int | float)]
                if found:
                    ax.loglog(*zip(*found, strict=True), style, label=peer)
            ax.set_xlabel("points")
            ax.set_ylabel("seconds")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend()
            ax.set_title("Delaunay triangulation of random points")
            fig.tight_layout()
            fig.savefig(images / "delaunay-time.png", metadata={"Software": None})
            drawn.append(("delaunay-time.png", "Delaunay construction time against the "
                          "number of points (geomexact builds the snapshot and its trace)."))
    return drawn


def page(arguments: list[str], quick: bool, host: dict[str, Any], load_after: Any,
         outcomes: dict[str, Outcome], sweep_outcome: Outcome | None,
         drawn: list[tuple[str, str]], images_rel: str, total: float, now: str) -> str:
    """The Markdown of ``docs/performance.md``."""
    command = " ".join(["python -m benchmarks", *arguments])
    kind = ("quick: small sizes, a smoke run; read the shapes, not the numbers" if quick
            else "the full default workloads")
    present = [p for p in PEERS if host["versions"].get(p)]
    missing = [p for p in PEERS if not host["versions"].get(p)]
    lines = [
        "# Performance report",
        "",
        f"This page was made by `{command}` on {now}, in {total:.0f} s "
        f"({kind}).",
        "Run `python -m benchmarks` (the full run, many minutes) or `python -m benchmarks "
        "--quick` from the repository's root to make it again; every benchmark is a "
        "script of `benchmarks/` with its own `--help` (`benchmarks/README.md`).",
        "Compare **ratios** measured in the same run, not absolute times: the machine below "
        "is shared and its wall times are noisy.",
        "",
        "## The machine",
        "",
        *table([
            {"": "CPU", "value": host["cpu"]},
            {"": "cores", "value": host["cores"]},
            {"": "load average (1, 5, 15 min) before", "value": _load(host["load"])},
            {"": "load average after", "value": _load(load_after)},
            {"": "system", "value": host["system"]},
            {"": "Python", "value": host["python"]},
            *({"": "geomexact" if i == 0 else "", "value": line.strip()}
              for i, line in enumerate(host["geomexact"])),
            *({"": name, "value": version or "not installed"}
              for name, version in host["versions"].items()),
        ]),
        "",
        f"Peers present: {', '.join(present) or 'none'}"
        + (f"; missing (skipped by the benchmarks that use them; `pip install "
           f"geomexact[bench]`): {', '.join(missing)}." if missing else "."),
        "",
    ]
    lines += ["## Lepp refinement against Triangle: the sweep", ""]
    if sweep_outcome is not None and sweep_outcome.data:
        lines += [f"`python -m benchmarks --sweep {' '.join(sweep_outcome.command[4:])}`: "
                  "the unit square (two triangles) refined by Lepp bisection to each max "
                  "area (default engine), and triangulated by Triangle `pQa<area>` (the same "
                  "job), in one process.", ""]
        rows = []
        for r in sweep_outcome.data["rows"]:
            row = dict(r)
            if "triangle_seconds" in r:
                row["time ratio"] = r["geomexact_seconds"] / r["triangle_seconds"]
                row["triangle count ratio"] = (r["geomexact_triangles"]
                                               / r["triangle_triangles"])
            rows.append(row)
        lines += [*table(rows), ""]
    elif sweep_outcome is not None:
        lines += _failure(sweep_outcome)
    for name, caption in drawn:
        lines += [f"![{caption}]({images_rel}/{name})", "", caption, ""]
    for bench in BENCHMARKS:
        outcome = outcomes.get(bench.name)
        if outcome is None:
            continue
        shown = " ".join(["python", f"benchmarks/{bench.script}", *outcome.command[2:]])
        lines += [f"## {bench.title}", "", f"`{shown}` ({outcome.seconds:.0f} s"
                  + (f"; peers: {', '.join(bench.peers)}" if bench.peers else "") + ")", ""]
        if not outcome.ok:
            lines += _failure(outcome)
        elif outcome.data is not None:
            formatter = FORMATTERS.get(bench.name, generic_tables)
            lines += formatter(outcome.data)
        else:
            lines += ["```text", outcome.stdout.rstrip()[-6000:], "```", ""]
        lines += [f"*{note}*" for note in outcome.notes]
    return "\n".join(lines).rstrip() + "\n"


def _load(load: Any) -> str:
    return ", ".join(f"{x:.2f}" for x in load) if load else "—"


def _failure(outcome: Outcome) -> list[str]:
    tail = (outcome.stderr.strip().splitlines() or ["(no message)"])[-1]
    status = ("timed out" if outcome.returncode is None
              else f"failed (exit {outcome.returncode})")
    return [f"**{status}**: `{tail[:300]}`", ""]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m benchmarks",
        description="Run every benchmark of benchmarks/ with its peers and write "
                    "docs/performance.md and its plots.")
    parser.add_argument("--quick", action="store_true",
                        help="small sizes (a smoke run of a minute or two)")
    parser.add_argument("--only", nargs="+", choices=[b.name for b in BENCHMARKS],
                        metavar="NAME", help="run only these benchmarks: "
                        + ", ".join(b.name for b in BENCHMARKS))
    parser.add_argument("--no-sweep", action="store_true", help="skip the Lepp sweep")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "performance.md")
    parser.add_argument("--images", type=Path,
                        default=ROOT / "docs" / "images" / "performance")
    parser.add_argument("--timeout", type=float, default=None,
                        help="seconds per benchmark (default 600 quick, 7200 full)")
    parser.add_argument("--render", action="store_true",
                        help="only write the page again from the results.json of the last "
                             "run (in --images), running nothing")
    parser.add_argument("--sweep", nargs="+", metavar="AREA", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.sweep:
        print(json.dumps(sweep(args.sweep)))
        return 0
    if args.render:
        saved = json.loads((args.images / RESULTS).read_text(encoding="utf-8"))
        write_page(args, saved)
        return 0
    timeout = args.timeout or (600.0 if args.quick else 7200.0)
    began = time.perf_counter()
    host = machine()
    arguments = [a for a in (argv if argv is not None else sys.argv[1:])]
    sweep_outcome = None
    if not args.no_sweep:
        areas = SWEEP_QUICK if args.quick else SWEEP_FULL
        print(f"== sweep {' '.join(areas)}", flush=True)
        sweep_outcome = run_child("sweep", [sys.executable, "-m", "benchmarks", "--sweep",
                                            *areas], timeout)
    outcomes = {}
    for bench in BENCHMARKS:
        if args.only and bench.name not in args.only:
            continue
        print(f"== {bench.name}: {bench.script}", flush=True)
        outcomes[bench.name] = outcome = run_benchmark(bench, args.quick, timeout)
        print(f"   {'ok' if outcome.ok else 'FAILED'} in {outcome.seconds:.1f} s", flush=True)
    saved = {
        "arguments": arguments, "quick": args.quick, "host": host,
        "load_after": os.getloadavg() if hasattr(os, "getloadavg") else None,
        "seconds": time.perf_counter() - began,
        "when": _dt.datetime.now(_dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "sweep": asdict(sweep_outcome) if sweep_outcome else None,
        "outcomes": {name: asdict(outcome) for name, outcome in outcomes.items()},
    }
    args.images.mkdir(parents=True, exist_ok=True)
    (args.images / RESULTS).write_text(json.dumps(saved, indent=1) + "\n", encoding="utf-8")
    write_page(args, saved)
    return 0


RESULTS = "results.json"
"""The raw results of the last run (every child's command, output and parsed JSON), kept
beside the plots so that ``--render`` can write the page again."""


def write_page(args: argparse.Namespace, saved: dict[str, Any]) -> None:
    """Draw the plots and write the page from the results of a run."""
    outcomes = {name: Outcome(**value) for name, value in saved["outcomes"].items()}
    sweep_outcome = Outcome(**saved["sweep"]) if saved["sweep"] else None
    drawn = plots(args.images, outcomes, sweep_outcome.data if sweep_outcome else None)
    try:
        images_rel = os.path.relpath(args.images, args.out.parent)
    except ValueError:
        images_rel = str(args.images)
    text = page(saved["arguments"], saved["quick"], saved["host"], saved["load_after"],
                outcomes, sweep_outcome, drawn, Path(images_rel).as_posix(),
                saved["seconds"], saved["when"])
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(text, encoding="utf-8")
    print(f"wrote {args.out}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
