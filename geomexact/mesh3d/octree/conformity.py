"""The exact conformity check of an octree's tetrahedral mesh, on its integer lattice.

On the lattice every coordinate is an integer, so orientations, volumes and areas are
exact int64 / Python-int arithmetic (no float, no tolerance).  Checked, for every
generated mesh: every tetrahedron is positive; each face is used by one tetrahedron
(boundary) or by two with opposite orientations (interior), never more; every boundary
face lies on the box surface, and those on each of the six box faces add up to exactly
its area; the boundary is closed (each directed boundary edge is met once each way);
the volumes add up to exactly the box's; every vertex is used.
"""

from __future__ import annotations

from typing import Any

import attrs
import numpy as np

from geomexact.errors import PreconditionError
from geomexact.kernel.numbers import Rational, mpq
from geomexact.mesh3d.cuboid import compiled

__all__ = ["ConformityReport", "lattice_conformity"]


@attrs.frozen(slots=True, kw_only=True)
class FaceConformity:
    """An exact conformity check of a cell mesh: the faces two cells share
    (``interior_faces``) and those on one cell (``boundary_faces``); ``conforming`` when
    ``problems`` is empty."""

    interior_faces: int
    boundary_faces: int
    problems: tuple[str, ...]

    @property
    def conforming(self) -> bool:
        return not self.problems


@attrs.frozen(slots=True, kw_only=True)
class ConformityReport(FaceConformity):
    """The result of :func:`lattice_conformity` (:class:`FaceConformity`) for its
    ``tetrahedra``; ``volume6``, six times their lattice volume."""

    tetrahedra: int
    volume6: int

    def volume(self, unit_volume: Rational) -> Rational:
        """The exact volume, given the exact volume of one lattice cell."""
        return mpq(self.volume6, 6) * unit_volume  # type: ignore[no-any-return]


def _det6(points: Any, tetrahedra: Any) -> Any:
    x, y, z = (np.ascontiguousarray(points[:, axis]) for axis in range(3))
    # each corner's coordinates gathered by column (T each): the same int64 arithmetic
    corners = [[coordinate[tetrahedra[:, n]] for coordinate in (x, y, z)] for n in range(4)]
    b, c, d = ([p - q for p, q in zip(corners[n], corners[0], strict=True)]
               for n in (1, 2, 3))
    return (b[0] * (c[1] * d[2] - c[2] * d[1])
            - b[1] * (c[0] * d[2] - c[2] * d[0])
            + b[2] * (c[0] * d[1] - c[1] * d[0]))


_FACES = ((0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 3, 2))
"""A positive tetrahedron's faces, each oriented as it has it."""


def _face_keys(tetrahedra: Any, base: Any) -> Any:
    """One uint64 per face of every tetrahedron (4T, face by face): its ids sorted, as
    ``(low * base + middle) * base + high``, then the parity of the sorting permutation
    (an odd number of inversions among the three) as the lowest bit.  Each id below
    2**21, so the key is below 2**64."""
    columns = [np.ascontiguousarray(tetrahedra[:, n]) for n in range(4)]
    keys = np.empty(4 * len(tetrahedra), dtype=np.uint64)
    for n, (i, j, k) in enumerate(_FACES):
        x, y, z = columns[i], columns[j], columns[k]
        low = np.minimum(np.minimum(x, y), z)
        high = np.maximum(np.maximum(x, y), z)
        middle = x + y + z - low - high
        odd = (x > y) ^ (x > z) ^ (y > z)
        keys[n * len(x):(n + 1) * len(x)] = (
            (low.astype(np.uint64) * base + middle.astype(np.uint64)) * base
            + high.astype(np.uint64)) * np.uint64(2) + odd
    return keys


def _faces_and_volumes(points: Any, tetrahedra: Any, base: Any) -> tuple[Any, Any]:
    """(:func:`_det6`, :func:`_face_keys`): in one pass of the compiled cuboid kernel
    (``lattice_faces``: the same integers, tested equal) when it is built and every id
    is a vertex's, else by numpy (which also says how an id out of range fails)."""
    if (len(tetrahedra) and int(tetrahedra.min()) >= 0
            and int(tetrahedra.max()) < len(points)):
        found = compiled.lattice_faces(points, tetrahedra, base)
        if found is not None:
            return found
    return _det6(points, tetrahedra), _face_keys(tetrahedra, base)


def lattice_conformity(points: Any, tetrahedra: Any, size: tuple[int, int, int],
                       limit: int = 10) -> ConformityReport:
    """Check the mesh of lattice ``points`` (V x 3 ints, fewer than 2**21) and
    ``tetrahedra`` (T x 4 ids) against the box [0, size]; at most ``limit`` examples of
    each problem are named."""
    points = np.asarray(points, dtype=np.int64).reshape(-1, 3)
    tetrahedra = np.asarray(tetrahedra, dtype=np.int64).reshape(-1, 4)
    problems: list[str] = []
    if len(points) >= 1 << 21:
        raise PreconditionError("octree", f"{len(points)} vertices: the conformity check "
                                "takes fewer than 2**21")
    base = np.uint64(max(len(points), 1))
    det, face_keys = _faces_and_volumes(points, tetrahedra, base)
    bad = np.flatnonzero(det <= 0)
    if bad.size:
        problems.append(f"{bad.size} tetrahedra are not positive, e.g. "
                        f"{tetrahedra[bad[:limit]].tolist()}")
    # |det| < 2**63 / T: the int64 sum is exact (else Python ints)
    exact = not len(det) or int(np.abs(det).max()) < (1 << 62) // len(det)
    volume6 = int(det.sum()) if exact else int(det.astype(object).sum())
    nx, ny, nz = size
    if volume6 != 6 * nx * ny * nz:
        problems.append(f"the volumes add up to {mpq(volume6, 6)} lattice cells, not "
                        f"{nx * ny * nz}")
    # one sort of the keys (the sorted face, then the parity): runs of one face give its
    # counts; a face of two tetrahedra has them on opposite sides when their parities
    # differ, i.e. when its two keys do
    sorted_keys = np.sort(face_keys)
    face_keys = sorted_keys >> np.uint64(1)
    starts = (np.flatnonzero(np.concatenate(([True], face_keys[1:] != face_keys[:-1])))
              if len(face_keys) else np.zeros(0, dtype=np.int64))
    counts = np.diff(np.append(starts, len(face_keys)))
    first_keys = sorted_keys[starts]
    if (counts > 2).any():
        over = _face_ids(first_keys[counts > 2] >> np.uint64(1), base)
        problems.append(f"{len(over)} faces have more than two tetrahedra, e.g. "
                        f"{over[:limit].tolist()}")
    pairs = counts == 2
    same_side = np.zeros(len(starts), dtype=bool)
    same_side[pairs] = first_keys[pairs] == sorted_keys[starts[pairs] + 1]
    if same_side.any():
        one_side = _face_ids(first_keys[same_side] >> np.uint64(1), base)
        problems.append(f"{len(one_side)} faces have both tetrahedra on one side, "
                        f"e.g. {one_side[:limit].tolist()}")
    boundary = counts == 1
    # a boundary face as its tetrahedron has it, up to a rotation: its sorted ids, two of
    # them swapped when the permutation was odd
    outer = _face_ids(first_keys[boundary] >> np.uint64(1), base)
    swapped = (first_keys[boundary] & np.uint64(1)).astype(bool)
    outer[swapped] = outer[swapped][:, [0, 2, 1]]
    problems.extend(_boundary_problems(points, outer, size, limit))
    used = np.zeros(len(points), dtype=bool)
    used[tetrahedra.ravel()] = True
    if not used.all():
        problems.append(f"{int((~used).sum())} vertices are in no tetrahedron, e.g. "
                        f"{np.flatnonzero(~used)[:limit].tolist()}")
    return ConformityReport(tetrahedra=len(tetrahedra), interior_faces=int(pairs.sum()),
                            boundary_faces=int(boundary.sum()), volume6=volume6,
                            problems=tuple(problems))


def _face_ids(keys: Any, base: Any) -> Any:
    """The (F x 3) int64 ids of the face keys ``(a * base + b) * base + c``."""
    high, c = np.divmod(keys, base)
    a, b = np.divmod(high, base)
    return np.stack((a, b, c), axis=1).astype(np.int64)


def _boundary_problems(points: Any, outer: Any, size: tuple[int, int, int],
                       limit: int) -> list[str]:
    """The problems of the boundary faces ``outer`` (F x 3 ids, oriented inward, as their
    positive tetrahedron has them, up to a rotation)."""
    problems = []
    corners = points[outer]  # F x 3 x 3
    on_plane = np.zeros(len(outer), dtype=bool)
    for axis in range(3):
        other = [n for n in range(3) if n != axis]
        for side, value in ((0, 0), (1, size[axis])):
            mask = (corners[:, :, axis] == value).all(axis=1)
            on_plane |= mask
            u = corners[mask][:, :, other[0]]
            v = corners[mask][:, :, other[1]]
            area2 = np.abs((u[:, 1] - u[:, 0]) * (v[:, 2] - v[:, 0])
                           - (u[:, 2] - u[:, 0]) * (v[:, 1] - v[:, 0]))
            wanted = 2 * size[other[0]] * size[other[1]]
            total = int(area2.astype(object).sum())
            if total != wanted:
                problems.append(f"the boundary triangles on box face {'xyz'[axis]}="
                                f"{'low' if side == 0 else 'high'} cover {mpq(total, 2)} "
                                f"lattice units, not {wanted // 2}")
    if not on_plane.all():
        inside = outer[~on_plane]
        problems.append(f"{len(inside)} boundary triangles are inside the box (a face not "
                        f"matched: a hanging vertex), e.g. {inside[:limit].tolist()}")
    # closed: each directed edge of the (inward) boundary once, and its reverse once
    edges = np.concatenate([outer[:, [0, 1]], outer[:, [1, 2]], outer[:, [2, 0]]])
    forward = np.unique(edges, axis=0, return_counts=True)
    reverse = np.unique(edges[:, ::-1], axis=0)
    if (forward[1] > 1).any() or len(forward[0]) != len(reverse) or not np.array_equal(
            forward[0], reverse):
        problems.append("the boundary is not a closed surface (a boundary edge is not met "
                        "exactly once in each direction)")
    return problems
