"""The machinery behind :func:`geomexact.refine.refine`: the refinement driver
(:mod:`~geomexact.refinement.driver`), its work queue (:mod:`~geomexact.refinement.queue`)
and the engines that run it (:mod:`~geomexact.refinement.transient_engine`, the reference;
:mod:`~geomexact.refinement.fast_engine`, the default).  Users call ``refine``."""
