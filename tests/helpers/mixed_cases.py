"""Mixed meshes for the tests: random exact box grids of hexahedra, and random walks of
split_cell / merge_cells steps on them (each step recorded in one transient)."""

from __future__ import annotations

import random

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.conversion import box_grid_mesh
from geomexact.mesh3d.mixed.ops import merge_cells_in, split_cell_in
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import MixedTransient3


def random_box(rng: random.Random) -> Box:
    """A box with random exact corners (small denominators)."""
    low = [mpq(rng.randint(-9, 9), rng.randint(1, 4)) for _ in range(3)]
    high = [lo + mpq(rng.randint(1, 9), rng.randint(1, 4)) for lo in low]
    return Box(tuple(low), tuple(high))


def random_grid(rng: random.Random, largest: int = 3) -> tuple[Box, MixedMesh3]:
    box = random_box(rng)
    sizes = [rng.randint(1, largest) for _ in range(3)]
    return box, box_grid_mesh(box, *sizes)


def random_walk(t: MixedTransient3, rng: random.Random, steps: int) -> int:
    """Apply up to ``steps`` random splits and merges to ``t`` (a step whose precondition
    fails is skipped); the number applied."""
    applied = 0
    for _ in range(steps):
        cells = t.cell_list()
        if not cells:
            break
        cell = rng.choice(cells)
        try:
            if rng.random() < 0.6:
                split_cell_in(t, cell, rng.sample(cell.vertices, 3))
            else:
                face = rng.choice(cell.faces)
                merge_cells_in(t, face)
            applied += 1
        except PreconditionError:
            continue
    return applied
