"""Display measures of triangles, vectorised (NumPy, doubles): the smallest angle and the
area of each.  They are for pictures and the quality arrays of VTK and Gmsh files only;
exact questions (orientation, area, angles against a threshold) are answered by
``measures`` and the predicates.  The tetrahedral ones are in ``geomexact.mesh3d.quality``."""

from __future__ import annotations

import numpy as np

__all__ = ["areas", "min_angles"]


def min_angles(xy: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """The smallest angle of each triangle, in degrees (doubles, for colouring)."""
    if not len(triangles):
        return np.zeros(0)
    a, b, c = xy[triangles[:, 0]], xy[triangles[:, 1]], xy[triangles[:, 2]]

    def angle(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> np.ndarray:
        u, v = q - p, r - p
        cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        dot = u[:, 0] * v[:, 0] + u[:, 1] * v[:, 1]
        degrees: np.ndarray = np.degrees(np.arctan2(cross, dot))
        return degrees

    smallest: np.ndarray = np.minimum(np.minimum(angle(a, b, c), angle(b, c, a)),
                                      angle(c, a, b))
    return smallest


def areas(xy: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """The area of each triangle (doubles, for colouring)."""
    if not len(triangles):
        return np.zeros(0)
    a, b, c = xy[triangles[:, 0]], xy[triangles[:, 1]], xy[triangles[:, 2]]
    u, v = b - a, c - a
    result: np.ndarray = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / 2
    return result
