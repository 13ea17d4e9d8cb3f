"""Delaunay and constrained Delaunay triangulation: the Python batch builder and the
optional compiled insertion kernel beside it."""
