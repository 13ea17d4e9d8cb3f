"""A mixed mesh with named integer arrays over its cells (:class:`MixedMeshData`): what a
mesher hands to a writer to label each cell (the octree's leaf ``level``).  The arrays
follow ``mesh.cell_list()`` order, the order in which the writers write the cells.
Specification: ``specs/formats/meshio.md`` ("Cell data")."""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from types import MappingProxyType

import attrs

from geomexact.errors import PreconditionError
from geomexact.mesh3d.mixed.snapshot import MixedMesh3

__all__ = ["RESERVED_CELL_DATA", "MixedMeshData"]

RESERVED_CELL_DATA = ("kind",)
"""Names a caller cannot give: the writers write ``kind`` (each cell's VTK type) always."""

_FORBIDDEN_CHARACTERS = frozenset('"<>&\'')


def _arrays(value: Mapping[str, Iterable[int]]) -> Mapping[str, tuple[int, ...]]:
    """The arrays as tuples of ints, sorted by name (read-only)."""
    converted: dict[str, tuple[int, ...]] = {}
    for name in sorted(value):
        values = tuple(value[name])
        if not all((isinstance(v, int) and not isinstance(v, bool)) or _is_integer_scalar(v)
                   for v in values):
            raise PreconditionError("cell data", f"array {name!r} holds values that are not "
                                    "integers")
        converted[name] = tuple(int(v) for v in values)
    return MappingProxyType(converted)


def _is_integer_scalar(value: object) -> bool:
    """True for a numpy integer scalar (``numpy.int32(3)``), without importing numpy."""
    kind = getattr(getattr(value, "dtype", None), "kind", None)
    return kind in ("i", "u") and not hasattr(value, "__len__")


@attrs.frozen(slots=True, eq=False)
class MixedMeshData:
    """``mesh`` with integer ``cell_data``: name -> one int per cell, in
    ``mesh.cell_list()`` order (sorted canonical cells).  Names are non-empty, printable,
    without spaces, quotes, ``<``, ``>`` or ``&`` (they go into XML attributes and Gmsh
    strings) and not ``kind``; :class:`PreconditionError` otherwise, or for an array of
    the wrong length."""

    mesh: MixedMesh3
    cell_data: Mapping[str, tuple[int, ...]] = attrs.field(converter=_arrays,
                                                          factory=dict)

    def __attrs_post_init__(self) -> None:
        count = self.mesh.cell_count
        for name, values in self.cell_data.items():
            if (not name or not name.isprintable() or any(c.isspace() for c in name)
                    or _FORBIDDEN_CHARACTERS.intersection(name)):
                raise PreconditionError("cell data", f"{name!r} is not a usable array name "
                                        "(printable, no spaces, quotes, <, > or &)")
            if name in RESERVED_CELL_DATA:
                raise PreconditionError("cell data", f"{name!r} is written by the writers "
                                        "themselves; give the array another name")
            if len(values) != count:
                raise PreconditionError("cell data", f"array {name!r} has {len(values)} "
                                        f"values for {count} cells")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MixedMeshData):
            return NotImplemented
        return self.mesh == other.mesh and dict(self.cell_data) == dict(other.cell_data)

    def __hash__(self) -> int:
        return hash((self.mesh, tuple(self.cell_data.items())))
