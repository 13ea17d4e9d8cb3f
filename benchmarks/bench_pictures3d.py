"""Pictures and the 3D page of a large tetrahedral mesh: a grid of cubes cut into six
tetrahedra each (``tests/helpers/mesh3d_cases.py``), 32 × 32 × 33 cubes = 202,752
tetrahedra by default.

Usage::

    .venv/bin/python benchmarks/bench_pictures3d.py [--cubes 32 32 33] [--out DIR] [--json]

Times, in seconds: building the mesh (not part of drawing), ``plot_mesh3`` to PNG without
a clip, with a clip, with a clip and radius-ratio colours, and ``viewer_html_3d``.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from helpers.mesh3d_cases import cube_grid

from geomexact.viz.pictures3d import plot_mesh3
from geomexact.viz.scene3d import clip_plane, viewer_html_3d


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cubes", type=int, nargs=3, default=(32, 32, 33))
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    out = args.out or Path(tempfile.mkdtemp(prefix="bench3d-"))
    out.mkdir(parents=True, exist_ok=True)
    nx, ny, nz = args.cubes
    times: dict[str, float] = {}
    begun = time.perf_counter()
    mesh = cube_grid(nx, ny, nz)
    times["build mesh"] = time.perf_counter() - begun
    cases = {
        "picture": {},
        "picture, clip": {"clip": clip_plane("y", ny // 2)},
        "picture, clip, quality": {"clip": clip_plane("z", f"{nz}/3"), "colour": "quality"},
    }
    for index, (name, options) in enumerate(cases.items()):
        begun = time.perf_counter()
        plot_mesh3(mesh, out / f"grid-{index}.png", overwrite=True, **options)
        times[name] = time.perf_counter() - begun
    begun = time.perf_counter()
    page = viewer_html_3d(mesh, clip=clip_plane("x", nx // 2))
    times["page"] = time.perf_counter() - begun
    (out / "grid.html").write_text(page, encoding="utf-8")
    report = {"tetrahedra": mesh.tetrahedron_count, "vertices": mesh.vertex_count,
              "page_bytes": len(page.encode()), "seconds": times, "out": str(out)}
    if args.json:
        print(json.dumps(report, indent=2))
    else:
        print(f"{mesh.tetrahedron_count:,} tetrahedra, {mesh.vertex_count:,} vertices")
        for name, seconds in times.items():
            print(f"  {name:<24} {seconds:6.2f} s")
        print(f"  page size {len(page.encode()) / 1e6:.1f} MB; files in {out}")


if __name__ == "__main__":
    main()
