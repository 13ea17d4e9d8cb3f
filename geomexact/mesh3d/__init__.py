"""Tetrahedral meshes (planned): snapshots, split-tetra, Joe's flips, 1-irregular cuboids
and the octree mesher.  See ``docs/design.md`` for where each module goes."""
