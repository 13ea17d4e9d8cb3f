"""Mixed meshes made from other values and back: :func:`from_tetrahedral` (every
tetrahedron of a :class:`~geomexact.mesh3d.snapshot.Mesh3` a tetra cell, the same
digest), :func:`to_tetrahedral` (a mixed mesh cut into tetrahedra, no new vertex) and
:func:`box_grid_mesh` (a box cut into nx x ny x nz hexahedra, the octree's start)."""

from __future__ import annotations

from itertools import pairwise

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point3
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.mixed.cells import CellKind, standard_cell
from geomexact.mesh3d.mixed.snapshot import MixedMesh3
from geomexact.mesh3d.mixed.transient import mixed_mesh_from_cells
from geomexact.mesh3d.snapshot import Mesh3
from geomexact.mesh3d.transient import mesh3_from_positive_arrays

__all__ = ["box_grid_mesh", "from_tetrahedral", "to_tetrahedral"]


def from_tetrahedral(mesh: Mesh3) -> MixedMesh3:
    """The mixed mesh whose cells are the tetrahedra of ``mesh`` (same vertex ids and
    points); its digest is ``mesh.digest`` (a tetra cell hashes as in ``Mesh3``)."""
    cells = [standard_cell(CellKind.TETRA, tetrahedron) for tetrahedron in mesh.tetrahedra()]
    return mixed_mesh_from_cells(mesh.point_list(), cells)


def to_tetrahedral(mesh: MixedMesh3) -> Mesh3:
    """``mesh`` cut into tetrahedra on its own vertices: every face of four or more
    vertices fanned from its least vertex (so the two cells of a face cut it alike),
    every cell the cones from its least vertex over the triangles of its other faces
    (positive in a convex cell: a face's plane meets the cell only in the face).  A
    tetra cell stays itself, so a tetrahedral mesh comes back unchanged."""
    tetrahedra = []
    for cell in mesh.cell_list():
        apex = min(cell.vertices)
        for face in cell.faces:
            if apex in face:
                continue
            # a face is stored rotated to its least vertex: the fan's centre
            for b, c in pairwise(face[1:]):
                tetrahedra.append((face[0], c, b, apex))
    points = [mesh.point(vertex) for vertex in range(mesh.vertex_count)]
    return mesh3_from_positive_arrays(points, tetrahedra)


def box_grid_mesh(box: Box, nx: int, ny: int, nz: int) -> MixedMesh3:
    """``box`` cut into ``nx * ny * nz`` equal hexahedra.  Vertex (i, j, k) is the exact
    point ``low + extents * (i/nx, j/ny, k/nz)`` with id ``(i (ny + 1) + j)(nz + 1) + k``
    (the lexicographic order of the points, as the octree numbers its lattice); each
    hexahedron in VTK's order from its low corner, bottom (z low) counter-clockwise seen
    from above.  O(n) and no predicate: a grid's cells are valid by construction."""
    if min(nx, ny, nz) < 1:
        raise PreconditionError("box_grid_mesh", f"a grid needs 1 or more cells on each "
                                f"axis, not {(nx, ny, nz)}")
    (x0, y0, z0), (ex, ey, ez) = box.low, box.extents
    xs = [x0 + ex * mpq(i, nx) for i in range(nx + 1)]
    ys = [y0 + ey * mpq(j, ny) for j in range(ny + 1)]
    zs = [z0 + ez * mpq(k, nz) for k in range(nz + 1)]
    points = [point3(x, y, z) for x in xs for y in ys for z in zs]

    def vertex(i: int, j: int, k: int) -> int:
        return (i * (ny + 1) + j) * (nz + 1) + k

    cells = []
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                bottom = [vertex(i, j, k), vertex(i + 1, j, k), vertex(i + 1, j + 1, k),
                          vertex(i, j + 1, k)]
                top = [v + 1 for v in bottom]
                cells.append(standard_cell(CellKind.HEXAHEDRON, bottom + top))
    return mixed_mesh_from_cells(points, cells)
