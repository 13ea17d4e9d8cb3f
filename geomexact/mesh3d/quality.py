"""Display measures of tetrahedra, vectorised (numpy, doubles): dihedral angles and the
radius-edge ratio.  They are for reports and pictures only; exact questions (orientation,
volume, Delaunay) are answered by ``measures`` and ``validation``."""

from __future__ import annotations

from typing import Any

import attrs
import numpy as np

__all__ = ["QualitySummary", "dihedral_angles", "quality_summary", "radius_edge_ratios"]

_EDGES = ((0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2), (1, 2, 0, 3), (1, 3, 0, 2), (2, 3, 0, 1))
"""Each edge (i, j) of a tetrahedron with its two other vertices (k, l)."""


def _corners(points: Any, tetrahedra: Any) -> Any:
    return np.asarray(points, dtype=np.float64)[np.asarray(tetrahedra, dtype=np.int64)]


def dihedral_angles(points: Any, tetrahedra: Any) -> Any:
    """The six dihedral angles (degrees) of each tetrahedron (T x 6), from float
    coordinates ``points`` (V x 3)."""
    p = _corners(points, tetrahedra)
    angles = []
    for i, j, k, m in _EDGES:
        edge = p[:, j] - p[:, i]
        first = np.cross(edge, p[:, k] - p[:, i])
        second = np.cross(edge, p[:, m] - p[:, i])
        cosine = np.einsum("ij,ij->i", first, second) / (
            np.linalg.norm(first, axis=1) * np.linalg.norm(second, axis=1))
        angles.append(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))))
    return np.stack(angles, axis=1)


def radius_edge_ratios(points: Any, tetrahedra: Any) -> Any:
    """Circumradius / shortest edge of each tetrahedron (sqrt(6)/4 ~ 0.612 for the
    regular one)."""
    p = _corners(points, tetrahedra)
    b, c, d = (p[:, n] - p[:, 0] for n in (1, 2, 3))
    numerator = (np.einsum("ij,ij->i", b, b)[:, None] * np.cross(c, d)
                 + np.einsum("ij,ij->i", c, c)[:, None] * np.cross(d, b)
                 + np.einsum("ij,ij->i", d, d)[:, None] * np.cross(b, c))
    denominator = 2.0 * np.einsum("ij,ij->i", b, np.cross(c, d))
    radius = np.linalg.norm(numerator, axis=1) / np.abs(denominator)
    lengths = [np.linalg.norm(p[:, j] - p[:, i], axis=1) for i, j, _, _ in _EDGES]
    return radius / np.min(np.stack(lengths, axis=1), axis=1)


@attrs.frozen(slots=True)
class QualitySummary:
    """Extremes over a mesh (degrees; ratios): None for an empty mesh."""

    min_dihedral: float | None
    max_dihedral: float | None
    max_radius_edge: float | None


def quality_summary(points: Any, tetrahedra: Any) -> QualitySummary:
    """The smallest and largest dihedral angle and the largest radius-edge ratio."""
    if len(tetrahedra) == 0:
        return QualitySummary(None, None, None)
    angles = dihedral_angles(points, tetrahedra)
    ratios = radius_edge_ratios(points, tetrahedra)
    return QualitySummary(float(angles.min()), float(angles.max()), float(ratios.max()))
