"""The compiled cuboid kernel: glue between the reference
(:func:`~geomexact.mesh3d.cuboid.partition.partition_cuboid`,
:func:`~geomexact.mesh3d.cuboid.census.census_row`) and the typed kernel
:mod:`geomexact.mesh3d.cuboid.cuboid_kernel` (a Cython extension, optional).

The kernel works on small integers: the box translated to the origin and scaled by the
positive factor that makes its corners even integers (twice the extents over their common
denominator, divided by their gcd), so every Steiner point is an integer point.  Both
orient3d and insphere keep their signs under a translation and a positive uniform scaling
(not under a per-axis one: a 1x2x4 box is computed with its own coordinates).  A box whose
scaled corners exceed ``MAX_COORDINATE`` (2**20) is outside the kernel: :func:`kernel_corners`
returns None and the callers use the reference.  ``tests/mesh3d/test_cuboid_kernel.py``
proves the kernel equal to the reference (same steps, tetrahedra, digests and rows).
"""

from __future__ import annotations

import importlib
import math
import threading
from collections.abc import Sequence
from functools import lru_cache
from typing import Any, Final

import attrs
import gmpy2

from geomexact.errors import PreconditionError
from geomexact.kernel import digest as _digest
from geomexact.kernel.points import Point3
from geomexact.mesh3d.cuboid.boxes import Box
from geomexact.mesh3d.cuboid.census import CensusRow
from geomexact.mesh3d.cuboid.numbering import CORNER_POSITIONS, check_pattern
from geomexact.mesh3d.cuboid.split_order import check_order, split_ranks
from geomexact.mesh3d.cuboid.templates import TEMPLATE_TETRAHEDRA, check_template, segment_of
from geomexact.mesh3d.snapshot import Tetrahedron, canonical_tetrahedron
from geomexact.trace.step import Step

__all__ = ["AVAILABLE", "MAX_COORDINATE", "CompiledRun", "bulk_digest", "compiled_rows",
           "kernel_corners", "row_of", "run_compiled", "unsupported"]


def _load() -> Any:
    try:
        return importlib.import_module("geomexact.mesh3d.cuboid.cuboid_kernel")
    except ImportError:
        return None


_cuboid_kernel: Any = _load()

AVAILABLE: bool = _cuboid_kernel is not None
"""True when the extension is built and importable."""
MAX_COORDINATE: Final = 1 << 20
MAX_BINARY_BYTES: Final = 40
"""The longest ``gmpy2.to_binary`` of a coordinate the kernel's vertex hash takes (the id
and three of them fit BLAKE2b's one 128-byte block)."""
_MPQ: Final = type(gmpy2.mpq())
ROW_WIDTH: Final = 12
_OPS: Final = ("split_tetra", "flip23", "flip32", "flip22", "flip44")


def bulk_digest(points: Sequence[Point3], rows: Any) -> int | None:
    """The digest of the mesh of ``points`` (by id) and the canonical tetrahedra ``rows``
    (an integer array): the sum mod 2**128 of ``digest.vertex_hash`` over the vertices and
    ``digest.cell_hash`` over the tetrahedra, in the kernel (each distinct coordinate's
    ``gmpy2.to_binary`` made once); None when the kernel is not built, a coordinate is
    not an ``mpq`` or its binary is longer than the kernel's 40 bytes (the acceleration
    of ``Mesh3``'s bulk digest, bound by ``geomexact.mesh3d``)."""
    if _cuboid_kernel is None:
        return None
    import numpy as np

    coordinates = [c for point in points for c in point[:3]]
    # every one an mpq: equal values of other types (an mpz 1, mpq 1) hash alike but
    # encode differently, and the table keeps one encoding a value
    if set(map(type, coordinates)) - {_MPQ}:
        return None
    numbers: dict[Any, int] = {}
    number = numbers.setdefault
    codes = [number(c, len(numbers)) for c in coordinates]
    binaries = [gmpy2.to_binary(value) for value in numbers]
    if any(len(binary) > MAX_BINARY_BYTES for binary in binaries):
        return None
    starts = np.cumsum([0, *map(len, binaries)], dtype=np.int64)
    total = _cuboid_kernel.vertex_hash_sum(
        np.frombuffer(b"".join(binaries) or b"\0", dtype=np.uint8), starts,
        np.array(codes, dtype=np.int64).reshape(-1, 3))
    if len(rows):
        total += _cuboid_kernel.tetrahedra_hash_sum(
            np.ascontiguousarray(rows, dtype=np.int64), _digest._POSITION_MULTIPLIERS,
            _digest.FINAL_MULTIPLIER)
    return int(total) & (_digest.MODULUS - 1)


def lattice_faces(points: Any, tetrahedra: Any, base: Any) -> tuple[Any, Any] | None:
    """The octree conformity check's pass over ``tetrahedra`` (T x 4 int64 ids, each in
    0 .. V - 1) of the lattice ``points`` (V x 3 int64) in the kernel: (six times each
    tetrahedron's signed volume, the 4T face keys over ``base``), the integers of
    ``geomexact.mesh3d.octree.conformity``'s numpy ``_det6`` and ``_face_keys`` (tested
    equal); None when the kernel is not built."""
    if _cuboid_kernel is None:
        return None
    import numpy as np

    det = np.empty(len(tetrahedra), dtype=np.int64)
    keys = np.empty(4 * len(tetrahedra), dtype=np.uint64)
    _cuboid_kernel.lattice_faces(np.ascontiguousarray(points), np.ascontiguousarray(tetrahedra),
                                 base, det, keys)
    return det, keys


def kernel_corners(box: Box) -> tuple[tuple[int, int, int], ...] | None:
    """The eight corners of ``box`` as the kernel's integers (the low corner at the origin,
    every coordinate even), or None when they exceed ``MAX_COORDINATE``."""
    extents = box.extents
    scale = math.lcm(*(int(e.denominator) for e in extents))
    integers = [int(e.numerator) * (scale // int(e.denominator)) for e in extents]
    common = math.gcd(*integers)
    doubled = [2 * value // common for value in integers]
    if max(doubled) > MAX_COORDINATE:
        return None
    return tuple(
        (doubled[0] * x, doubled[1] * y, doubled[2] * z) for x, y, z in CORNER_POSITIONS
    )


def unsupported(box: Box) -> str | None:
    """Why the kernel cannot run on ``box``, or None when it can."""
    if not AVAILABLE:
        return "the compiled cuboid kernel is not built (no C compiler at install)"
    if kernel_corners(box) is None:
        return (f"the box {box.describe()} needs integer coordinates above "
                f"{MAX_COORDINATE} (its extents' ratios are too large)")
    return None


def _setup(box: Box, order: str, template: int, improve: bool,
           allow_boundary_flips: bool) -> Any:
    # a Setup owns the scratch mesh the kernel fills without the GIL: threads sharing one
    # (a Dask worker's threads) would overwrite each other's partitions, so one per thread
    return _thread_setup(box, order, template, improve, allow_boundary_flips,
                         threading.get_ident())


@lru_cache(maxsize=32)
def _thread_setup(box: Box, order: str, template: int, improve: bool,
                  allow_boundary_flips: bool, thread: int) -> Any:
    reason = unsupported(box)
    if reason is not None:
        raise PreconditionError("cuboid", reason)
    segments = [segment_of(bit, template) for bit in range(18)]
    return _cuboid_kernel.Setup(kernel_corners(box), split_ranks(box, order), segments,
                                TEMPLATE_TETRAHEDRA[template], improve, allow_boundary_flips)


def row_of(values: Sequence[int], pattern: int, shape: str, order: str,
           template: int) -> CensusRow:
    """The :class:`CensusRow` of the kernel's 12 row ints."""
    (tetrahedra, valid, kinds, failing, f23, f32, f22, f44, rounds, after, valid_after,
     failing_after) = values
    if rounds < 0:
        return CensusRow(pattern, shape, order, template, tetrahedra, valid == 1, kinds,
                         failing)
    return CensusRow(pattern, shape, order, template, tetrahedra, valid == 1, kinds, failing,
                     (f23, f32, f22, f44), rounds, after, valid_after == 1, failing_after)


@attrs.frozen(slots=True)
class CompiledRun:
    """The kernel's run of one pattern: its census row, its steps (splits, then flips) and
    the final tetrahedra (canonical, sorted)."""

    row: CensusRow
    steps: tuple[Step, ...]
    tetrahedra: tuple[Tetrahedron, ...]


def run_compiled(pattern: int, box: Box, *, order: str = "conforming", template: int = 0,
                 improve: bool = False, allow_boundary_flips: bool = False) -> CompiledRun:
    """What ``partition_cuboid`` and ``census_row`` compute, by the kernel;
    :class:`PreconditionError` when it cannot run (:func:`unsupported`)."""
    check_pattern(pattern)
    order = check_order(order)
    check_template(template)
    setup = _setup(box, order, template, improve, allow_boundary_flips)
    values, raw_steps, raw_tetrahedra = setup.run_pattern(pattern)
    steps = tuple(
        Step(_OPS[op], (a, b) if op == 0 else tuple(sorted((a, b, c))))
        for op, a, b, c in raw_steps
    )
    tetrahedra = tuple(sorted(canonical_tetrahedron(*t) for t in raw_tetrahedra))
    return CompiledRun(row_of(values, pattern, box.describe(), order, template), steps,
                       tetrahedra)


def compiled_rows(start: int, stop: int, box: Box, *, order: str = "conforming",
                  template: int = 0, improve: bool = False,
                  allow_boundary_flips: bool = False) -> list[int]:
    """The kernel's row ints of patterns start .. stop - 1, flat (12 per pattern)."""
    order = check_order(order)
    check_template(template)
    setup = _setup(box, order, template, improve, allow_boundary_flips)
    values: list[int] = setup.census_rows(start, stop)
    return values
