"""Mixed-cell meshes: tetrahedra, pyramids, wedges, hexahedra (VTK's orderings) and
convex polyhedra in one exact value, :class:`MixedMesh3`; its transient, its steps
(``ops``: add_vertex, add_cell, remove_cell, merge_cells, split_cell), the exact checker
(``validation``) and the converters (``conversion``: from a tetrahedral mesh, a box grid
of hexahedra) and :class:`MixedMeshData` (a mesh with integer cell arrays, for the
writers).  Specification: ``specs/mixed.md``."""

from geomexact.mesh3d.mixed.cell_data import MixedMeshData
from geomexact.mesh3d.mixed.cells import (
    Cell,
    CellKind,
    cell_of_faces,
    standard_cell,
)
from geomexact.mesh3d.mixed.conversion import box_grid_mesh, from_tetrahedral
from geomexact.mesh3d.mixed.ops import OPERATIONS as _OPERATIONS
from geomexact.mesh3d.mixed.snapshot import MixedMesh3, empty_mixed_mesh, mixed_volume
from geomexact.mesh3d.mixed.transient import MixedTransient3, mixed_mesh_from_cells
from geomexact.mesh3d.mixed.validation import check_mixed, validate_mixed
from geomexact.trace.protocols import MeshKind as _MeshKind
from geomexact.trace.protocols import bind_kind as _bind_kind

# The mixed-cell mesh kind, bound here, above the modules it joins (the snapshot reaches
# its transient and the step table through it: no import circle, tests/architecture).
_bind_kind(MixedMesh3, _MeshKind(MixedTransient3, _OPERATIONS))

__all__ = [
    "Cell",
    "CellKind",
    "MixedMesh3",
    "MixedMeshData",
    "MixedTransient3",
    "box_grid_mesh",
    "cell_of_faces",
    "check_mixed",
    "empty_mixed_mesh",
    "from_tetrahedral",
    "mixed_mesh_from_cells",
    "mixed_volume",
    "standard_cell",
    "validate_mixed",
]
