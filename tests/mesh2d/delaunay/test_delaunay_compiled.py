"""The compiled Delaunay kernel (``geomexact.mesh2d.delaunay.delaunay_kernel`` through
``geomexact.mesh2d.delaunay.compiled``): what only the kernel has — its grid states and its
hashes.  Its equality with the reference engine ``ReferenceDelaunay`` (same steps, same digest
after every step, same mesh with ``outgoing`` hints) on random, lattice, collinear,
duplicated, huge, tiny, beyond-double, non-dyadic and real point sets and PSLGs, and the
replay of every trace through the reference ops, are in
``tests/engines/test_engine_equivalence.py``.  Skipped when the extension is not built."""

from __future__ import annotations

import pytest

from geomexact.kernel.numbers import mpq
from geomexact.kernel.points import point2
from geomexact.mesh2d.delaunay.compiled import AVAILABLE

pytestmark = pytest.mark.skipif(not AVAILABLE, reason="the compiled Delaunay kernel is not built")


def test_grid_states() -> None:
    """Doubles in [0, 1) at or above 2**-8 are on the grid, exact non-doubles are not."""
    from geomexact.mesh2d.delaunay import delaunay_kernel  # type: ignore[attr-defined]

    points = [point2(mpq(1, 2), mpq(3, 4)), point2(mpq(2) ** -8, mpq(0)),
              point2(mpq(2) ** -60, mpq(1, 2)), point2(mpq(1, 3), mpq(1, 2)),
              point2(mpq(2) ** -61, mpq(1, 2))]
    builder = delaunay_kernel.Builder(points)
    assert builder.grid == (60, 3)
    assert builder.vertex_state(0) == (True, 2**59, 3 * 2**58)
    assert builder.vertex_state(1) == (True, 2**52, 0)
    assert builder.vertex_state(2)[0]
    assert not builder.vertex_state(3)[0] and not builder.vertex_state(4)[0]


def test_hashes_match_digest() -> None:
    from geomexact.kernel import digest
    from geomexact.mesh2d.delaunay import delaunay_kernel  # type: ignore[attr-defined]

    for cell in [(0, 1, 2), (5, 3, 9), (70000, 2, 123456)]:
        assert delaunay_kernel.cell_hash(*cell) == digest.cell_hash(cell)




@pytest.mark.parametrize("scale", [1, 2**-3, 2**-10, 2**70, 3])
def test_vertex_hashes_match_the_digest(scale: int) -> None:
    """The builder's sum of vertex hashes (C for grid vertices with 0 <= F <= 62, Python for
    the others) is digest.vertex_hash's, whatever the grid (tiny and huge coordinates
    give F > 62 and F < 0) and with off-grid vertices among them."""
    import random

    from geomexact.kernel import digest
    from geomexact.mesh2d.delaunay import delaunay_kernel  # type: ignore[attr-defined]

    rng = random.Random(scale)
    points = [point2(mpq(rng.random()) * scale, mpq(rng.random()) * scale)
              for _ in range(50)]
    points += [point2(mpq(1, 3) * scale, mpq(-2, 7)), point2(mpq(0), mpq(-1, 2) * scale)]
    expected = sum(digest.vertex_hash(i, (p.x, p.y)) for i, p in enumerate(points))
    builder = delaunay_kernel.Builder(points)
    assert builder.vertex_hashes == expected % digest.MODULUS


@pytest.mark.parametrize("seed", [0, 1, -5, 2**70, 12345])
def test_shuffled_ids_are_random_shuffle(seed: int) -> None:
    """The kernel's shuffle of the insertion order is ``random.Random(seed).shuffle``'s,
    element for element, across the Mersenne Twister's regenerations (624 words)."""
    import random

    from geomexact.mesh2d.delaunay import delaunay_kernel  # type: ignore[attr-defined]

    for count in (0, 1, 2, 3, 100, 700, 5000):
        expected = list(range(count))
        random.Random(seed).shuffle(expected)
        assert delaunay_kernel.shuffled_ids(count, seed).tolist() == expected
