"""Polygon meshes: the polygon-mesh value, Polylla, and convex decomposition."""
