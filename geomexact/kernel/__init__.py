"""The exact kernel: rational numbers, points, adaptive predicates, digests.

Every module here is dimension-free or holds both dimensions apart; nothing here knows a
mesh.  Layer 1 of ``docs/design.md``: imports only :mod:`geomexact.errors`.
"""
