"""Delaunay property of 2D meshes (exact).

An interior edge {u, v} with triangles (u, v, w) and (v, u, x) is *locally Delaunay* when x
is not strictly inside the circle through u, v, w.  A mesh is (constrained) Delaunay when
every unconstrained interior edge is locally Delaunay; constrained segments are exempt.
Cocircular quadrilaterals count as Delaunay.  See ``specs/delaunay.md``.
"""

from __future__ import annotations

from geomexact.mesh2d import Edge, Mesh2
from geomexact.predicates import CircleLocation, incircle


def non_delaunay_edges(mesh: Mesh2) -> list[Edge]:
    """Sorted (u, v), u < v, of the unconstrained interior edges that are not locally
    Delaunay.  O(n) exact incircle tests."""
    halfedges, vertices, segments = mesh.halfedges, mesh.vertices, mesh.segments
    found = []
    for key, w in halfedges.items():
        u, v = key
        if u > v or key in segments:
            continue
        x = halfedges.get((v, u))
        if x is None:
            continue
        location = incircle(vertices[u], vertices[v], vertices[w], vertices[x])
        if location == CircleLocation.INSIDE:
            found.append((u, v))
    return sorted(found)


def is_delaunay(mesh: Mesh2) -> bool:
    """True when every unconstrained interior edge is locally Delaunay (exact)."""
    return not non_delaunay_edges(mesh)
