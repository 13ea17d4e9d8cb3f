"""Files at disk speed (issue 15, item 2): reading and writing the line formats, library
calls and whole ``convert`` commands, against meshio in the same run.

Usage::

    .venv/bin/python benchmarks/bench_io.py [--repeat 3] [--json] [--keep DIR]

Inputs, made once by geomexact itself in a temporary directory (or ``--keep DIR``):

* ``square.off`` refined by Lepp-bisection to max area 1e-5 (``geomexact refine``):
  66,049 vertices, 131,072 triangles, written as ``big.off`` and ``big.ele`` (+ ``.node``,
  ``.neigh``); coordinates are dyadic (``0.001953125`` …);
* the octree mesh of ``geomexact octree --refine-sphere 0.5 0.5 0.5 0.3 --surface
  --level 6``: 28,177 vertices, 139,128 tetrahedra (TetGen ``tet.ele``, ``.node``,
  ``.face``).

Times are CPU seconds (user + system; of the child for a command), the best of
``--repeat``: on a shared machine wall time measures the neighbours.  Library rows
(``io.read`` / ``io.write``, in this process) are
printed beside meshio reading and writing the same file where meshio has the format (OFF
and TetGen; it has no Triangle ``.ele``/``.node`` reader); the ratio is geomexact / meshio
(meshio reads doubles, geomexact exact rationals and builds a checked persistent mesh).
Command rows run ``geomexact convert IN OUT --force`` and ``meshio convert IN OUT`` as
fresh processes (start-up included).
"""

from __future__ import annotations

import argparse
import gc
import json
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

PYTHON = sys.executable
GEOMEXACT = [PYTHON, "-m", "geomexact"]
MESHIO = [str(Path(PYTHON).parent / "meshio")]
SQUARE_OFF = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n"


def _run(command: list[str], cwd: Path) -> float:
    """The CPU time (user + system) of the command, a fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(command, cwd=cwd, check=True, capture_output=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _make_inputs(directory: Path) -> None:
    if not (directory / "big.off").exists():
        (directory / "square.off").write_text(SQUARE_OFF)
        _run([*GEOMEXACT, "refine", "square.off", "--max-area", "0.00001", "--method",
              "bisection", "-o", "big.off"], directory)
        _run([*GEOMEXACT, "convert", "big.off", "big.ele"], directory)
    if not (directory / "tet.ele").exists():
        _run([*GEOMEXACT, "octree", "--refine-sphere", "0.5", "0.5", "0.5", "0.3",
              "--surface", "--level", "6", "-o", "tet.ele"], directory)


def _best(action: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        gc.collect()
        began = time.process_time()
        action()
        times.append(time.process_time() - began)
    return min(times)


def _clear(directory: Path, stem: str) -> None:
    for path in directory.glob(f"{stem}.*"):
        path.unlink()


def library_rows(directory: Path, repeat: int) -> list[dict[str, Any]]:
    import meshio

    from geomexact import io

    mesh2 = io.read(directory / "big.off")
    mesh3 = io.read(directory / "tet.ele")
    peer2 = meshio.read(directory / "big.off")
    peer3 = meshio.read(directory / "tet.ele")
    out = directory / "out"
    out.mkdir(exist_ok=True)

    def write(name: str, value: Any) -> Callable[[], object]:
        def action() -> object:
            _clear(out, name.split(".")[0])
            return io.write(out / name, value)
        return action

    def peer_write(name: str, value: Any, file_format: str) -> Callable[[], object]:
        def action() -> object:
            _clear(out, name.split(".")[0])
            return meshio.write(out / name, value, file_format=file_format)
        return action

    rows = [
        ("read big.off (131,072 triangles)", lambda: io.read(directory / "big.off"),
         lambda: meshio.read(directory / "big.off")),
        ("write big.off", write("g.off", mesh2), peer_write("p.off", peer2, "off")),
        ("read big.ele + .node + .neigh", lambda: io.read(directory / "big.ele"), None),
        ("write big.ele + .node + .neigh", write("g.ele", mesh2), None),
        ("read tet.ele + .node + .face (139,128 tetrahedra)",
         lambda: io.read(directory / "tet.ele"), lambda: meshio.read(directory / "tet.ele")),
        ("write tet.ele + .node + .face", write("t.ele", mesh3),
         peer_write("q.ele", peer3, "tetgen")),
    ]
    results = []
    for name, ours, peer in rows:
        ours_time = _best(ours, repeat)
        peer_time = _best(peer, repeat) if peer is not None else None
        results.append({"row": name, "geomexact": ours_time, "meshio": peer_time})
    return results


def command_rows(directory: Path, repeat: int) -> list[dict[str, Any]]:
    rows = [
        ("convert big.off big2.off", ["big.off", "c.off"], ["big.off", "m.off"]),
        ("convert big.off big2.ele", ["big.off", "c.ele"], None),
        ("convert big.ele big2.off", ["big.ele", "d.off"], None),
        ("convert tet.ele tet2.ele", ["tet.ele", "c3.ele"], ["tet.ele", "m3.ele"]),
    ]
    results = []
    for name, ours, peer in rows:
        ours_time = min(_run([*GEOMEXACT, "convert", *ours, "--force"], directory)
                        for _ in range(repeat))
        peer_time = (min(_run([*MESHIO, "convert", *peer], directory) for _ in range(repeat))
                     if peer is not None else None)
        results.append({"row": f"geomexact {name}", "geomexact": ours_time,
                        "meshio": peer_time})
    return results


def _print(title: str, rows: list[dict[str, Any]]) -> None:
    print(f"\n{title}")
    print(f"{'':52s} {'geomexact':>10s} {'meshio':>10s} {'ratio':>7s}")
    for row in rows:
        peer = row["meshio"]
        ratio = f"{row['geomexact'] / peer:6.2f}x" if peer else "     —"
        peer_text = f"{peer:9.3f}s" if peer else "         —"
        print(f"{row['row']:52s} {row['geomexact']:9.3f}s {peer_text} {ratio}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--keep", type=Path, help="make (or reuse) the inputs here")
    args = parser.parse_args()
    directory = args.keep or Path(tempfile.mkdtemp(prefix="bench_io."))
    directory.mkdir(parents=True, exist_ok=True)
    try:
        _make_inputs(directory)
        library = library_rows(directory, args.repeat)
        commands = command_rows(directory, args.repeat)
    finally:
        if args.keep is None:
            shutil.rmtree(directory, ignore_errors=True)
    if args.json:
        print(json.dumps({"library": library, "commands": commands}, indent=2))
        return
    _print(f"library calls, CPU seconds (best of {args.repeat})", library)
    _print(f"whole commands, fresh processes, CPU seconds (best of {args.repeat})", commands)


if __name__ == "__main__":
    main()
