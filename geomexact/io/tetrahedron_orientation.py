"""The orientation rule of the tetrahedral readers (TetGen, meshio), the 3D form of the 2D
readers' rule (:func:`geomexact.io.registry.orient_triangles`): tetrahedra all positive
(exact ``orient3d``, ``specs/predicates.md``) are kept, all negative are reversed with a
note, a file mixing them is refused naming one of each, a flat one is refused naming it.
Spec: ``specs/formats/tetgen.md`` (step 4 of Reading) and ``specs/formats/meshio.md``."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from geomexact.errors import FormatError
from geomexact.kernel.array_filters import orient3d_signs, point_doubles3
from geomexact.kernel.points import Point3
from geomexact.kernel.predicates3d import orient3d

__all__ = ["flat_problem", "mixed_problem", "negative_note", "orient_tetrahedra"]


def negative_note(count: int) -> str:
    """The note of a reader that reversed every one of ``count`` negative tetrahedra."""
    if count == 1:
        return "the only tetrahedron was negatively oriented; reversed it"
    return f"all {count} tetrahedra were negatively oriented; reversed them"


def flat_problem(tetrahedron: str) -> str:
    """The problem of a flat tetrahedron, described as ``tetrahedron``."""
    return f"{tetrahedron} is flat (zero volume): its corners are coplanar"


def mixed_problem(negative: str, positive: str) -> str:
    """The problem of a file of both orientations, ``negative`` and ``positive`` describing
    one tetrahedron of each."""
    return (f"tetrahedra have mixed orientations: {negative} is negatively oriented but "
            f"{positive} is positive (orient3d, specs/predicates.md)")


def orient_tetrahedra(
    path: str,
    points: Sequence[Point3],
    tetrahedra: Any,
    describe: Callable[[int], str],
    notes: list[str],
) -> Any:
    """The (T x 4) ``tetrahedra`` (indices into ``points``, in range, corners distinct) all
    made positive, by the rule of this module; FormatError on ``path`` (no line) naming
    the first flat tetrahedron, or the first negative and the first positive one, by
    ``describe(index)``.  The float filter decides most signs, exact ``orient3d`` the
    rest."""
    rows = np.asarray(tetrahedra, dtype=np.int64).reshape(-1, 4)
    signs = orient3d_signs(*point_doubles3(points), *rows.T)
    for index in np.flatnonzero(signs == 0).tolist():
        a, b, c, d = rows[index].tolist()
        signs[index] = int(orient3d(points[a], points[b], points[c], points[d]))
    flat = np.flatnonzero(signs == 0)
    if len(flat):
        raise FormatError(path, None, flat_problem(describe(int(flat[0]))))
    negative = np.flatnonzero(signs < 0)
    if not len(negative):
        return rows
    positive = np.flatnonzero(signs > 0)
    if len(positive):
        raise FormatError(path, None, mixed_problem(describe(int(negative[0])),
                                                    describe(int(positive[0]))))
    notes.append(negative_note(len(rows)))
    return rows[:, [1, 0, 2, 3]]
