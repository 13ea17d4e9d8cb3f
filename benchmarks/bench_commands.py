"""Whole commands against their peer end to end, in the same run: what a user waits for.

Usage::

    .venv/bin/python benchmarks/bench_commands.py [--only refine-1e-5 ...] [--repeat 3]
        [--repeat-large 1] [--json]

Rows:

* ``refine-1e-5`` / ``refine-1e-6``: ``geomexact refine square.off --max-area 0.00001
  --method bisection -o out.off --json`` (square.off: the unit square as two triangles),
  a fresh process from start to exit, against the peer end to end: a fresh Python process
  that imports Triangle's Python binding ``triangle`` (the ``bench`` extra), reads the same
  OFF file, triangulates it with ``pa<area>`` (its boundary edges as segments) and writes
  the result as ``.node`` / ``.ele`` files.  The ``seconds`` geomexact reports (the
  algorithm alone) is printed beside it, so what the command adds to its kernel shows.
  Peak memory is each child's maximum resident set size.
* ``import``: ``python -c "import geomexact"``; ``help``: ``geomexact --help``;
  ``info``: ``geomexact info square.off`` (start-up of a command on a tiny file).
* ``triangulate-1e4``: ``geomexact triangulate points.node -o points.off --json`` on 10^4
  seeded random points of the unit square (decimal coordinates, written back exactly).
* ``refine-pikachu`` / ``info-pikachu`` (issue 25): ``geomexact refine
  pikachu_triangle.off --min-angle 30 -o x.off`` (a real 531-triangle mesh,
  ``../shared/data/polylla-refinement``; skipped when absent) and ``geomexact info`` on
  it: what a user scripting many small runs waits for (targets 0.25 s and 0.15 s wall).

Each measurement is a fresh child process, the best of ``--repeat`` runs
(``--repeat-large`` for 1e-6); wall time and CPU time (user + system, from the child's own
``wait4`` resource usage) are both reported, because this machine is shared and wall times
are noisy: ratios are taken on CPU time.

Targets (issue 15): the triangulate command on 10^4 points in at most 0.6 s; the refine
command at 1e-5 and 1e-6 within 3x the peer end to end,
peak memory at 1e-6 at most 1 GB; ``import geomexact`` at most 0.15 s.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"
RATIO_TARGET = 3.0
MEMORY_TARGET_BYTES = 1024**3
IMPORT_TARGET_SECONDS = 0.15
PIKACHU = ROOT.parent / "shared" / "data" / "polylla-refinement" / "pikachu_triangle.off"
SMALL_REFINE_TARGET_SECONDS = 0.25
SMALL_INFO_TARGET_SECONDS = 0.15

PEER = r'''
import sys
import numpy as np
import triangle

source, area, stem = sys.argv[1], sys.argv[2], sys.argv[3]
words = open(source).read().split()
assert words[0] == "OFF"
nv, nf = int(words[1]), int(words[2])
at = 4
vertices = np.array(words[at:at + 3 * nv], dtype=float).reshape(nv, 3)[:, :2]
at += 3 * nv
faces = []
for _ in range(nf):
    size = int(words[at])
    faces.append([int(w) for w in words[at + 1:at + 1 + size]])
    at += 1 + size
directed = {(f[i], f[(i + 1) % len(f)]) for f in faces for i in range(len(f))}
segments = sorted((u, v) for u, v in directed if (v, u) not in directed)
out = triangle.triangulate({"vertices": vertices, "segments": np.array(segments)},
                           "pa" + area)
points, cells = out["vertices"], out["triangles"]
with open(stem + ".node", "w") as node:
    node.write(f"{len(points)} 2 0 0\n")
    np.savetxt(node, np.column_stack([np.arange(1, len(points) + 1), points]),
               fmt=["%d", "%.17g", "%.17g"])
with open(stem + ".ele", "w") as ele:
    ele.write(f"{len(cells)} 3 0\n")
    np.savetxt(ele, np.column_stack([np.arange(1, len(cells) + 1), cells + 1]), fmt="%d")
print(len(cells))
'''


def child(argv: list[str], cwd: Path) -> dict[str, Any]:
    """Run ``argv`` in ``cwd``; its wall time, CPU time, peak RSS and stdout."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(ROOT), *([env["PYTHONPATH"]] if env.get("PYTHONPATH") else [])])
    started = time.perf_counter()
    process = subprocess.Popen(argv, cwd=cwd, env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE)
    assert process.stdout is not None and process.stderr is not None
    out, err = process.stdout.read(), process.stderr.read()  # small outputs only
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - started
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise RuntimeError(f"{argv} failed ({process.returncode}): {err.decode()[-2000:]}")
    return {"wall": wall, "cpu": usage.ru_utime + usage.ru_stime,
            "peak_bytes": usage.ru_maxrss * 1024, "stdout": out.decode()}


def best(argv: list[str], cwd: Path, repeat: int) -> dict[str, Any]:
    runs = [child(argv, cwd) for _ in range(repeat)]
    chosen = min(runs, key=lambda run: run["cpu"])
    chosen["wall"] = min(run["wall"] for run in runs)
    chosen["peak_bytes"] = max(run["peak_bytes"] for run in runs)
    return chosen


def refine_row(name: str, area: str, work: Path, repeat: int) -> dict[str, Any]:
    ours = best([sys.executable, "-m", "geomexact", "refine", "square.off", "--max-area",
                 area, "--method", "bisection", "-o", "out.off", "--json", "--force"],
                work, repeat)
    report = json.loads(ours.pop("stdout"))
    peer = best([sys.executable, "-c", PEER, "square.off", area, "peer"], work, repeat)
    peer_triangles = int(peer.pop("stdout"))
    return {
        "row": name, "geomexact": ours, "peer": peer,
        "algorithm_seconds": report["seconds"], "triangles": report["triangles"],
        "peer_triangles": peer_triangles,
        "ratio_cpu": ours["cpu"] / peer["cpu"], "ratio_wall": ours["wall"] / peer["wall"],
        "target": RATIO_TARGET,
    }


TRIANGULATE_TARGET_SECONDS = 0.6
TRIANGULATE_POINTS = 10_000


def points_node(path: Path, count: int) -> None:
    """``count`` seeded random points of the unit square as a Triangle ``.node`` file
    (each coordinate the shortest text of a random double)."""
    generator = random.Random(15)
    rows = [f"{count} 2 0 0"]
    rows += [f"{index} {generator.random()!r} {generator.random()!r}"
             for index in range(count)]
    path.write_text("\n".join(rows) + "\n")


def triangulate_row(name: str, work: Path, repeat: int) -> dict[str, Any]:
    """``geomexact triangulate points.node -o out.off --json``: a fresh process from start
    to exit (target: at most 0.6 s wall for 10^4 points)."""
    points_node(work / "points.node", TRIANGULATE_POINTS)
    ours = best([sys.executable, "-m", "geomexact", "triangulate", "points.node", "-o",
                 "points.off", "--json", "--force"], work, repeat)
    report = json.loads(ours.pop("stdout"))
    return {"row": name, "geomexact": ours, "algorithm_seconds": report["seconds"],
            "triangles": report["triangles"], "target": TRIANGULATE_TARGET_SECONDS}


def start_row(name: str, argv: list[str], work: Path, repeat: int) -> dict[str, Any]:
    measured = best([sys.executable, *argv], work, repeat)
    measured.pop("stdout")
    return {"row": name, "geomexact": measured}


def compile_bytecode() -> None:
    """Compile the package's bytecode first, as ``pip install`` does: with
    ``PYTHONDONTWRITEBYTECODE`` set (as on some machines) an editable install would
    otherwise compile every module again in every child, which no installed user pays."""
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(ROOT / "geomexact")],
                   check=True, stdout=subprocess.DEVNULL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="*", default=None,
                        choices=("refine-1e-5", "refine-1e-6", "import", "help", "info",
                                 "triangulate-1e4", "refine-pikachu", "info-pikachu"))
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--repeat-large", type=int, default=1)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    chosen = args.only or ["import", "help", "info", "triangulate-1e4", "refine-1e-5",
                           "refine-1e-6", "refine-pikachu", "info-pikachu"]
    compile_bytecode()
    rows = []
    with tempfile.TemporaryDirectory() as directory:
        work = Path(directory)
        (work / "square.off").write_text(SQUARE_OFF)
        for name in chosen:
            if name == "import":
                row = start_row(name, ["-c", "import geomexact"], work, max(args.repeat, 5))
                row["target"] = IMPORT_TARGET_SECONDS
            elif name == "help":
                row = start_row(name, ["-m", "geomexact", "--help"], work,
                                max(args.repeat, 5))
            elif name == "triangulate-1e4":
                row = triangulate_row(name, work, max(args.repeat, 3))
            elif name == "info":
                row = start_row(name, ["-m", "geomexact", "info", "square.off"], work,
                                max(args.repeat, 5))
            elif name in ("refine-pikachu", "info-pikachu"):
                if not PIKACHU.exists():
                    print(f"{name:<15} skipped: {PIKACHU} absent", flush=True)
                    continue
                (work / "pikachu.off").write_bytes(PIKACHU.read_bytes())
                command = (["refine", "pikachu.off", "--min-angle", "30", "-o", "x.off",
                            "--force"] if name == "refine-pikachu" else ["info", "pikachu.off"])
                row = start_row(name, ["-m", "geomexact", *command], work,
                                max(args.repeat, 5))
                row["target"] = (SMALL_REFINE_TARGET_SECONDS if name == "refine-pikachu"
                                 else SMALL_INFO_TARGET_SECONDS)
            else:
                area = "0.00001" if name == "refine-1e-5" else "0.000001"
                repeat = args.repeat if name == "refine-1e-5" else args.repeat_large
                row = refine_row(name, area, work, repeat)
                if name == "refine-1e-6":
                    row["memory_target_bytes"] = MEMORY_TARGET_BYTES
            rows.append(row)
            if not args.json:
                show(row)
    if args.json:
        print(json.dumps({"machine": platform.platform(), "python": sys.version.split()[0],
                          "rows": rows}, indent=2))


def show(row: dict[str, Any]) -> None:
    ours = row["geomexact"]
    mb = ours["peak_bytes"] / 1024**2
    if "peer" not in row:
        target = f"  (target <= {row['target']} s)" if "target" in row else ""
        print(f"{row['row']:<15} wall {ours['wall']:.3f} s  cpu {ours['cpu']:.3f} s  "
              f"peak {mb:.0f} MB{target}", flush=True)
        return
    peer = row["peer"]
    print(f"{row['row']:<12} geomexact wall {ours['wall']:.2f} s cpu {ours['cpu']:.2f} s "
          f"(algorithm {row['algorithm_seconds']:.2f} s) peak {mb:.0f} MB, "
          f"{row['triangles']} triangles", flush=True)
    print(f"{'':<12} peer      wall {peer['wall']:.2f} s cpu {peer['cpu']:.2f} s "
          f"peak {peer['peak_bytes'] / 1024**2:.0f} MB, {row['peer_triangles']} triangles",
          flush=True)
    memory = ""
    if "memory_target_bytes" in row:
        memory = f", memory target <= {row['memory_target_bytes'] / 1024**3:.0f} GB"
    print(f"{'':<12} ratio cpu {row['ratio_cpu']:.2f}x wall {row['ratio_wall']:.2f}x "
          f"(target <= {row['target']:.0f}x{memory})", flush=True)


if __name__ == "__main__":
    main()
