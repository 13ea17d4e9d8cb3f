"""Triangle meshes in the plane: snapshots, transients, the reference steps, validation,
measures, and the 2D algorithms (Delaunay, Lepp refinement, polygonal meshes).

Layer 3 of ``docs/design.md``: imports :mod:`geomexact.kernel` and :mod:`geomexact.trace`.
"""
