"""Lepp refinement: :func:`~geomexact.mesh2d.refinement.api.refine` (the entry point), its
criteria and regions, the centroid rules, the driver and work queue, and the engines that
run it (:mod:`~geomexact.mesh2d.refinement.engines`)."""
