"""Tetrahedral meshes: the :class:`~geomexact.mesh3d.snapshot.Mesh3` snapshot and its
transient, the reference steps (``split_tetra``, Joe's flips, ``insert_cuboid``) in
``ops``, ``validation``, ``measures`` and ``quality``; ``cuboid/`` partitions 1-irregular
cuboids and runs their census; ``octree/`` is the octree mesher built on them
(``docs/design.md``); ``mixed/`` holds meshes of mixed cells (hexahedra, wedges, pyramids,
tetrahedra, convex polyhedra: ``specs/mixed.md``)."""
