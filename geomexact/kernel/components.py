"""Connected components of a graph given as two arrays of edge ends, on numpy arrays: the
one routine both dimensions' validation uses to count pieces of a mesh (edge-connected
triangles, face-connected tetrahedra around a vertex or an edge)."""

from __future__ import annotations

from typing import Any

import numpy as np


def component_labels(size: int, first: Any, second: Any) -> Any:
    """The smallest node of each node's connected component, in the graph of ``size``
    nodes with the edges ``first[k]``-``second[k]`` (hooking roots by their minimum, then
    path doubling, until no edge joins two labels): an int array of ``size`` labels."""
    parent = np.arange(size)
    while True:
        a, b = parent[first], parent[second]
        differ = a != b
        if not differ.any():
            return parent
        np.minimum.at(parent, np.maximum(a, b)[differ], np.minimum(a, b)[differ])
        while True:
            grand = parent[parent]
            if np.array_equal(grand, parent):
                break
            parent = grand
