"""The compiled cuboid kernel equals the reference: the same steps, the same tetrahedra
(hence digests) and the same census row, on a fixed random sample of patterns, every
single-bit pattern and the full pattern, for both shapes, both orders, both templates and
the improvement's options.  The exhaustive run over every pattern is ``slow``."""

from __future__ import annotations

import random

import pytest

from geomexact.mesh3d.cuboid import compiled
from geomexact.mesh3d.cuboid.boxes import Box, box_of_extents, unit_cube
from geomexact.mesh3d.cuboid.census import census_row, kinds_of_mask
from geomexact.mesh3d.cuboid.numbering import PATTERN_COUNT
from geomexact.mesh3d.cuboid.partition import partition_cuboid
from geomexact.mesh3d.cuboid.split_order import ORDERS
from geomexact.mesh3d.transient import mesh3_from_tetrahedra

needs_kernel = pytest.mark.skipif(not compiled.AVAILABLE, reason="the cuboid kernel is not built")
# built and not stale: tests/package/test_kernels_built.py covers this kernel too
SAMPLE = sorted(random.Random(2007).sample(range(1, PATTERN_COUNT), 24))
CI_PATTERNS = [0, *(1 << bit for bit in range(18)), PATTERN_COUNT - 1, *SAMPLE]
BOXES = [unit_cube(), box_of_extents(1, 2, 4)]


def assert_equal_runs(pattern: int, box: Box, order: str, template: int, improve: bool,
                      boundary: bool) -> None:
    options = {"order": order, "template": template, "improve": improve,
               "allow_boundary_flips": boundary}
    reference = partition_cuboid(pattern, box, **options)  # type: ignore[arg-type]
    fast = compiled.run_compiled(pattern, box, **options)  # type: ignore[arg-type]
    assert fast.steps == reference.trace.steps
    assert fast.tetrahedra == tuple(reference.mesh.tetrahedra())
    points = [reference.mesh.point(v) for v in range(reference.mesh.vertex_count)]
    assert mesh3_from_tetrahedra(points, fast.tetrahedra).digest == reference.mesh.digest
    assert fast.row == census_row(pattern, box, **options)  # type: ignore[arg-type]


@needs_kernel
@pytest.mark.parametrize("box", BOXES, ids=lambda b: b.describe())
@pytest.mark.parametrize("order", ORDERS)
@pytest.mark.parametrize("improve", [False, True])
def test_the_kernel_equals_the_reference(box: Box, order: str, improve: bool) -> None:
    for index, pattern in enumerate(CI_PATTERNS):
        template = index % 2
        assert_equal_runs(pattern, box, order, template, improve, boundary=False)


@needs_kernel
@pytest.mark.parametrize("box", BOXES, ids=lambda b: b.describe())
def test_the_kernel_equals_the_reference_with_boundary_flips(box: Box) -> None:
    for index, pattern in enumerate(SAMPLE[:12]):
        assert_equal_runs(pattern, box, ORDERS[index % 2], (index // 2) % 2, True, True)


@needs_kernel
def test_the_kernel_runs_any_rational_box_it_can_scale() -> None:
    box = Box(("-1/3", 2, "0.5"), (1, "17/7", 3))
    assert compiled.kernel_corners(box) is not None
    for pattern in SAMPLE[:8]:
        assert_equal_runs(pattern, box, "conforming", 1, True, False)


@needs_kernel
def test_a_box_beyond_the_kernel_is_refused_and_named() -> None:
    thin = box_of_extents(1, 1, 2**21)
    assert compiled.kernel_corners(thin) is None
    assert "2**20" in (compiled.unsupported(thin) or "") or "1048576" in (
        compiled.unsupported(thin) or "")
    with pytest.raises(ValueError, match="integer coordinates"):
        compiled.run_compiled(1, thin)


@needs_kernel
def test_rows_of_a_range_equal_the_rows_one_by_one() -> None:
    box = box_of_extents(1, 2, 4)
    values = compiled.compiled_rows(4090, 4110, box, order="index", improve=True)
    for offset, pattern in enumerate(range(4090, 4110)):
        row = compiled.row_of(values[12 * offset:12 * offset + 12], pattern, box.describe(),
                              "index", 0)
        assert row == compiled.run_compiled(pattern, box, order="index", improve=True).row


@needs_kernel
@pytest.mark.slow
@pytest.mark.parametrize("box", BOXES, ids=lambda b: b.describe())
@pytest.mark.parametrize("order", ORDERS)
def test_every_pattern_is_valid_with_the_exact_volume(box: Box, order: str) -> None:
    """All 262,143 patterns (and 0): valid (positive, closed on the box, exact volume)
    before and after the improvement, which leaves no transformable face failing."""
    values = compiled.compiled_rows(0, PATTERN_COUNT, box, order=order, improve=True)
    for pattern in range(PATTERN_COUNT):
        row = compiled.row_of(values[12 * pattern:12 * pattern + 12], pattern,
                              box.describe(), order, 0)
        assert row.valid and row.valid_improved, pattern
        assert row.failing_improved is not None
        assert not {"T23", "T32", "T44"} & set(kinds_of_mask(row.failing_improved)), pattern
    rng = random.Random(order)
    for pattern in rng.sample(range(PATTERN_COUNT), 200):  # and a wider equivalence sample
        assert_equal_runs(pattern, box, order, pattern % 2, True, False)
