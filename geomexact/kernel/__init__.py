"""The exact kernel: rational numbers, points, adaptive predicates, digests.

Every module here is dimension-free or holds both dimensions apart; nothing here knows a
mesh.  The predicates: :mod:`predicates2d`, :mod:`predicates3d`, :mod:`comparisons`,
:mod:`angles`, returning the enums of :mod:`predicate_results`; every copy of their float
filters (numpy: :mod:`array_filters`; C: ``ckernel.h``, reached by the tests through
``cfilters``) takes its constants from :mod:`filter_bounds`.

Layer 1 of ``docs/design.md``: imports only :mod:`geomexact.errors`.
"""
