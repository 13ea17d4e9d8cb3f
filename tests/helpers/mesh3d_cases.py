"""Tetrahedral meshes for the tests and benchmarks: a box of unit cubes, each cut into the
six tetrahedra around its main diagonal (Kuhn's subdivision: conforming across cubes)."""

from __future__ import annotations

from itertools import permutations

from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_tetrahedra


def cube_grid(nx: int, ny: int, nz: int) -> Mesh3:
    """[0, nx] × [0, ny] × [0, nz] in 6 nx ny nz tetrahedra ((nx+1)(ny+1)(nz+1) integer
    vertices).  About 15 s for 200,000 tetrahedra."""
    points = [(i, j, k) for i in range(nx + 1) for j in range(ny + 1) for k in range(nz + 1)]
    return mesh3_from_tetrahedra(points, kuhn_tetrahedra(nx, ny, nz), orient=True)


def kuhn_tetrahedra(nx: int, ny: int, nz: int) -> list[tuple[int, int, int, int]]:
    """The six tetrahedra of each unit cube of the grid (the paths from its low corner to
    its high one), vertex (i, j, k) numbered (i (ny + 1) + j)(nz + 1) + k."""

    def vertex(i: int, j: int, k: int) -> int:
        return (i * (ny + 1) + j) * (nz + 1) + k

    tetrahedra = []
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                for axes in permutations(range(3)):
                    corner = [i, j, k]
                    path = [vertex(*corner)]
                    for axis in axes:
                        corner[axis] += 1
                        path.append(vertex(*corner))
                    tetrahedra.append((path[0], path[1], path[2], path[3]))
    return tetrahedra
