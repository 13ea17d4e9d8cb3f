"""The 1-irregular cuboid: its numbering, the two 5-tetrahedron templates, the partition
by bisection in a conforming or the source's split order, Joe's improvement and the census
of all 2**18 patterns.  Specification: ``specs/cuboid.md``; results: ``docs/cuboid.md``."""
