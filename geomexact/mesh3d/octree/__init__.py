"""The octree mixed-element mesher: a box domain covered by an octree of cuboids, refined
where asked, balanced so that every leaf is 1-irregular, and each leaf partitioned into
tetrahedra by its Steiner pattern so that the whole mesh conforms.  Each stage is a
swappable strategy (``stages``); :func:`~geomexact.mesh3d.octree.pipeline.generate` runs
them.  Specification: ``specs/octree.md``; guide: ``docs/octree.md``."""
