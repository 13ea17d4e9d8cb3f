"""Tetrahedral meshes: the :class:`~geomexact.mesh3d.snapshot.Mesh3` snapshot and its
transient, the reference steps (``split_tetra``, Joe's flips) in ``ops``, ``validation``
and ``measures``; ``cuboid/`` partitions 1-irregular cuboids and runs their census.  The
octree mesher comes next (``docs/design.md``)."""
