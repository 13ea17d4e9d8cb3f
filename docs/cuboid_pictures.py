"""Draw the cuboid partitions of ``docs/cuboid.md`` before and after Joe's flips.

For each pattern, one PNG under ``docs/images/`` with two panels: the partition as made
(``run.partition``) and the improved mesh (``run.mesh``), on the unit cube, clipped at
x = 1/2 so that the inside shows, faces coloured by their tetrahedron's radius ratio.
It prints the Markdown line ``docs/cuboid.md`` embeds for each picture.

Usage::

    .venv/bin/python docs/cuboid_pictures.py [--out docs/images] [--force]
"""

from __future__ import annotations

import argparse
from pathlib import Path

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure

from geomexact.io.files import write_bytes_atomic
from geomexact.mesh3d.cuboid.improvement import FLIP_NAMES
from geomexact.mesh3d.cuboid.partition import CuboidMesh, partition_cuboid
from geomexact.viz.pictures import figure_bytes
from geomexact.viz.pictures3d import QUALITY_MAP, draw_mesh3
from geomexact.viz.scene3d import clip_plane

PATTERNS = {
    "70688": 70688,
    "12304": 12304,
    "bits 3, 8, 12": (1 << 3) | (1 << 8) | (1 << 12),
    "262143 (every Steiner point)": 262143,
}
CLIP = clip_plane("x", "1/2")


def _flips(run: CuboidMesh) -> str:
    assert run.improvement is not None
    done = [f"{count} {name}" for name, count in zip(FLIP_NAMES, run.improvement.flips,
                                                      strict=True) if count]
    return ", ".join(done) or "no flip"


def picture(label: str, run: CuboidMesh) -> Figure:
    """The two panels of one pattern, 900 × 420 pixels."""
    fig = Figure(figsize=(9.0, 4.2), dpi=100)
    FigureCanvasAgg(fig)
    for index, (mesh, name) in enumerate(((run.partition, "partition"),
                                          (run.mesh, "after Joe's flips"))):
        ax = fig.add_axes((0.01 + 0.45 * index, 0.02, 0.44, 0.8))
        drawing = draw_mesh3(ax, mesh, clip=CLIP, colour="quality", colorbar=False)
        ax.set_title(f"{name}: {drawing.tetrahedra} tetrahedra ({drawing.kept} with "
                     f"x ≤ 1/2 shown)", fontsize=9)
    bar = fig.add_axes((0.92, 0.12, 0.018, 0.6))
    fig.colorbar(ScalarMappable(Normalize(0.0, 1.0), QUALITY_MAP), cax=bar,
                 label="radius ratio")
    fig.suptitle(f"pattern {label}: {_flips(run)}", fontsize=11)
    return fig


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(__file__).parent / "images")
    parser.add_argument("--force", action="store_true", help="replace existing pictures")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for label, pattern in PATTERNS.items():
        run = partition_cuboid(pattern, improve=True)
        name = f"cuboid-{pattern}.png"
        data = figure_bytes(picture(label, run), "png")
        write_bytes_atomic(args.out / name, data, overwrite=args.force)
        before, after = run.partition.tetrahedron_count, run.mesh.tetrahedron_count
        print(f"![pattern {label}](images/{name})  \n"
              f"Pattern {label}: {before} → {after} tetrahedra, {_flips(run)} "
              f"({len(data) // 1024} KB)")


if __name__ == "__main__":
    main()
